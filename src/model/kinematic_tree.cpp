#include "inertial/model/kinematic_tree.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "inertial/inertia/assert.hpp"
#include "inertial/model/rigid_body_regressor.hpp"
#include "inertial/model/spatial_algebra.hpp"

namespace inertial {

Vector6 SpatialTransform::ApplyToMotion(const Vector6& v_A) const {
  const Vector3 w = v_A.head<3>();
  Vector6 v_B;
  v_B.head<3>() = R_AB.transpose() * w;
  v_B.tail<3>() = R_AB.transpose() * (v_A.tail<3>() - p_AB.cross(w));
  return v_B;
}

Vector6 SpatialTransform::ApplyTransposeToForce(const Vector6& f_B) const {
  Vector6 f_A;
  f_A.tail<3>() = R_AB * f_B.tail<3>();
  f_A.head<3>() = R_AB * f_B.head<3>() + p_AB.cross(f_A.tail<3>());
  return f_A;
}

int KinematicTree::AddBody(const std::string& name, int parent, const JointModel& joint,
                           const InertialParams& inertia) {
  if (parent < -1 || parent >= num_bodies()) {
    throw std::invalid_argument("body '" + name + "': parent index " + std::to_string(parent) +
                                " does not exist (add parents first)");
  }
  if (!joint.R_parent_joint.allFinite() || !joint.p_parent_joint.allFinite() || !joint.axis.allFinite() ||
      !inertia.AllFinite()) {
    throw std::invalid_argument("body '" + name + "': non-finite joint origin, axis or inertia");
  }
  if (joint.type != JointType::kFixed && std::abs(joint.axis.norm() - 1.0) > 1e-9) {
    throw std::invalid_argument("body '" + name + "': joint '" + joint.name + "' axis is not a unit vector");
  }
  Body b;
  b.name = name;
  b.parent = parent;
  b.joint = joint;
  b.inertia = inertia;
  b.dof = joint.type == JointType::kFixed ? -1 : num_dofs_++;
  bodies_.push_back(b);
  return num_bodies() - 1;
}

int KinematicTree::AddRotor(const std::string& name, int parent, const JointModel& joint,
                            const InertialParams& inertia, int driven_dof, double gear_ratio) {
  if (joint.type != JointType::kRevolute) {
    throw std::invalid_argument("rotor '" + name + "': its joint must be revolute");
  }
  if (driven_dof < 0 || driven_dof >= num_dofs_) {
    throw std::invalid_argument("rotor '" + name + "': driven DOF " + std::to_string(driven_dof) +
                                " does not exist");
  }
  if (!std::isfinite(gear_ratio) || gear_ratio == 0.0) {
    throw std::invalid_argument("rotor '" + name + "': gear ratio must be finite and non-zero");
  }
  const int dofs_before = num_dofs_;
  const int i = AddBody(name, parent, joint, inertia);
  num_dofs_ = dofs_before;
  bodies_[i].dof = driven_dof;
  bodies_[i].gear = gear_ratio;
  bodies_[i].rotor = true;
  return i;
}

Eigen::VectorXd KinematicTree::StackedParameters() const {
  Eigen::VectorXd pi(10 * num_bodies());
  for (int i = 0; i < num_bodies(); ++i) pi.segment<10>(10 * i) = bodies_[i].inertia.vector();
  return pi;
}

SpatialTransform KinematicTree::ParentToBody(int i, double q_i) const {
  const JointModel& j = bodies_[i].joint;
  SpatialTransform X;
  X.R_AB = j.R_parent_joint;
  X.p_AB = j.p_parent_joint;
  if (j.type == JointType::kRevolute) {
    X.R_AB = j.R_parent_joint * Eigen::AngleAxisd(q_i, j.axis).toRotationMatrix();
  } else if (j.type == JointType::kPrismatic) {
    X.p_AB = j.p_parent_joint + j.R_parent_joint * (q_i * j.axis);
  }
  return X;
}

Vector6 KinematicTree::MotionSubspace(int i) const {
  const JointModel& j = bodies_[i].joint;
  Vector6 S = Vector6::Zero();
  // The axis is fixed in the joint frame and unchanged by motion along itself, so it has the same
  // coordinates in the body frame.
  if (j.type == JointType::kRevolute) S.head<3>() = j.axis;
  if (j.type == JointType::kPrismatic) S.tail<3>() = j.axis;
  return S;
}

void KinematicTree::CheckSizes(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) const {
  if (q.size() != num_dofs_ || qd.size() != num_dofs_ || qdd.size() != num_dofs_) {
    throw std::invalid_argument("kinematic tree: q, qd, qdd must have " + std::to_string(num_dofs_) +
                                " entries, got " + std::to_string(q.size()) + ", " + std::to_string(qd.size()) +
                                ", " + std::to_string(qdd.size()));
  }
}

TreeWorkspace KinematicTree::MakeWorkspace() const {
  TreeWorkspace ws;
  ws.X.resize(bodies_.size());
  ws.v.resize(bodies_.size());
  ws.a.resize(bodies_.size());
  return ws;
}

void KinematicTree::Kinematics(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                               const Vector3& g_base, TreeWorkspace* ws) const {
  INERTIAL_ASSERT(q.size() == num_dofs_ && qd.size() == num_dofs_ && qdd.size() == num_dofs_);
  INERTIAL_ASSERT(ws->X.size() == bodies_.size() && ws->v.size() == bodies_.size() && ws->a.size() == bodies_.size());
  const int n = num_bodies();
  Vector6 a_base = Vector6::Zero();
  a_base.tail<3>() = -g_base;  // gravity as an upward acceleration of the base (Featherstone 5.3)
  for (int i = 0; i < n; ++i) {
    const Body& b = bodies_[i];
    // A rotor turns by gear * q (zero offset at q = 0), so a non-symmetric rotor's pose is exact.
    const double qi = b.dof >= 0 ? b.gear * q[b.dof] : 0.0;
    const double qdi = b.dof >= 0 ? b.gear * qd[b.dof] : 0.0;
    const double qddi = b.dof >= 0 ? b.gear * qdd[b.dof] : 0.0;
    ws->X[i] = ParentToBody(i, qi);
    const Vector6 v_parent = b.parent >= 0 ? ws->v[b.parent] : Vector6::Zero();
    const Vector6 a_parent = b.parent >= 0 ? ws->a[b.parent] : a_base;
    const Vector6 S = MotionSubspace(i);
    ws->v[i] = ws->X[i].ApplyToMotion(v_parent) + S * qdi;
    ws->a[i] = ws->X[i].ApplyToMotion(a_parent) + S * qddi + MotionCross(ws->v[i]) * (S * qdi);
  }
}

Eigen::VectorXd KinematicTree::InverseDynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                               const Eigen::VectorXd& qdd, const Vector3& g_base) const {
  return InverseDynamics(StackedParameters(), q, qd, qdd, g_base);
}

Eigen::VectorXd KinematicTree::InverseDynamics(const Eigen::VectorXd& pi, const Eigen::VectorXd& q,
                                               const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                                               const Vector3& g_base) const {
  CheckSizes(q, qd, qdd);
  const int n = num_bodies();
  if (pi.size() != 10 * n) {
    throw std::invalid_argument("kinematic tree: " + std::to_string(pi.size()) + " inertial parameters given, " +
                                std::to_string(10 * n) + " expected (10 per body)");
  }
  TreeWorkspace ws = MakeWorkspace();
  Kinematics(q, qd, qdd, g_base, &ws);
  std::vector<Vector6> f(n);
  for (int i = 0; i < n; ++i) {
    const Matrix6 M = InertialParams::FromVector(pi.segment<10>(10 * i)).spatial_inertia();
    f[i] = M * ws.a[i] + ForceCross(ws.v[i]) * (M * ws.v[i]);
  }
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(num_dofs_);
  for (int i = n - 1; i >= 0; --i) {
    if (bodies_[i].dof >= 0) tau[bodies_[i].dof] += bodies_[i].gear * MotionSubspace(i).dot(f[i]);
    if (bodies_[i].parent >= 0) f[bodies_[i].parent] += ws.X[i].ApplyTransposeToForce(f[i]);
  }
  return tau;
}

Eigen::MatrixXd KinematicTree::JointTorqueRegressor(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                                    const Eigen::VectorXd& qdd, const Vector3& g_base) const {
  CheckSizes(q, qd, qdd);
  TreeWorkspace ws = MakeWorkspace();
  Eigen::MatrixXd Y(num_dofs_, 10 * num_bodies());
  JointTorqueRegressor(q, qd, qdd, g_base, &ws, Y);
  return Y;
}

void KinematicTree::JointTorqueRegressor(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                         const Eigen::VectorXd& qdd, const Vector3& g_base, TreeWorkspace* ws,
                                         Eigen::Ref<Eigen::MatrixXd> Y) const {
  INERTIAL_ASSERT(Y.rows() == num_dofs_ && Y.cols() == 10 * num_bodies());
  Kinematics(q, qd, qdd, g_base, ws);
  Y.setZero();
  for (int i = 0; i < num_bodies(); ++i) {
    // Body i's wrench, linear in its pi, carried up to the root: each ancestor joint j sees S_j^T F.
    Matrix6x10 F = RigidBodyRegressor(ws->v[i], ws->a[i]);
    for (int j = i; j >= 0; j = bodies_[j].parent) {
      if (bodies_[j].dof >= 0) {
        Y.block<1, 10>(bodies_[j].dof, 10 * i) += bodies_[j].gear * (MotionSubspace(j).transpose() * F);
      }
      if (bodies_[j].parent >= 0) {
        // X^T F column by column: [R m + p x (R f); R f], as one 3x3 product per half.
        const SpatialTransform& X = ws->X[j];
        const Eigen::Matrix<double, 3, 10> f = X.R_AB * F.bottomRows<3>();
        const Eigen::Matrix<double, 3, 10> m = X.R_AB * F.topRows<3>();
        F.bottomRows<3>() = f;
        F.topRows<3>() = m + Skew(X.p_AB) * f;
      }
    }
  }
}

std::vector<Vector6> KinematicTree::BodyVelocities(const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(num_dofs_);
  CheckSizes(q, qd, zero);
  TreeWorkspace ws = MakeWorkspace();
  Kinematics(q, qd, zero, Vector3::Zero(), &ws);
  return ws.v;
}

std::vector<SpatialTransform> KinematicTree::BodyPoses(const Eigen::VectorXd& q) const {
  if (q.size() != num_dofs_) {
    throw std::invalid_argument("kinematic tree: q must have " + std::to_string(num_dofs_) + " entries, got " +
                                std::to_string(q.size()));
  }
  std::vector<SpatialTransform> pose(num_bodies());
  for (int i = 0; i < num_bodies(); ++i) {
    const SpatialTransform X = ParentToBody(i, bodies_[i].dof >= 0 ? bodies_[i].gear * q[bodies_[i].dof] : 0.0);
    if (bodies_[i].parent < 0) {
      pose[i] = X;
    } else {
      const SpatialTransform& P = pose[bodies_[i].parent];
      pose[i].R_AB = P.R_AB * X.R_AB;
      pose[i].p_AB = P.p_AB + P.R_AB * X.p_AB;
    }
  }
  return pose;
}

}  // namespace inertial
