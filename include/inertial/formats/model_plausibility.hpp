/// @file model_plausibility.hpp
/// The plausibility of a robot model's bodies where no fit ran (`inertial validate`, `inertial
/// check`): the verdicts of model/region_plausibility.hpp, each body judged against a reference
/// that does not come from its own values where one exists.
///
///  - A model file written by inertial records each link's prior (<inertial_priors>, urdf_model.hpp):
///    the link is judged against it exactly as the fit that wrote the file judged it (the region
///    built from that prior as the fit built it, the mass against the prior's), so `validate` of
///    the file calls a body implausible where `identify` did.
///  - Otherwise the link is a drawing and its own prior. With collision primitives, it is judged
///    against the region of those shapes alone (body_region.hpp's source 1 without the prior's own
///    ellipsoid, RegionOfPoints): shapes are drawn to enclose the link, so an inertia whose mass lies
///    outside them (a COM on the wrong side, second moments of a body larger than the link) is wrong
///    in one of the two. Without shapes, its segment region holds its own equivalent ellipsoid by
///    construction (SegmentRegion; an end link's mass lies beyond its joint, where no other geometry
///    says it may be), so only its density can be judged there: a link denser than steel over its
///    region (a mass typed ten times too large with its inertia unchanged, or scaled with it).
///    Its mass is not compared (it is its own reference).
///  - Payloads stated in the file: against their reach region, which holds them; rotors: not judged.
///
/// Conventions: SI units; bodies as the model reports them (RobotDynamics::BodyInertia).
#pragma once

#include <string>
#include <vector>

#include "inertial/formats/urdf_model.hpp"
#include "inertial/model/region_plausibility.hpp"
#include "inertial/model/robot_dynamics.hpp"

namespace inertial {

/// One body judged.
struct JudgedBody {
  int body = -1;                 ///< index into model.bodies()
  std::string name;
  /// Its reference: the prior and region it is judged against (PlausibilityText's body).
  EstimatedBody reference;
  RegionPlausibility plausibility;
  bool against_recorded_prior = false;  ///< a model file's recorded prior (file comment)
};

/// Every body of `model` (built from `robot`, MakeRobotDynamics) that has a region, at x, judged as
/// the file comment says, in model.bodies() order.
/// @throws std::invalid_argument if x does not fit the model.
std::vector<JudgedBody> JudgeModelBodies(const RobotModel& robot, const RobotDynamics& model, const Eigen::VectorXd& x);

/// "recorded prior" for a body judged against a model file's recorded prior, else "itself".
const char* ReferenceName(const JudgedBody& judged);

/// The mass of the links fixed to the base (the root link and those fixed to it), as the URDF
/// states it [kg]: the part of a weighed robot no estimated body holds (total_mass_barrier.hpp's F).
double MassFixedToBase(const RobotModel& robot);

/// The links fixed to the base that have mass, "name (m kg), ..." ("none" if none), for messages.
std::string LinksFixedToBase(const RobotModel& robot);

}  // namespace inertial
