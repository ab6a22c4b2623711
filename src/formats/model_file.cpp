#include "inertial/formats/model_file.hpp"

#include <cmath>
#include <stdexcept>

#include "inertial/inertia/consistency.hpp"
#include "inertial/formats/urdf_writer.hpp"

namespace inertial {
namespace {

// "rotor@hip" -> "hip".
std::string TargetOf(const std::string& body_name) { return body_name.substr(body_name.find('@') + 1); }

bool IsLinkBody(const RobotModel& robot, const EstimatedBody& body) {
  return body.tree_body < static_cast<int>(robot.body_links.size()) && body.name == robot.body_links[body.tree_body];
}

}  // namespace

ModelSnapshot SnapshotAt(const RobotDynamics& model, const Eigen::VectorXd& x) {
  if (x.size() != model.num_parameters()) {
    throw std::invalid_argument("model snapshot: " + std::to_string(x.size()) + " parameters, the model has " +
                                std::to_string(model.num_parameters()));
  }
  ModelSnapshot s;
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) s.bodies.emplace_back(model.BodyInertia(e, x));
  for (int k = 0; k < static_cast<int>(model.effects().size()); ++k) s.effect_values.push_back(model.EffectValues(k, x));
  return s;
}

ModelSnapshot SnapshotOf(const OnlineJointEstimator& estimator) {
  const RobotDynamics& model = estimator.model();
  if (estimator.kind() != EstimatorKind::kLinearRls) return SnapshotAt(model, estimator.estimator().parameters());
  // Linear RLS: w itself. Payloads are inside their links' pi.
  ModelSnapshot s;
  Eigen::VectorXd w(model.num_features());
  estimator.estimator().Coefficients(w);  // from the estimator's state (also right after a Restore)
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    const EstimatedBody& body = model.bodies()[e];
    if (body.name.rfind("payload@", 0) == 0) {
      s.bodies.emplace_back(std::nullopt);
      continue;
    }
    const InertialParams pi = InertialParams::FromVector(w.segment<10>(10 * body.tree_body));
    const ConsistencyReport report = CheckConsistency(pi);
    if (!report.fully_consistent()) {
      throw std::invalid_argument("the linear RLS estimate of '" + body.name + "' is not physically consistent (" +
                                  report.reason + "); use the gauss_newton or gradient estimator for a model file");
    }
    s.bodies.emplace_back(pi);
  }
  for (const EffectTerm& t : model.effects()) {
    const double c = w[t.first_feature];
    if (t.kind != EffectKind::kOffset && c < 0) {
      throw std::invalid_argument("the linear RLS estimate of " + std::string(ToString(t.kind)) + "@" + t.joint +
                                  " is negative (" + std::to_string(c) + "): not a physical coefficient");
    }
    if (t.kind == EffectKind::kAsymmetric && w[t.first_feature + 1] < 0) {
      throw std::invalid_argument("the linear RLS estimate of asymmetric@" + t.joint +
                                  " (negative direction) is negative (" + std::to_string(w[t.first_feature + 1]) +
                                  "): not a physical coefficient");
    }
    if (t.kind == EffectKind::kAsymmetric) {
      s.effect_values.push_back({c, w[t.first_feature + 1]});
    } else if (t.kind == EffectKind::kSpring) {
      s.effect_values.push_back({c, c > 0 ? w[t.first_feature + 1] / c : 0.0});
    } else {
      s.effect_values.push_back({c});
    }
  }
  return s;
}

std::vector<ModelEffect> EffectsOf(const RobotDynamics& model, const ModelSnapshot& snapshot) {
  if (snapshot.bodies.size() != model.bodies().size() || snapshot.effect_values.size() != model.effects().size()) {
    throw std::invalid_argument("model snapshot: sizes do not match the model");
  }
  std::vector<ModelEffect> effects;
  for (int k = 0; k < static_cast<int>(model.effects().size()); ++k) {
    const EffectTerm& t = model.effects()[k];
    ModelEffect m;
    m.spec.kind = t.kind;
    m.spec.target = t.joint;
    m.spec.velocity_scale = t.velocity_scale;
    m.spec.steepness = t.steepness;
    m.spec.shift = t.shift;
    m.values = snapshot.effect_values[k];
    effects.push_back(m);
  }
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    const EstimatedBody& body = model.bodies()[e];
    const bool rotor = model.tree().is_rotor(body.tree_body) && body.name.rfind("rotor@", 0) == 0;
    const bool payload = body.name.rfind("payload@", 0) == 0;
    if ((!rotor && !payload) || !snapshot.bodies[e]) continue;
    ModelEffect m;
    m.spec.kind = rotor ? EffectKind::kRotor : EffectKind::kPayload;
    m.spec.target = TargetOf(body.name);
    if (rotor) m.spec.gear_ratio = model.tree().gear_ratio(body.tree_body);
    m.spec.inertia = *snapshot.bodies[e];
    effects.push_back(m);
  }
  return effects;
}

void WriteModelUrdf(const std::string& urdf_path, const std::string& out_path, const RobotModel& robot,
                    const RobotDynamics& model, const ModelSnapshot& snapshot, const std::string& origin) {
  UrdfModelChanges changes;
  changes.origin = origin;
  changes.effects = EffectsOf(model, snapshot);
  changes.effects->insert(changes.effects->end(), snapshot.measurement.begin(), snapshot.measurement.end());
  // Each link's prior recorded (urdf_model.hpp): the drawing the values are judged against. A model
  // read from a model file keeps the priors that file recorded, so the drawing survives refits.
  changes.priors.emplace();
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    const EstimatedBody& body = model.bodies()[e];
    if (!IsLinkBody(robot, body)) continue;
    if (snapshot.bodies[e]) changes.inertias[body.name] = *snapshot.bodies[e];
    const auto recorded = robot.recorded_priors.find(body.name);
    (*changes.priors)[body.name] = recorded != robot.recorded_priors.end() ? recorded->second : body.prior;
  }
  for (const UrdfLinkInertial& link : robot.links) {
    const int b = robot.BodyIndex(link.link);
    if (link.present && b >= 0 && robot.body_links[b] != link.link) changes.removed_inertials.insert(link.link);
  }
  changes.notes = snapshot.notes;
  WriteUrdfModel(urdf_path, out_path, changes);
}

Eigen::VectorXd StatedLogGains(const RobotModel& robot, const std::vector<ModelEffect>& effects) {
  Eigen::VectorXd g = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(robot.dof_names.size()));
  bool any = false;
  for (const ModelEffect& m : effects) {
    if (m.spec.kind != EffectKind::kGain || m.values.size() != 1) continue;
    const int d = robot.DofIndex(m.spec.target);
    if (d >= 0) g[d] = m.values[0];
    any = any || d >= 0;
  }
  return any ? g : Eigen::VectorXd();
}

std::vector<ModelEffect> MeasurementEffects(const std::vector<ModelEffect>& effects) {
  std::vector<ModelEffect> out;
  for (const ModelEffect& m : effects) {
    if (IsMeasurementEffect(m.spec.kind)) out.push_back(m);
  }
  return out;
}

std::vector<EffectSpec> MergeEffects(const std::vector<EffectSpec>& from_file, const std::vector<EffectSpec>& extra) {
  std::vector<EffectSpec> merged;
  for (const EffectSpec& f : from_file) {
    bool replaced = false;
    for (const EffectSpec& e : extra) {
      if (e.kind == f.kind && (e.target == f.target || (e.target.empty() && IsJointEffect(e.kind)))) replaced = true;
    }
    if (!replaced) merged.push_back(f);
  }
  merged.insert(merged.end(), extra.begin(), extra.end());
  return merged;
}

RobotDynamics MakeRobotDynamics(const RobotModel& robot, const std::vector<EffectSpec>& effects, const Vector3& gravity) {
  const LinkResolver resolve = [&robot](const std::string& link, LinkLocation* location) {
    const auto it = robot.placements.find(link);
    if (it == robot.placements.end()) return false;
    location->body = it->second.body;
    location->link_in_body = it->second.X_body_link;
    return true;
  };
  RobotDynamics model(robot.tree, robot.dof_names, effects, resolve, gravity);
  // A link's own collision shapes bound it better than its segment (body_region.hpp, source 1);
  // without them its segment reaches the frames fixed to it too (a flange, tool0), which the tree
  // alone does not know.
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    const EstimatedBody& body = model.bodies()[e];
    const int b = body.tree_body;
    if (!body.region || body.region->source != RegionSource::kSegment || b >= static_cast<int>(robot.body_links.size())) {
      continue;
    }
    try {
      if (b < static_cast<int>(robot.body_shape_points.size()) && robot.body_shape_points[b].size() >= 4) {
        model.SetBodyRegion(e, RegionAround(robot.body_shape_points[b], body.prior, kShapeRegionMargin, RegionSource::kShape));
        continue;
      }
      std::vector<Vector3> fixed_frames;
      for (const auto& [link, placement] : robot.placements) {
        if (placement.body == b && link != robot.body_links[b]) fixed_frames.push_back(placement.X_body_link.p_AB);
      }
      if (!fixed_frames.empty()) model.SetBodyRegion(e, SegmentRegion(model.tree(), b, body.prior, fixed_frames));
    } catch (const std::invalid_argument&) {
      // Shapes that determine no ellipsoid (all in a plane): the segment's region stays.
    }
  }
  return model;
}

}  // namespace inertial
