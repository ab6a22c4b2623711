#include "inertial/formats/user_region.hpp"

#include <stdexcept>

#include "inertial/formats/number_parsing.hpp"
#include "inertial/model/number_text.hpp"
#include "inertial/model/rotation_from_rpy.hpp"

namespace inertial {
namespace {

std::string CountError(const std::string& what, std::size_t expected, std::size_t given, const std::string& text) {
  return what + ": " + std::to_string(given) + " numbers given, " + std::to_string(expected) + " expected ('" + text +
         "')";
}

// The links a region can name: those that start a moving body, for the error of an unknown one.
std::string MovingLinks(const RobotModel& robot) {
  std::string links;
  for (const std::string& link : robot.body_links) links += (links.empty() ? "" : ", ") + link;
  return links;
}

}  // namespace

UserRegion ParseUserRegion(const std::string& text, const std::string& option) {
  UserRegion r;
  r.text = text;
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos) throw std::invalid_argument("expected LINK=cx,cy,cz,a,b,c[:rpy=r,p,y]");
  r.target = text.substr(0, eq);
  if (r.target.empty()) throw std::invalid_argument("no link before '='");
  std::vector<std::string> parts;
  std::string rest = text.substr(eq + 1);
  for (std::size_t at; (at = rest.find(':')) != std::string::npos; rest = rest.substr(at + 1)) parts.push_back(rest.substr(0, at));
  parts.push_back(rest);
  const std::string what = option + " " + r.target;
  const std::vector<double> v = ParseNumberList(parts[0], what);
  if (v.size() != 6) throw std::invalid_argument(CountError("centre and semi-axes", 6, v.size(), parts[0]));
  r.center = Vector3(v[0], v[1], v[2]);
  r.semi_axes = Vector3(v[3], v[4], v[5]);
  bool rpy_given = false;
  for (std::size_t k = 1; k < parts.size(); ++k) {
    const std::size_t at = parts[k].find('=');
    const std::string key = parts[k].substr(0, at);
    if (at == std::string::npos || key != "rpy") {
      throw std::invalid_argument("unknown part '" + parts[k] + "' (the only key is rpy=r,p,y)");
    }
    if (rpy_given) throw std::invalid_argument("rpy is given twice");
    rpy_given = true;
    const std::string value = parts[k].substr(at + 1);
    const std::vector<double> a = ParseNumberList(value, what + " rpy");
    if (a.size() != 3) throw std::invalid_argument(CountError("rpy", 3, a.size(), value));
    r.rpy = Vector3(a[0], a[1], a[2]);
  }
  for (int i = 0; i < 3; ++i) {
    if (!(r.semi_axes[i] > 0.0)) {
      throw std::invalid_argument("semi-axis " + std::to_string(i + 1) + " is " + FormatNumber(r.semi_axes[i], 6) +
                                  "; every semi-axis must be positive [m]");
    }
  }
  // A length beyond any robot (urdf_model.hpp's kMaxUrdfLength) is most likely a region in
  // millimetres: refused as a URDF's length would be.
  if (r.semi_axes.maxCoeff() > kMaxUrdfLength || r.center.cwiseAbs().maxCoeff() > kMaxUrdfLength) {
    throw std::invalid_argument("a length beyond " + FormatNumber(kMaxUrdfLength, 6) +
                                " m (the centre and semi-axes are in metres)");
  }
  return r;
}

PlacedUserRegion PlaceUserRegion(const RobotModel& robot, const RobotDynamics& model, const UserRegion& region,
                                 bool require_body) {
  PlacedUserRegion placed;
  SpatialTransform link_in_body;  // the link's frame (the region's) posed in the tree body's frame
  const std::vector<EstimatedBody>& bodies = model.bodies();
  if (region.target.rfind("payload@", 0) == 0) {
    for (int e = 0; e < static_cast<int>(bodies.size()); ++e) {
      if (bodies[static_cast<size_t>(e)].name == region.target && placed.body < 0) placed.body = e;  // the model's own (run payloads come after it)
    }
    if (placed.body < 0) {
      if (!require_body) return placed;
      throw std::invalid_argument("the model has no " + region.target + " (add it with --effects " + region.target + ")");
    }
    link_in_body = bodies[static_cast<size_t>(placed.body)].report_frame;
  } else {
    if (region.target.rfind("rotor@", 0) == 0) {
      throw std::invalid_argument("a rotor has no region (it turns about its own axis; body_region.hpp)");
    }
    const auto it = robot.placements.find(region.target);
    if (it == robot.placements.end()) {
      throw std::invalid_argument("there is no link '" + region.target + "' in the robot; the links that move: " +
                                  MovingLinks(robot));
    }
    if (it->second.body < 0) {
      throw std::invalid_argument("'" + region.target + "' is fixed to the base: no inertia of it is estimated");
    }
    placed.body = it->second.body;  // tree bodies come first among the estimated bodies, in order
    link_in_body = it->second.X_body_link;
  }
  const Matrix3 axes = link_in_body.R_AB * RotationFromRpy(region.rpy);
  const Vector3 center = link_in_body.R_AB * region.center + link_in_body.p_AB;
  placed.region.ellipsoid = BoundingEllipsoid::FromAxes(center, axes, region.semi_axes);
  placed.region.max_mass = kMaxRegionDensity * placed.region.ellipsoid.Volume();
  placed.region.source = RegionSource::kUser;
  const EstimatedBody& body = bodies[static_cast<size_t>(placed.body)];
  const double slack = placed.region.ellipsoid.Slack(body.prior);
  if (!(slack > 0.0)) {
    throw std::invalid_argument("the region does not hold " + body.name + "'s prior (the URDF's inertia: its slack in " +
                                "the region is " + FormatNumber(slack, 3) + ", 0 on the region's edge, 1 all at its " +
                                "centre); the fit starts at the prior, so the region must hold it");
  }
  if (!(body.prior.mass() < placed.region.max_mass)) {
    throw std::invalid_argument("the region is too small for " + body.name + "'s prior mass of " +
                                FormatNumber(body.prior.mass(), 4) + " kg (at most " +
                                FormatNumber(placed.region.max_mass, 4) + " kg: solid steel throughout it)");
  }
  return placed;
}

void ApplyUserRegions(const RobotModel& robot, const std::vector<UserRegion>& regions, RobotDynamics* model,
                      bool require_body) {
  std::vector<PlacedUserRegion> placed;
  for (const UserRegion& r : regions) {
    try {
      placed.push_back(PlaceUserRegion(robot, *model, r, require_body));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(r.text + ": " + e.what());
    }
    for (std::size_t k = 0; k + 1 < placed.size(); ++k) {
      if (placed.back().body >= 0 && placed[k].body == placed.back().body) {
        throw std::invalid_argument(r.text + ": " + model->bodies()[static_cast<size_t>(placed.back().body)].name +
                                    " already has a region (" + regions[k].text + ")");
      }
    }
  }
  for (const PlacedUserRegion& p : placed) {
    if (p.body >= 0) model->SetBodyRegion(p.body, p.region);
  }
}

}  // namespace inertial
