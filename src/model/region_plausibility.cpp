#include "inertial/model/region_plausibility.hpp"

#include <stdexcept>

#include "inertial/model/number_text.hpp"

namespace inertial {

RegionPlausibility JudgeAgainstRegion(const InertialParams& body, const InertialParams& prior, const BodyRegion& region,
                                      bool drawn_prior) {
  if (!(prior.mass() > 0.0)) throw std::invalid_argument("plausibility: the prior's mass is not positive");
  RegionPlausibility p;
  const double m = body.mass();
  p.slack = region.ellipsoid.Slack(body);
  p.density = m / region.ellipsoid.Volume();
  p.mass_ratio = m / prior.mass();
  p.mass_compared = drawn_prior;
  p.inside = p.slack >= 0.0 && m <= region.max_mass;
  p.on_edge = p.inside && p.slack < kRegionEdgeSlack;
  const bool mass_ok =
      !drawn_prior || (p.mass_ratio <= kImplausibleMassRatio && p.mass_ratio >= 1.0 / kImplausibleMassRatio);
  p.plausible = p.inside && mass_ok;
  std::string words;
  const auto add = [&words](const std::string& s) { words += (words.empty() ? "" : "; ") + s; };
  const std::string region_name = std::string("its region (") + ToString(region.source) + ")";
  if (p.slack < 0.0) add("its mass lies outside " + region_name + ", where the link is not");
  if (m > region.max_mass) {
    add("denser than steel throughout " + region_name + " (" + FormatNumber(p.density, 3) + " kg/m^3)");
  }
  if (!mass_ok) {
    add(FormatNumber(m, 4) + " kg is " + FormatNumber(p.mass_ratio, 3) + " times the URDF's " +
        FormatNumber(prior.mass(), 4) + " kg (a CAD mass is off by tens of per cent, not a factor of " +
        FormatNumber(kImplausibleMassRatio, 2) + "): the fit may be explaining friction, a payload or an offset with mass");
  }
  if (p.on_edge) {
    add("held on the edge of " + region_name +
        ": the data push its mass outward, so the model likely lacks an effect (friction, a payload, an offset)");
  }
  p.words = words;
  return p;
}

bool HasDrawnPrior(const EstimatedBody& body) {
  return body.region && body.region->source != RegionSource::kPayloadReach;
}

std::optional<RegionPlausibility> JudgeEstimatedBody(const EstimatedBody& body, const Vector10& theta) {
  if (!body.region || !(body.prior.mass() > 0.0)) return std::nullopt;
  return JudgeAgainstRegion(InertialParams::FromVector(body.map.ToPi(theta)), body.prior, *body.region,
                            HasDrawnPrior(body));
}

std::optional<RegionPlausibility> JudgeReportedBody(const EstimatedBody& body, const InertialParams& in_report_frame) {
  if (!body.region || !(body.prior.mass() > 0.0)) return std::nullopt;
  // The report frame is posed in the tree body's frame: x_tree = R x_report + p.
  const InertialParams in_tree = in_report_frame.Transformed(body.report_frame.R_AB, body.report_frame.p_AB);
  return JudgeAgainstRegion(in_tree, body.prior, *body.region, HasDrawnPrior(body));
}

}  // namespace inertial
