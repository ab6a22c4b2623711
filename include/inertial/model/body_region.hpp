/// @file body_region.hpp
/// Where each estimated body's mass may lie, so that a fit returns bodies a robot could have, not
/// only physically consistent ones: a bounding ellipsoid per body (bounding_ellipsoid.hpp; the
/// condition tr(Q J) >= 0 of Wensing, Kim and Slotine, RA-L 2018) and the largest mass that region
/// can hold.
///
/// Where a region comes from, in this order:
///  1. The link's own shape ("drawn geometry"): the URDF's collision shapes of every link merged
///     into the body (formats/ reads them: primitives by ShapePoints*, meshes whose files are at
///     hand by formats/mesh_vertices.hpp), when they draw all of the body's material (no mesh left
///     unread, no link with mass undrawn), with kShapeRegionMargin. Visual shapes are not used:
///     they are drawn for looks, not to enclose. Collision shapes are drawn to enclose the link for collision
///     checking, so they hold its mass already; the margin covers what they leave out (cables,
///     connectors) and the point sampling of round shapes (already circumscribed,
///     ShapePointsOfSphere).
///  2. Otherwise (meshes whose files are not at hand, as most vendor URDFs name `package://` files
///     that are not shipped with the URDF, or no geometry): the link's segment, i.e. its joint (the frame origin), the joints of the
///     bodies it carries and the frames fixed to it (a flange, tool0), each dilated by a ball of the prior's RMS radius rho0 = sqrt(tr(Sigma_c)/m)
///     (a link is a shell about its joint axes about as thick as its own mass is spread), with
///     kSegmentRegionMargin. The margin: CAD moments are up to about 50 % off (plausibility.hpp),
///     which is radii up to sqrt(1.5) = 1.22 times the prior's; 0.25 leaves that inside.
///  3. A payload: a ball about its link's frame origin whose radius is the robot's longest
///     joint-to-joint segment (an object held at a link that reaches farther from it than the
///     robot's longest link is not a payload that link holds).
///  4. Rotors: none (a rotor turns about its own axis; its inertia is not a shape the URDF draws).
/// Every region also holds the prior's equivalent uniform ellipsoid (EquivalentUniformEllipsoid),
/// so that the prior itself is strictly inside: the fit starts feasible.
/// The region is the smallest ellipsoid holding those points (MinimumVolumeEllipsoid), its
/// semi-axes then multiplied by 1 + margin.
///
/// Mass. No link is denser than solid steel throughout its bounding ellipsoid (which is much larger
/// than the link's material: a box's is 2.7 times its volume, and links are hollow):
/// max_mass = kMaxRegionDensity * volume.
///
/// Conventions: SI units; every region in its body's tree-body frame (as EstimatedBody::prior).
#pragma once

#include <string>
#include <vector>

#include "inertial/inertia/bounding_ellipsoid.hpp"
#include "inertial/inertia/log_cholesky.hpp"
#include "inertial/model/kinematic_tree.hpp"

namespace inertial {

/// [kg/m^3] steel (7850) over the whole region: the mass bound of the file comment.
inline constexpr double kMaxRegionDensity = 7850.0;
inline constexpr double kShapeRegionMargin = 0.10;
inline constexpr double kSegmentRegionMargin = 0.25;

/// A body whose slack s = tr(Q J) / m is at least this, and whose mass is at most 1 - this of the
/// region's bound, is well inside its region: the fit's barrier (region_barrier.hpp) acts only
/// below it, so such a body is fitted exactly as without the region. (s = 0.4 for a solid
/// ellipsoid filling its region, 0 for a shell on its surface.)
inline constexpr double kWellInsideSlack = 0.1;

enum class RegionSource { kShape, kSegment, kPayloadReach, kUser };
/// "drawn geometry", "joints and prior", "payload reach", "the user (--region)" (each follows
/// "region from" in the reports).
const char* ToString(RegionSource source);

struct BodyRegion {
  BoundingEllipsoid ellipsoid;
  double max_mass = 0.0;  ///< kMaxRegionDensity * ellipsoid.Volume() [kg]
  RegionSource source = RegionSource::kSegment;
};

/// The region of the smallest ellipsoid holding `points` and the prior's equivalent uniform
/// ellipsoid, its semi-axes multiplied by 1 + margin (file comment).
/// @throws std::invalid_argument if the prior is not fully consistent or the points are not finite.
BodyRegion RegionAround(const std::vector<Vector3>& points, const InertialParams& prior, double margin,
                        RegionSource source);

/// The region of the smallest ellipsoid holding `points` alone, its semi-axes multiplied by
/// 1 + margin: what the link's geometry says without its inertia. Not for a fit (its prior need not
/// be inside); for judging a drawn inertia against the drawing's own shapes (validate, check).
/// @throws std::invalid_argument as MinimumVolumeEllipsoid (fewer than 4 points, points in a plane).
BodyRegion RegionOfPoints(const std::vector<Vector3>& points, double margin, RegionSource source);

/// Points around a ball, circumscribing it: 26 directions (the cube's faces, edges and corners)
/// at radius r / 0.9 (the polytope of those 26 unit directions holds the ball of radius 0.9, more
/// than its inradius cos(25.3 deg) = 0.904 rounded down), so their enclosing ellipsoid holds the ball.
std::vector<Vector3> ShapePointsOfSphere(const Vector3& center, double radius);
/// The 8 corners of a box of `size` (full edge lengths) posed at (R, p).
std::vector<Vector3> ShapePointsOfBox(const Matrix3& R, const Vector3& p, const Vector3& size);
/// A cylinder of `radius` and `length` along its z axis, posed at (R, p): each end's circle by 12
/// points at radius r / cos(15 deg) (the 12-gon circumscribing it).
std::vector<Vector3> ShapePointsOfCylinder(const Matrix3& R, const Vector3& p, double radius, double length);

/// The segment region of tree body `body` (source 2 of the file comment): its joint, the joints of
/// its children in `tree` and `fixed_frames` (the origins, in its frame, of the frames fixed to it:
/// a flange, tool0, a sensor; its material reaches them), dilated by the prior's RMS radius.
BodyRegion SegmentRegion(const KinematicTree& tree, int body, const InertialParams& prior,
                         const std::vector<Vector3>& fixed_frames = {});

/// The slack a simulated truth keeps at least (ShrinkIntoRegion): twice kWellInsideSlack, so that a
/// fit of its data, which noise moves about the truth, does not reach the barrier's onset.
inline constexpr double kSimulatedTruthSlack = 2.0 * kWellInsideSlack;

/// theta (log-Cholesky relative to `map`'s prior) scaled by 0.8^k with the smallest k >= 0 that
/// leaves the body with slack at least kSimulatedTruthSlack and mass at most (1 - that) of the
/// region's bound: a random draw of a body about its prior pulled back toward the prior until the
/// link could have it (simulation's plausible truths). 0 (the prior) if no k <= 60 does.
Vector10 ShrinkIntoRegion(const LogCholeskyParameterization& map, const BodyRegion& region, const Vector10& theta);

/// The robot's longest joint-to-joint segment: the largest |p_parent_joint| over the tree's
/// non-rotor bodies that have a parent body [m] (0 for a robot of one body).
double LongestSegment(const KinematicTree& tree);

}  // namespace inertial
