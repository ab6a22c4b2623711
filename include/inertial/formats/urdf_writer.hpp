/// @file urdf_writer.hpp
/// Rewriting an existing URDF file with new inertias (e.g. identified ones) and joint dynamics,
/// keeping everything else (links, joints, visuals, comments, unknown elements) as it is. The XML is
/// re-indented by tinyxml2; numbers are written with full precision (%.17g).
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "inertial/inertia/inertial_params.hpp"
#include "inertial/formats/urdf_model.hpp"

namespace inertial {

/// URDF `<dynamics damping friction>` of a joint (N m s/rad or N s/m; N m or N).
struct JointDynamics {
  double damping = 0;
  double friction = 0;
};

/// What WriteUrdfModel changes in a URDF.
struct UrdfModelChanges {
  /// link name -> pi about that link's frame origin in link axes (see WriteUrdfWithInertias).
  std::map<std::string, InertialParams> inertias;
  /// links whose `<inertial>` is removed (e.g. merged into another link's new value).
  std::set<std::string> removed_inertials;
  /// Set: the model's effects replace the file's (urdf_model.hpp, the model file): <dynamics
  /// damping friction> of every moving joint and one <inertial_effects> element.
  std::optional<std::vector<ModelEffect>> effects;
  /// Set: one <inertial_priors> (urdf_model.hpp) recording these link priors replaces the file's
  /// (none written if empty): link name -> pi about its frame origin in its axes.
  std::optional<std::map<std::string, InertialParams>> priors;
  /// A comment to place inside an element: a link name ("thigh") or an effect ("payload@tool0").
  std::map<std::string, std::string> notes;
  /// What the top comment says about where the values come from (e.g. "identified from run1.csv").
  std::string origin;
};

/// Reads the URDF at in_path and writes it to out_path with `changes`, keeping everything else.
/// The file is written to a temporary file in the same folder and renamed over out_path, so a
/// crash or signal never leaves half a file. @throws UrdfError as WriteUrdfWithInertias, and for an
/// effect on an unknown joint or with a non-finite coefficient.
void WriteUrdfModel(const std::string& in_path, const std::string& out_path, const UrdfModelChanges& changes);

/// Reads the URDF at in_path and writes it to out_path (which may be the same file) with:
/// - new_inertias: link name -> pi about that link's frame origin in link axes. Written as a fresh
///   `<inertial>` (replacing the link's one, in place, or added as its first element): the mass,
///   `<origin xyz="COM" rpy="0 0 0">` and the inertia tensor about the COM in link axes (ixy the
///   (0,1) entry). A body of zero mass is written with its COM at the origin.
/// - removed_inertials: links whose `<inertial>` is removed (e.g. their inertia was merged into
///   another link's new value); a link without one is fine.
/// - dynamics: joint name -> `<dynamics damping friction>` set (the element created or its two
///   attributes replaced).
/// A comment at the top of the document says the file was written by inertial and what changed.
/// @throws UrdfError (message starting with the path concerned) if in_path cannot be read or is not
/// XML with a <robot> root, out_path cannot be written, a link or joint name is unknown, a link is
/// both given a new inertia and removed, or a number is not finite.
void WriteUrdfWithInertias(const std::string& in_path, const std::string& out_path,
                           const std::map<std::string, InertialParams>& new_inertias,
                           const std::set<std::string>& removed_inertials,
                           const std::map<std::string, JointDynamics>& dynamics);

}  // namespace inertial
