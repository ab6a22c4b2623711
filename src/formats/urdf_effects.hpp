/// @file urdf_effects.hpp
/// (Private to the io layer.) The model's effects in a URDF document: standard `<dynamics damping
/// friction>` of moving joints and the one extension element `<inertial_effects>` (format in
/// urdf_model.hpp), read strictly and written back.
#pragma once

#include <tinyxml2.h>

#include <map>
#include <string>
#include <vector>

#include "inertial/inertia/inertial_params.hpp"
#include "inertial/model/joint_effect.hpp"

namespace inertial::detail {

/// The name of the extension element (a child of <robot>).
inline constexpr const char* kEffectsElement = "inertial_effects";

/// Effects of the document (robot: its <robot> element): every moving joint's non-zero <dynamics>
/// damping (viscous) and friction (Coulomb), and everything <inertial_effects> declares.
/// *declared gets one flag per effect: stated in <inertial_effects> (not only a <dynamics> value).
/// @throws UrdfError naming source, element and attribute for a number that is not a finite
/// decimal, a negative coefficient, an unknown element or joint, a duplicate, a missing attribute.
std::vector<ModelEffect> ReadModelEffects(const tinyxml2::XMLElement& robot, const std::string& source,
                                          const std::vector<std::string>& moving_joints, std::vector<bool>* declared);

/// Makes the document state exactly `effects`: <dynamics damping friction> of every moving joint
/// set to its viscous and Coulomb coefficients (0 where the model has none and the joint had a
/// <dynamics>), and one <inertial_effects> replacing any earlier one. notes: an effect's name
/// ("coulomb@knee", "payload@tool0") -> a comment written inside its element.
/// @throws UrdfError (path) for an unknown joint or a non-finite number.
void WriteModelEffects(tinyxml2::XMLDocument& doc, tinyxml2::XMLElement* robot, const std::vector<ModelEffect>& effects,
                       const std::map<std::string, std::string>& notes, const std::string& path);

/// The name of the element recording each link's prior (a child of <robot>; urdf_model.hpp).
inline constexpr const char* kPriorsElement = "inertial_priors";

/// The priors <inertial_priors> records (link -> pi about the link's frame origin), empty without
/// the element. `body_links`: the links a prior may be given for (those that start a moving body).
/// @throws UrdfError naming source and element for another version, an unknown child or attribute,
/// a link that does not start a moving body, a link given twice, an <inertial> that is missing, not
/// finite or not fully physically consistent.
std::map<std::string, InertialParams> ReadRecordedPriors(const tinyxml2::XMLElement& robot, const std::string& source,
                                                         const std::vector<std::string>& body_links);

/// Makes the document record exactly `priors` (one <inertial_priors> replacing any earlier one;
/// none if empty). @throws UrdfError (path) for a prior that is not finite.
void WriteRecordedPriors(tinyxml2::XMLDocument& doc, tinyxml2::XMLElement* robot,
                         const std::map<std::string, InertialParams>& priors, const std::string& path);

/// `<inertial>` content (origin at the COM with rpy 0, mass, inertia about the COM) of pi.
void FillInertialElement(tinyxml2::XMLDocument& doc, tinyxml2::XMLElement* inertial, const InertialParams& pi);
/// The inverse: pi about the element's frame origin. `where` starts error messages.
/// @throws UrdfError for a missing <mass> or <inertia>, a number that is not finite, a body that is not
/// fully physically consistent.
InertialParams ReadInertialElement(const tinyxml2::XMLElement& inertial, const std::string& where);

/// XML comments may not contain "--".
std::string CommentSafe(std::string text);

}  // namespace inertial::detail
