/// @file uncertainty_report.hpp
/// One presentation of how sure each number is, for batch fits (fit_uncertainty.hpp: the fit's
/// curvature, the noise from the residual) and online estimates (the estimator's covariance,
/// covariance_uncertainty.hpp; both compute the numbers, this file only presents them): standard
/// deviations of mass, COM and the inertia about the COM of every body, and of every effect
/// coefficient, with the quantities the prior rather than the data determines labelled "held by the
/// prior". As text, as JSON, and as the comments a model file carries (model_file.hpp). Units: kg,
/// m, kg m^2 (the effects' own units).
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "inertial/estimation/fit_uncertainty.hpp"
#include "inertial/estimation/online/online_joint_estimator.hpp"
#include "inertial/formats/model_file.hpp"

namespace inertial {

/// Standard deviations of a model's numbers (per estimated body and per effect term of the model).
struct ModelUncertainty {
  std::vector<BodyUncertainty> bodies;
  std::vector<BodyHeldByPrior> held;             ///< empty: no labels (the Kalman and RLS estimators)
  std::vector<std::vector<double>> effects;      ///< per effect term, per EffectValues entry
  std::string source;                            ///< how they were obtained, one phrase
};

/// From a batch fit's uncertainty.
ModelUncertainty FromFit(const FitUncertainty& fit);
/// gauss_newton (the online fit): FromFit of its statistics at its solution, the batch's own
/// uncertainty with "held by the prior"; nullopt before it has residual degrees of freedom.
/// The other estimators: from their covariance; nullopt for those that keep none (gradient law).
/// Linear RLS: per tree body (payloads inside their links'), effects from w's covariance.
std::optional<ModelUncertainty> FromOnlineEstimator(const OnlineJointEstimator& estimator);

/// "mass 3.9 +- 1.2 kg (held by the prior), COM [..] +- [..] m, inertia about COM [Ixx Iyy Izz Ixy
/// Iyz Ixz] +- [..] kg m^2" (held quantities named).
std::string BodyUncertaintyText(const InertialParams& body, const BodyUncertainty& u, const BodyHeldByPrior* held);
/// {"mass_std", "com_std" [3], "inertia_about_com_std" [6], "held_by_prior": ["mass", "com.x", ...,
/// "Ixx", ...]} (standard deviations of +infinity as the string "inf").
nlohmann::json BodyUncertaintyJson(const BodyUncertainty& u, const BodyHeldByPrior* held);
/// The names of the held quantities ("mass", "com.y", "Izz", ...).
std::vector<std::string> HeldQuantities(const BodyHeldByPrior& held);

/// Comments for a model file: body name or effect name ("coulomb@knee") -> its standard deviations.
std::map<std::string, std::string> UncertaintyNotes(const RobotDynamics& model, const ModelSnapshot& snapshot,
                                                    const ModelUncertainty& u);

/// SnapshotOf(estimator) (model_file.hpp) with the standard deviations of its covariance as notes.
/// @throws as SnapshotOf.
ModelSnapshot SnapshotWithUncertainty(const OnlineJointEstimator& estimator);

}  // namespace inertial
