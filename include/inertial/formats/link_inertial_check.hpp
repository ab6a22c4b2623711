/// @file link_inertial_check.hpp
/// The physical consistency of every link's `<inertial>` in a URDF (`inertial check`): each link
/// with its margins, the nearest consistent body (same mass and COM) of each impossible one, and a
/// repaired copy of the file, checked again after it is written.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "inertial/formats/urdf_model.hpp"
#include "inertial/inertia/consistency.hpp"

namespace inertial {

/// What a link's `<inertial>` is.
enum class LinkInertialKind {
  kAbsent,   ///< no <inertial> element
  kZero,     ///< all ten numbers zero (a massless frame)
  kPresent,  ///< a body, checked
};

/// One link of the file.
struct LinkInertialCheck {
  std::string link;
  bool used_by_dynamics = false;  ///< part of a moving body (not fixed to the base)
  LinkInertialKind kind = LinkInertialKind::kAbsent;
  ConsistencyReport consistency;  ///< kPresent only
  /// An impossible link's nearest consistent body (nearest_consistent.hpp), if it has one ...
  std::optional<InertialParams> repaired;
  /// ... else why not (e.g. its mass is not positive).
  std::string unrepairable;

  /// A body that is not fully physically consistent.
  bool impossible() const { return kind == LinkInertialKind::kPresent && !consistency.fully_consistent(); }
};

/// Every link of a URDF, in file order.
struct UrdfInertialCheck {
  std::string path;  ///< the file checked
  std::string robot;
  int moving_joints = 0;
  std::vector<LinkInertialCheck> links;

  int checked() const;     ///< links with a body (kPresent)
  int impossible() const;  ///< of them, the impossible ones
  /// Link name -> repaired body, for every impossible link that has one.
  std::map<std::string, InertialParams> Repairs() const;
};

/// Checks every link of `robot`, read from `path` (loaded without requiring consistent inertials).
UrdfInertialCheck CheckLinkInertials(const std::string& path, const RobotModel& robot);

/// Loads the URDF at `path` without requiring consistent inertials and checks every link.
/// @throws UrdfError if it cannot be read or loaded.
UrdfInertialCheck CheckUrdfInertials(const std::string& path);

/// A repaired copy of a checked URDF.
struct UrdfRepair {
  std::string path;          ///< the copy written
  int repaired = 0;          ///< links given their nearest consistent body
  int still_impossible = 0;  ///< links of the copy, read back, that are still impossible (mass <= 0)
};

/// Writes `check.path` to `out_path` with every repairable impossible link replaced by its nearest
/// consistent body (the rest of the file as it was), then reads the copy back and checks it.
/// @throws UrdfError if the file cannot be read or the copy written or read.
UrdfRepair WriteRepairedUrdf(const UrdfInertialCheck& check, const std::string& out_path);

}  // namespace inertial
