#include "inertial/model/body_region.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "inertial/inertia/consistency.hpp"

namespace inertial {

const char* ToString(RegionSource source) {
  switch (source) {
    case RegionSource::kShape: return "drawn geometry";
    case RegionSource::kSegment: return "joints and prior";
    case RegionSource::kPayloadReach: return "payload reach";
    case RegionSource::kUser: return "the user (--region)";
  }
  return "?";
}

std::vector<Vector3> ShapePointsOfSphere(const Vector3& center, double radius) {
  std::vector<Vector3> points;
  for (int i = -1; i <= 1; ++i) {
    for (int j = -1; j <= 1; ++j) {
      for (int k = -1; k <= 1; ++k) {
        if (i == 0 && j == 0 && k == 0) continue;
        points.push_back(center + Vector3(i, j, k).normalized() * (radius / 0.9));
      }
    }
  }
  return points;
}

std::vector<Vector3> ShapePointsOfBox(const Matrix3& R, const Vector3& p, const Vector3& size) {
  std::vector<Vector3> points;
  for (int i = 0; i < 8; ++i) {
    const Vector3 corner((i & 1 ? 0.5 : -0.5) * size.x(), (i & 2 ? 0.5 : -0.5) * size.y(), (i & 4 ? 0.5 : -0.5) * size.z());
    points.push_back(p + R * corner);
  }
  return points;
}

std::vector<Vector3> ShapePointsOfCylinder(const Matrix3& R, const Vector3& p, double radius, double length) {
  std::vector<Vector3> points;
  const double r = radius / std::cos(M_PI / 12.0);
  for (int end = -1; end <= 1; end += 2) {
    for (int k = 0; k < 12; ++k) {
      const double a = 2.0 * M_PI * k / 12.0;
      points.push_back(p + R * Vector3(r * std::cos(a), r * std::sin(a), 0.5 * end * length));
    }
  }
  return points;
}

BodyRegion RegionAround(const std::vector<Vector3>& points, const InertialParams& prior, double margin,
                        RegionSource source) {
  if (!CheckConsistency(prior).fully_consistent()) {
    throw std::invalid_argument("body region: the prior is not fully physically consistent");
  }
  std::vector<Vector3> all = points;
  // The prior's equivalent uniform ellipsoid, by its 6 axis ends and 20 more points circumscribing it
  // (the unit ball's 26 points of ShapePointsOfSphere mapped through the ellipsoid).
  const BoundingEllipsoid own = EquivalentUniformEllipsoid(prior);
  const Eigen::SelfAdjointEigenSolver<Matrix3> eig(own.shape_inverse);
  const Matrix3 to_ellipsoid = eig.eigenvectors() * eig.eigenvalues().cwiseSqrt().cwiseInverse().asDiagonal();
  for (const Vector3& u : ShapePointsOfSphere(Vector3::Zero(), 1.0)) all.push_back(own.center + to_ellipsoid * u);
  BodyRegion region;
  region.ellipsoid = MinimumVolumeEllipsoid(all).Scaled(1.0 + margin);
  region.max_mass = kMaxRegionDensity * region.ellipsoid.Volume();
  region.source = source;
  return region;
}

BodyRegion RegionOfPoints(const std::vector<Vector3>& points, double margin, RegionSource source) {
  BodyRegion region;
  region.ellipsoid = MinimumVolumeEllipsoid(points).Scaled(1.0 + margin);
  region.max_mass = kMaxRegionDensity * region.ellipsoid.Volume();
  region.source = source;
  return region;
}

BodyRegion SegmentRegion(const KinematicTree& tree, int body, const InertialParams& prior,
                         const std::vector<Vector3>& fixed_frames) {
  const Vector3 c = prior.com();
  const Matrix3 sigma_c = prior.second_moments_about_origin() - prior.mass() * c * c.transpose();
  const double rho0 = std::sqrt(sigma_c.trace() / prior.mass());
  std::vector<Vector3> joints{Vector3::Zero()};
  for (int child = 0; child < tree.num_bodies(); ++child) {
    if (tree.parent(child) == body && !tree.is_rotor(child)) joints.push_back(tree.joint(child).p_parent_joint);
  }
  joints.insert(joints.end(), fixed_frames.begin(), fixed_frames.end());
  std::vector<Vector3> points;
  for (const Vector3& j : joints) {
    const std::vector<Vector3> ball = ShapePointsOfSphere(j, rho0);
    points.insert(points.end(), ball.begin(), ball.end());
  }
  return RegionAround(points, prior, kSegmentRegionMargin, RegionSource::kSegment);
}

Vector10 ShrinkIntoRegion(const LogCholeskyParameterization& map, const BodyRegion& region, const Vector10& theta) {
  double scale = 1.0;
  for (int k = 0; k <= 60; ++k, scale *= 0.8) {
    const Vector10 pi = map.ToPi(scale * theta);
    if (!pi.allFinite() || !(pi[0] > 0.0)) continue;
    const InertialParams body = InertialParams::FromVector(pi);
    if (region.ellipsoid.Slack(body) >= kSimulatedTruthSlack && pi[0] <= (1.0 - kSimulatedTruthSlack) * region.max_mass) {
      return scale * theta;
    }
  }
  return Vector10::Zero();
}

double LongestSegment(const KinematicTree& tree) {
  double longest = 0.0;
  for (int b = 0; b < tree.num_bodies(); ++b) {
    if (tree.parent(b) >= 0 && !tree.is_rotor(b)) longest = std::max(longest, tree.joint(b).p_parent_joint.norm());
  }
  return longest;
}

}  // namespace inertial
