#include "inertial/report/online_estimate_text.hpp"

#include <optional>
#include <sstream>

#include "inertial/report/uncertainty_report.hpp"

namespace inertial {

std::string OnlineEstimateText(const OnlineJointEstimator& estimator) {
  const std::optional<ModelUncertainty> uncertainty = FromOnlineEstimator(estimator);
  const auto& bodies = estimator.model().bodies();
  std::ostringstream out;
  out << "final estimate" << (uncertainty ? " (+- one standard deviation " + uncertainty->source + ")" : "") << ":\n";
  for (int e = 0; e < static_cast<int>(bodies.size()); ++e) {
    const InertialParams b = estimator.Body(e);
    if (uncertainty) {
      const BodyHeldByPrior* held = uncertainty->held.empty() ? nullptr : &uncertainty->held[e];
      out << "  " << bodies[e].name << ": " << BodyUncertaintyText(b, uncertainty->bodies[e], held) << "\n";
    } else {
      out << "  " << bodies[e].name << ": mass " << b.mass() << " kg, COM [" << b.com().transpose() << "] m\n";
    }
  }
  return out.str();
}

}  // namespace inertial
