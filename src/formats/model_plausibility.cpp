#include "inertial/formats/model_plausibility.hpp"

#include <optional>
#include <stdexcept>

#include "inertial/formats/model_file.hpp"
#include "inertial/model/number_text.hpp"

namespace inertial {
namespace {

// The robot with each recorded prior in place of its link's inertia (the tree rebuilt: its
// inertias cannot change after AddBody), so that MakeRobotDynamics builds each link's region from
// its prior exactly as the fit that wrote the file did.
RobotModel WithRecordedPriors(const RobotModel& robot) {
  RobotModel out = robot;
  KinematicTree tree;
  for (int b = 0; b < robot.tree.num_bodies(); ++b) {
    const auto recorded = robot.recorded_priors.find(robot.body_links[static_cast<size_t>(b)]);
    tree.AddBody(robot.tree.body_name(b), robot.tree.parent(b), robot.tree.joint(b),
                 recorded != robot.recorded_priors.end() ? recorded->second : robot.tree.inertia(b));
  }
  out.tree = tree;
  return out;
}

bool IsUrdfLink(const RobotModel& robot, const EstimatedBody& body) {
  return body.tree_body >= 0 && body.tree_body < static_cast<int>(robot.body_links.size()) &&
         body.name == robot.body_links[static_cast<size_t>(body.tree_body)];
}

}  // namespace

std::vector<JudgedBody> JudgeModelBodies(const RobotModel& robot, const RobotDynamics& model, const Eigen::VectorXd& x) {
  if (x.size() != model.num_parameters()) throw std::invalid_argument("plausibility: x does not fit the model");
  std::optional<RobotDynamics> drawn;  // the links at their recorded priors
  if (!robot.recorded_priors.empty()) drawn.emplace(MakeRobotDynamics(WithRecordedPriors(robot), {}, model.gravity()));
  std::vector<JudgedBody> out;
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    const EstimatedBody& own = model.bodies()[static_cast<size_t>(e)];
    if (!own.region) continue;  // a rotor
    const InertialParams in_tree = model.BodyInertia(e, x).Transformed(own.report_frame.R_AB, own.report_frame.p_AB);
    JudgedBody j;
    j.body = e;
    j.name = own.name;
    const bool link = IsUrdfLink(robot, own);
    if (link && drawn && robot.recorded_priors.count(own.name) != 0 && drawn->bodies()[static_cast<size_t>(e)].region) {
      j.reference = drawn->bodies()[static_cast<size_t>(e)];
      j.against_recorded_prior = true;
      j.plausibility = JudgeAgainstRegion(in_tree, j.reference.prior, *j.reference.region, HasDrawnPrior(j.reference));
    } else {
      j.reference = own;
      j.reference.prior = in_tree;  // its own reference
      const int b = own.tree_body;
      if (link && b < static_cast<int>(robot.body_shape_points.size()) &&
          robot.body_shape_points[static_cast<size_t>(b)].size() >= 4) {
        try {
          j.reference.region = RegionOfPoints(robot.body_shape_points[static_cast<size_t>(b)], kShapeRegionMargin,
                                              RegionSource::kShape);
        } catch (const std::invalid_argument&) {
          // Shapes in a plane determine no ellipsoid: the model's own region stays.
        }
      }
      j.plausibility = JudgeAgainstRegion(in_tree, in_tree, *j.reference.region, false);
    }
    out.push_back(j);
  }
  return out;
}

const char* ReferenceName(const JudgedBody& judged) {
  return judged.against_recorded_prior ? "recorded prior" : "itself";
}

double MassFixedToBase(const RobotModel& robot) {
  double mass = 0.0;
  for (const UrdfLinkInertial& link : robot.links) {
    const auto placement = robot.placements.find(link.link);
    if (link.present && placement != robot.placements.end() && placement->second.body < 0) mass += link.pi.mass();
  }
  return mass;
}

std::string LinksFixedToBase(const RobotModel& robot) {
  std::string out;
  for (const UrdfLinkInertial& link : robot.links) {
    const auto placement = robot.placements.find(link.link);
    if (!link.present || link.pi.mass() == 0.0 || placement == robot.placements.end() || placement->second.body >= 0) {
      continue;
    }
    out += (out.empty() ? "" : ", ") + link.link + " (" + FormatNumber(link.pi.mass(), 4) + " kg)";
  }
  return out.empty() ? "none" : out;
}

}  // namespace inertial
