/// @file payload_report.hpp
/// A payload (payload_identification.hpp) in the forms controllers load, and as a report:
///
/// - Universal Robots URScript: `set_target_payload(m, [cx, cy, cz], [Ixx, Iyy, Izz, Ixy, Ixz, Iyz])`
///   (URScript manual, set_target_payload(m, cog, inertia, transition_time): mass in kg, the CoG
///   offset in m from the tool mount, the inertia matrix in kg m^2 with origin in the CoG and axes
///   aligned with the tool flange's, as six elements in that order).
/// - Franka (libfranka): `robot.setLoad(m, {cx, cy, cz}, {I00, I10, I20, I01, ...});`, i.e.
///   franka::Robot::setLoad(load_mass, F_x_Cload, load_inertia): F_x_Cload the COM in the flange
///   frame, load_inertia the 3 x 3 inertia about the COM column-major (symmetric: Ixx, Ixy, Ixz,
///   Ixy, Iyy, Iyz, Ixz, Iyz, Izz).
/// - URDF: a link with the payload's <inertial> (origin at the COM, axes the link's) and a fixed
///   joint to the link that holds it.
/// Every number round-trips (FormatNumberExact, number_text.hpp: the shortest text that reads back
/// as the same double). The frame is the holding link's: for UR and Franka it must be the flange
/// (tool mount) frame, which the caller chooses by the link. Inertia entries are the tensor's (Ixy
/// the (0,1) entry, as URDF's ixy).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "inertial/diagnosis/payload_event.hpp"
#include "inertial/diagnosis/payload_identification.hpp"
#include "inertial/inertia/types.hpp"

namespace inertial {

/// A payload as a controller takes it: mass [kg], COM [m] and inertia about the COM [kg m^2], in
/// the holding link's frame.
struct PayloadValues {
  double mass = 0.0;
  Vector3 com = Vector3::Zero();
  Matrix3 inertia_about_com = Matrix3::Zero();
};

/// From a body (in the link's frame). Precondition: positive mass.
PayloadValues PayloadValuesOf(const InertialParams& payload);

/// The body an online payload event (payload_event.hpp) added, in its link's report frame (the
/// link the event names, which for the controllers must be the flange's body): for a pick-up
/// (positive added mass, finite). nullopt for a put-down (the controller's payload afterwards is
/// what it held before, which the event does not know) or an event without a fit. The event's
/// added pi is an unconstrained least-squares fit, so its inertia about the COM is printed as it
/// is, not checked for consistency.
std::optional<PayloadValues> PayloadValuesOf(const PayloadEvent& event);

/// "set_target_payload(2.5, [0.01, -0.02, 0.05], [Ixx, Iyy, Izz, Ixy, Ixz, Iyz])".
std::string UrScriptPayload(const PayloadValues& p);
/// "robot.setLoad(2.5, {0.01, -0.02, 0.05}, {Ixx, Ixy, Ixz, Ixy, Iyy, Iyz, Ixz, Iyz, Izz});".
std::string FrankaSetLoad(const PayloadValues& p);
/// <link name="payload"> with its <inertial>, then <joint name="payload_joint" type="fixed"> with
/// parent `parent_link` (two-space indented lines, each ending in a newline).
std::string UrdfPayloadLink(const PayloadValues& p, const std::string& parent_link);

/// The report: mass, COM and inertia about the COM with standard deviations, "held by the prior"
/// where the data do not determine a quantity, how it was fitted, then the three forms above.
std::string PayloadText(const PayloadIdentification& r);
/// {link, mass, mass_std, com[3], com_std[3], inertia_about_com {ixx, iyy, izz, ixy, ixz, iyz},
/// inertia_about_com_std {the same}, held_by_prior [names], from_difference, (from the difference:
/// time_shift [s], position_mismatch and its _joint, position_mismatch_unshifted and its _joint,
/// mismatch_torque: BaselinePairing), num_samples, residual_rms, ur_script, franka, urdf} (an
/// infinite std as the string "inf").
nlohmann::json PayloadJson(const PayloadIdentification& r);

}  // namespace inertial
