/// @file user_region.hpp
/// A body's region given by the user (body_region.hpp: "a bounding ellipsoid per link ... or given
/// by the user"), in place of the automatic one, as the fitting commands take it:
///
///   --region LINK=cx,cy,cz,a,b,c[:rpy=r,p,y]
///
/// an ellipsoid with centre (cx, cy, cz) [m] and semi-axes a, b, c [m] along the axes of LINK's
/// frame, or, with rpy, along the axes of the frame R(r, p, y) (URDF's fixed-axis roll-pitch-yaw,
/// R = Rz(y) Ry(p) Rx(r)) in LINK's frame. LINK is a URDF link that moves with a joint (a link fixed
/// to another by a fixed joint names that link's body, the ellipsoid still in its own frame), or
/// payload@LINK for a payload of the model (its region, given in LINK's frame).
/// The region's source is RegionSource::kUser ("the user (--region)"); its largest mass follows the
/// automatic regions' rule (kMaxRegionDensity, solid steel, over its volume); its semi-axes are used
/// as given, no margin added: what the user states is what the fit keeps (Wensing, Kim and Slotine,
/// RA-L 2018: tr(Q J) >= 0 for the ellipsoid's Q, bounding_ellipsoid.hpp).
/// A fit starts at the prior, so a given region must hold the body's prior strictly (slack > 0,
/// mass below the region's largest): otherwise the option is refused, naming the prior's slack.
///
/// Conventions: SI units; the region in the link's frame as given, stored in the tree body's frame.
#pragma once

#include <string>
#include <vector>

#include "inertial/formats/urdf_model.hpp"
#include "inertial/model/robot_dynamics.hpp"

namespace inertial {

struct UserRegion {
  std::string target;                   ///< a URDF link, or payload@LINK
  Vector3 center = Vector3::Zero();     ///< [m] in the link's frame
  Vector3 semi_axes = Vector3::Ones();  ///< [m] along the columns of R(rpy)
  Vector3 rpy = Vector3::Zero();        ///< [rad] the ellipsoid's axes in the link's frame
  std::string text;                     ///< as given, for messages
};

/// Parses one --region value (file comment). `option` names the option in errors ("--region").
/// @throws InvalidNumber (number_parsing.hpp) for a value that is not a finite number; otherwise
/// std::invalid_argument saying what is wrong: no '=', no link, a count of numbers other than 6 (or
/// 3 for rpy), a semi-axis that is not positive, an unknown key.
UserRegion ParseUserRegion(const std::string& text, const std::string& option = "--region");

/// The estimated body a region is for and the region in that body's (tree body's) frame.
struct PlacedUserRegion {
  int body = -1;  ///< index into model.bodies()
  BodyRegion region;
};

/// Where `region` goes in `model` (built from `robot`). require_body: a payload@LINK that the model
/// does not have is an error (false: body -1 returned for it, e.g. a diagnosis's candidate payload
/// that is not in every model).
/// @throws std::invalid_argument naming the region and what is wrong: an unknown link (naming the
/// links that move), a link fixed to the base, a rotor, a missing payload, a region that does not hold
/// the body's prior strictly (with the prior's slack and mass against the region's largest).
PlacedUserRegion PlaceUserRegion(const RobotModel& robot, const RobotDynamics& model, const UserRegion& region,
                                 bool require_body = true);

/// Places every region (PlaceUserRegion) and replaces those bodies' regions in *model.
/// @throws std::invalid_argument as PlaceUserRegion, and for two regions given to one body.
void ApplyUserRegions(const RobotModel& robot, const std::vector<UserRegion>& regions, RobotDynamics* model,
                      bool require_body = true);

}  // namespace inertial
