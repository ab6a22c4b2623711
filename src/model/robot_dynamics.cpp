#include "inertial/model/robot_dynamics.hpp"

#include "inertial/inertia/consistency.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <stdexcept>

#include "inertial/inertia/assert.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"

namespace inertial {
namespace {

constexpr const char* kPiNames[10] = {"m", "hx", "hy", "hz", "Ixx", "Iyy", "Izz", "Ixy", "Iyz", "Ixz"};
constexpr const char* kThetaNames[10] = {"alpha", "d1", "d2", "d3", "s12", "s23", "s13", "t1", "t2", "t3"};

// A rotation taking the z axis to `axis` (unit).
Matrix3 RotationZTo(const Vector3& axis) {
  return Eigen::Quaterniond::FromTwoVectors(Vector3::UnitZ(), axis).toRotationMatrix();
}

// Every coefficient of these kinds is e^s (a spring's first only).
bool NonNegative(EffectKind kind) {
  return kind == EffectKind::kViscous || kind == EffectKind::kCoulomb || kind == EffectKind::kArmature ||
         kind == EffectKind::kAsymmetric || kind == EffectKind::kSigmoid;
}

// The regressor entries of effect term t on its joint (t.size() of them): A(t.dof, t.first_feature + k).
std::array<double, 2> EffectFeatures(const EffectTerm& t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                     const Eigen::VectorXd& qdd) {
  const int j = t.dof;
  switch (t.kind) {
    case EffectKind::kViscous: return {qd[j], 0.0};
    case EffectKind::kCoulomb: return {std::tanh(qd[j] / t.velocity_scale), 0.0};
    case EffectKind::kOffset: return {1.0, 0.0};
    case EffectKind::kArmature: return {qdd[j], 0.0};
    case EffectKind::kSpring: return {q[j], -1.0};
    case EffectKind::kAsymmetric: {
      const double s = std::tanh(qd[j] / t.velocity_scale);
      return {std::max(s, 0.0), std::min(s, 0.0)};
    }
    case EffectKind::kSigmoid: return {SigmoidFriction(qd[j], t.steepness, t.shift), 0.0};
    default: return {0.0, 0.0};
  }
}

// The index of the joint an effect names; throws, listing the joints, if there is none of that name.
int DofOf(const std::vector<std::string>& dof_names, const EffectSpec& e) {
  const auto it = std::find(dof_names.begin(), dof_names.end(), e.target);
  if (it == dof_names.end()) {
    std::string known;
    for (const std::string& n : dof_names) known += (known.empty() ? "" : ", ") + n;
    throw std::invalid_argument("effect '" + e.text + "': unknown joint '" + e.target + "' (joints: " + known + ")");
  }
  return static_cast<int>(it - dof_names.begin());
}

// Rotors become tree bodies on the joint's parent body, coaxial with the joint.
void AddRotors(const KinematicTree& links, const std::vector<std::string>& dof_names,
               const std::vector<EffectSpec>& effects, KinematicTree* tree) {
  std::set<int> rotor_dofs;
  for (const EffectSpec& e : effects) {
    if (e.kind != EffectKind::kRotor) continue;
    const int dof = DofOf(dof_names, e);
    if (!rotor_dofs.insert(dof).second) throw std::invalid_argument("effect '" + e.text + "': a second rotor on joint '" + e.target + "'");
    int child = -1;
    for (int b = 0; b < links.num_bodies(); ++b) {
      if (links.dof_index(b) == dof) child = b;
    }
    JointModel joint = links.joint(child);
    joint.name = "rotor@" + e.target;
    if (joint.type != JointType::kRevolute) {
      throw std::invalid_argument("effect '" + e.text + "': joint '" + e.target + "' is not revolute");
    }
    const double m = e.mass > 0 ? e.mass : 0.3, r = e.radius > 0 ? e.radius : 0.04, l = e.length > 0 ? e.length : 0.03;
    const InertialParams prior =
        e.inertia ? *e.inertia : SolidCylinder(m, r, l, Pose{RotationZTo(joint.axis), Vector3::Zero()});
    tree->AddRotor(joint.name, links.parent(child), joint, prior, dof, e.gear_ratio);
  }
}

// Payloads become estimated bodies on the tree body their link is fixed to.
void AddPayloads(const std::vector<EffectSpec>& effects, const LinkResolver& resolve_link,
                 std::vector<EstimatedBody>* bodies) {
  std::set<std::string> payload_links;
  for (const EffectSpec& e : effects) {
    if (e.kind != EffectKind::kPayload) continue;
    LinkLocation where;
    if (!resolve_link || !resolve_link(e.target, &where)) {
      throw std::invalid_argument("effect '" + e.text + "': unknown link '" + e.target + "'");
    }
    if (where.body < 0) {
      throw std::invalid_argument("effect '" + e.text + "': link '" + e.target +
                                  "' is fixed to the base, so a payload on it never affects the joint torques");
    }
    // a payload of its own block belongs to one run (run_local_bodies.hpp): several may share a link
    if (!e.own_features && !payload_links.insert(e.target).second) throw std::invalid_argument("effect '" + e.text + "': a second payload on '" + e.target + "'");
    const double m = e.mass > 0 ? e.mass : 0.5, r = e.radius > 0 ? e.radius : 0.05;
    const InertialParams prior =
        (e.inertia ? *e.inertia : SolidSphere(m, r)).Transformed(where.link_in_body.R_AB, where.link_in_body.p_AB);
    bodies->push_back(EstimatedBody{"payload@" + e.target, where.body, e.own_features ? -2 : where.body, prior,
                                    LogCholeskyParameterization(prior), where.link_in_body});
  }
}

// Joint effects: one term per (kind, joint), in the order given, their parameters and features
// numbered on from *num_parameters and *num_features.
void AddJointEffects(const std::vector<EffectSpec>& effects, const std::vector<std::string>& dof_names, int num_dofs,
                     int* num_parameters, int* num_features, std::vector<EffectTerm>* terms) {
  std::set<std::pair<int, int>> seen;
  for (const EffectSpec& e : effects) {
    if (!IsJointEffect(e.kind)) continue;
    if (IsMeasurementEffect(e.kind)) {  // of the log, not of the dynamics: no term (its joint checked)
      if (!e.target.empty()) DofOf(dof_names, e);
      continue;
    }
    std::vector<int> dofs;
    if (e.target.empty()) {
      for (int j = 0; j < num_dofs; ++j) dofs.push_back(j);
    } else {
      dofs.push_back(DofOf(dof_names, e));
    }
    for (int j : dofs) {
      if (!seen.insert({static_cast<int>(e.kind), j}).second) {
        throw std::invalid_argument("effect '" + e.text + "': " + std::string(ToString(e.kind)) + " on joint '" +
                                    dof_names[j] + "' is already in the list");
      }
      EffectTerm t;
      t.kind = e.kind;
      t.dof = j;
      t.joint = dof_names[j];
      t.velocity_scale = e.velocity_scale;
      t.steepness = e.steepness;
      t.shift = e.shift;
      t.first_parameter = *num_parameters;
      t.first_feature = *num_features;
      *num_parameters += t.size();
      *num_features += t.size();
      terms->push_back(t);
    }
  }
}

}  // namespace

RobotDynamics::RobotDynamics(const KinematicTree& links, std::vector<std::string> dof_names,
                             const std::vector<EffectSpec>& effects, const LinkResolver& resolve_link,
                             const Vector3& gravity)
    : tree_(links), dof_names_(std::move(dof_names)), gravity_(gravity) {
  if (static_cast<int>(dof_names_.size()) != links.num_dofs()) {
    throw std::invalid_argument("robot dynamics: " + std::to_string(dof_names_.size()) + " joint names for " +
                                std::to_string(links.num_dofs()) + " DOFs");
  }
  if (!gravity.allFinite()) throw std::invalid_argument("robot dynamics: gravity is not finite");
  AddRotors(links, dof_names_, effects, &tree_);
  for (int b = 0; b < tree_.num_bodies(); ++b) {
    bodies_.push_back(EstimatedBody{tree_.body_name(b), b, b, tree_.inertia(b),
                                    LogCholeskyParameterization(tree_.inertia(b)), SpatialTransform()});
  }
  AddPayloads(effects, resolve_link, &bodies_);
  AssignDefaultRegions();
  num_blocks_ = tree_.num_bodies();
  for (EstimatedBody& b : bodies_) {
    if (b.block == -2) b.block = num_blocks_++;  // a payload's own block, after the tree bodies'
  }
  num_parameters_ = 10 * static_cast<int>(bodies_.size());
  num_features_ = num_inertia_features();
  AddJointEffects(effects, dof_names_, num_dofs(), &num_parameters_, &num_features_, &effects_);
}

void RobotDynamics::AssignDefaultRegions() {
  const double reach = LongestSegment(tree_);
  for (EstimatedBody& b : bodies_) {
    if (!CheckConsistency(b.prior).fully_consistent()) continue;  // nothing to start a region from
    if (b.name.rfind("payload@", 0) == 0) {
      if (reach > 0.0) {
        b.region = RegionAround(ShapePointsOfSphere(b.report_frame.p_AB, reach), b.prior, 0.0, RegionSource::kPayloadReach);
      }
    } else if (!tree_.is_rotor(b.tree_body)) {
      b.region = SegmentRegion(tree_, b.tree_body, b.prior);
    }
  }
}

void RobotDynamics::SetBodyRegion(int e, std::optional<BodyRegion> region) {
  if (e < 0 || e >= static_cast<int>(bodies_.size())) {
    throw std::invalid_argument("robot dynamics: no estimated body " + std::to_string(e));
  }
  if (region && !(region->ellipsoid.Slack(bodies_[e].prior) > 0.0 && bodies_[e].prior.mass() < region->max_mass)) {
    throw std::invalid_argument("robot dynamics: the region given to '" + bodies_[e].name + "' does not hold its prior");
  }
  bodies_[e].region = std::move(region);
}

std::vector<std::string> RobotDynamics::ParameterNames() const {
  std::vector<std::string> names;
  for (const EstimatedBody& b : bodies_) {
    for (const char* n : kThetaNames) names.push_back(b.name + "." + n);
  }
  for (const EffectTerm& t : effects_) {
    const std::string prefix = std::string(ToString(t.kind)) + "@" + t.joint + ".";
    switch (t.kind) {
      case EffectKind::kViscous: names.push_back(prefix + "log_b"); break;
      case EffectKind::kCoulomb: names.push_back(prefix + "log_bc"); break;
      case EffectKind::kOffset: names.push_back(prefix + "c"); break;
      case EffectKind::kArmature: names.push_back(prefix + "log_Ia"); break;
      case EffectKind::kSpring: names.push_back(prefix + "log_k"); names.push_back(prefix + "q0"); break;
      case EffectKind::kAsymmetric: names.push_back(prefix + "log_bp"); names.push_back(prefix + "log_bn"); break;
      case EffectKind::kSigmoid: names.push_back(prefix + "log_p1"); break;
      default: break;
    }
  }
  return names;
}

std::vector<std::string> RobotDynamics::FeatureNames() const {
  std::vector<std::string> names;
  for (int b = 0; b < tree_.num_bodies(); ++b) {
    for (const char* n : kPiNames) names.push_back(tree_.body_name(b) + "." + n);
  }
  for (const EstimatedBody& b : bodies_) {
    if (b.block == b.tree_body) continue;
    for (const char* n : kPiNames) names.push_back(b.name + "." + n);
  }
  for (const EffectTerm& t : effects_) {
    const std::string prefix = std::string(ToString(t.kind)) + "@" + t.joint + ".";
    switch (t.kind) {
      case EffectKind::kViscous: names.push_back(prefix + "b"); break;
      case EffectKind::kCoulomb: names.push_back(prefix + "bc"); break;
      case EffectKind::kOffset: names.push_back(prefix + "c"); break;
      case EffectKind::kArmature: names.push_back(prefix + "Ia"); break;
      case EffectKind::kSpring: names.push_back(prefix + "k"); names.push_back(prefix + "k_q0"); break;
      case EffectKind::kAsymmetric: names.push_back(prefix + "bp"); names.push_back(prefix + "bn"); break;
      case EffectKind::kSigmoid: names.push_back(prefix + "p1"); break;
      default: break;
    }
  }
  return names;
}

void RobotDynamics::Features(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                             Eigen::Ref<Eigen::MatrixXd> A) const {
  if (A.rows() != num_dofs() || A.cols() != num_features_) {
    throw std::invalid_argument("robot dynamics: feature block must be " + std::to_string(num_dofs()) + " x " +
                                std::to_string(num_features_));
  }
  if (q.size() != num_dofs() || qd.size() != num_dofs() || qdd.size() != num_dofs()) {
    throw std::invalid_argument("robot dynamics: q, qd, qdd must have " + std::to_string(num_dofs()) + " entries");
  }
  TreeWorkspace workspace = tree_.MakeWorkspace();
  Features(q, qd, qdd, &workspace, A);
}

void RobotDynamics::Features(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                             TreeWorkspace* workspace, Eigen::Ref<Eigen::MatrixXd> A) const {
  INERTIAL_ASSERT(A.rows() == num_dofs() && A.cols() == num_features_);
  tree_.JointTorqueRegressor(q, qd, qdd, gravity_, workspace, A.leftCols(num_tree_features()));
  A.rightCols(num_features_ - num_tree_features()).setZero();
  for (const EstimatedBody& b : bodies_) {
    if (b.block != b.tree_body) A.middleCols<10>(10 * b.block) = A.middleCols<10>(10 * b.tree_body);
  }
  for (const EffectTerm& t : effects_) {
    const std::array<double, 2> a = EffectFeatures(t, q, qd, qdd);
    for (int k = 0; k < t.size(); ++k) A(t.dof, t.first_feature + k) = a[k];
  }
}

Eigen::VectorXd RobotDynamics::Coefficients(const Eigen::VectorXd& x, Eigen::MatrixXd* J_w_x) const {
  if (x.size() != num_parameters_) {
    throw std::invalid_argument("robot dynamics: " + std::to_string(x.size()) + " parameters given, " +
                                std::to_string(num_parameters_) + " expected");
  }
  Eigen::VectorXd w = Eigen::VectorXd::Zero(num_features_);
  if (J_w_x != nullptr) J_w_x->setZero(num_features_, num_parameters_);
  Matrix10 J;
  for (size_t e = 0; e < bodies_.size(); ++e) {
    const Vector10 theta = x.segment<10>(10 * e);
    const int row = 10 * bodies_[e].block;
    w.segment<10>(row) += bodies_[e].map.ToPi(theta, J_w_x != nullptr ? &J : nullptr);
    if (J_w_x != nullptr) J_w_x->block<10, 10>(row, 10 * e) = J;
  }
  for (const EffectTerm& t : effects_) {
    const int p = t.first_parameter, f = t.first_feature;
    if (t.kind == EffectKind::kOffset) {
      w[f] = x[p];
      if (J_w_x != nullptr) (*J_w_x)(f, p) = 1.0;
    } else if (t.kind == EffectKind::kSpring) {
      const double k = std::exp(x[p]);
      w[f] = k;
      w[f + 1] = k * x[p + 1];
      if (J_w_x != nullptr) {
        (*J_w_x)(f, p) = k;
        (*J_w_x)(f + 1, p) = k * x[p + 1];
        (*J_w_x)(f + 1, p + 1) = k;
      }
    } else {
      for (int k = 0; k < t.size(); ++k) {  // every coefficient e^s
        w[f + k] = std::exp(x[p + k]);
        if (J_w_x != nullptr) (*J_w_x)(f + k, p + k) = w[f + k];
      }
    }
  }
  return w;
}

Eigen::VectorXd RobotDynamics::InverseDynamics(const Eigen::VectorXd& x, const Eigen::VectorXd& q,
                                               const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) const {
  return InverseDynamicsFromCoefficients(Coefficients(x), q, qd, qdd);
}

Eigen::VectorXd RobotDynamics::InverseDynamicsFromCoefficients(const Eigen::VectorXd& w, const Eigen::VectorXd& q,
                                                               const Eigen::VectorXd& qd,
                                                               const Eigen::VectorXd& qdd) const {
  if (w.size() != num_features_) {
    throw std::invalid_argument("robot dynamics: " + std::to_string(w.size()) + " coefficients given, " +
                                std::to_string(num_features_) + " expected");
  }
  Eigen::VectorXd tau;
  if (num_blocks_ == tree_.num_bodies()) {
    tau = tree_.InverseDynamics(w.head(num_tree_features()), q, qd, qdd, gravity_);
  } else {  // payloads with blocks of their own move with their tree bodies
    Eigen::VectorXd pi = w.head(num_tree_features());
    for (const EstimatedBody& b : bodies_) {
      if (b.block != b.tree_body) pi.segment<10>(10 * b.tree_body) += w.segment<10>(10 * b.block);
    }
    tau = tree_.InverseDynamics(pi, q, qd, qdd, gravity_);
  }
  for (const EffectTerm& t : effects_) {
    const std::array<double, 2> a = EffectFeatures(t, q, qd, qdd);
    for (int k = 0; k < t.size(); ++k) tau[t.dof] += a[k] * w[t.first_feature + k];
  }
  return tau;
}

Eigen::VectorXd RobotDynamics::ParametersFromEffectCoefficients(const Eigen::VectorXd& c, double floor) const {
  if (c.size() != num_features_ - num_inertia_features()) {
    throw std::invalid_argument("robot dynamics: " + std::to_string(c.size()) + " effect coefficients given, " +
                                std::to_string(num_features_ - num_inertia_features()) + " expected");
  }
  Eigen::VectorXd x = Eigen::VectorXd::Zero(num_parameters_);
  for (const EffectTerm& t : effects_) {
    const int p = t.first_parameter, f = t.first_feature - num_inertia_features();
    if (t.kind == EffectKind::kOffset) {
      x[p] = c[f];
    } else if (t.kind == EffectKind::kSpring) {
      const double k = std::max(c[f], floor);
      x[p] = std::log(k);
      x[p + 1] = c[f + 1] / k;
    } else if (NonNegative(t.kind)) {
      for (int k = 0; k < t.size(); ++k) x[p + k] = std::log(std::max(c[f + k], floor));
    }
  }
  return x;
}

Eigen::VectorXd RobotDynamics::ParametersFromEffectValues(const std::vector<ModelEffect>& effects) const {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(num_parameters_);
  for (const EffectTerm& t : effects_) {
    const std::string name = std::string(ToString(t.kind)) + "@" + t.joint;
    const ModelEffect* found = nullptr;
    for (const ModelEffect& e : effects) {
      if (e.spec.kind == t.kind && (e.spec.target == t.joint || e.spec.target.empty())) found = &e;
    }
    if (found == nullptr) throw std::invalid_argument("robot dynamics: no coefficients given for " + name);
    const std::vector<double>& v = found->values;
    if (static_cast<int>(v.size()) != t.size()) {
      throw std::invalid_argument("robot dynamics: " + name + " needs " + std::to_string(t.size()) + " coefficients, " +
                                  std::to_string(v.size()) + " given");
    }
    for (double value : v) {
      if (!std::isfinite(value)) throw std::invalid_argument("robot dynamics: a coefficient of " + name + " is not finite");
    }
    const int p = t.first_parameter;
    if (t.kind == EffectKind::kOffset) {
      x[p] = v[0];
      continue;
    }
    if (t.kind == EffectKind::kSpring) {
      if (v[0] < 0.0) throw std::invalid_argument("robot dynamics: the stiffness of " + name + " must be >= 0");
      x[p] = std::log(std::max(v[0], 1e-300));
      x[p + 1] = v[1];
      continue;
    }
    for (int k = 0; k < t.size(); ++k) {
      if (v[k] < 0.0) throw std::invalid_argument("robot dynamics: the coefficients of " + name + " must be >= 0");
      x[p + k] = std::log(std::max(v[k], 1e-300));
    }
  }
  return x;
}

InertialParams RobotDynamics::BodyInertia(int e, const Eigen::VectorXd& x) const {
  const EstimatedBody& b = bodies_.at(e);
  const InertialParams in_body = InertialParams::FromVector(b.map.ToPi(x.segment<10>(10 * e)));
  const Matrix3 R = b.report_frame.R_AB.transpose();
  return in_body.Transformed(R, -(R * b.report_frame.p_AB));
}

std::vector<double> RobotDynamics::EffectValues(int k, const Eigen::VectorXd& x) const {
  const EffectTerm& t = effects_.at(k);
  const int p = t.first_parameter;
  if (t.kind == EffectKind::kOffset) return {x[p]};
  if (t.kind == EffectKind::kSpring) return {std::exp(x[p]), x[p + 1]};
  if (t.kind == EffectKind::kAsymmetric) return {std::exp(x[p]), std::exp(x[p + 1])};
  return {std::exp(x[p])};
}

}  // namespace inertial
