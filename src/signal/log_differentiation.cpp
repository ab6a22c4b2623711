#include "inertial/signal/log_differentiation.hpp"

#include <stdexcept>
#include <string>

namespace inertial {

void DeriveFromPositions(JointSamples* log, bool velocities, bool accelerations, const SavitzkyGolayOptions& options) {
  if (!velocities && !accelerations) return;
  SavitzkyGolayResult sg;
  try {
    sg = SavitzkyGolay(log->t, log->q, options);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("cannot derive ") + (velocities ? "velocities" : "accelerations") +
                                " from q: " + e.what());
  }
  for (Eigen::Index i = 0; i < log->q.rows(); ++i) {
    const bool qd_ok = !velocities || sg.first.row(i).allFinite();
    if (!qd_ok || (accelerations && !sg.second.row(i).allFinite())) {
      throw std::invalid_argument(std::string("the ") + (qd_ok ? "accelerations" : "velocities") +
                                  " derived from q are not finite at sample " + std::to_string(i) + " (t = " +
                                  std::to_string(log->t[i]) + " s): q too large for its time steps");
    }
  }
  if (velocities) log->qd = std::move(sg.first);
  if (accelerations) log->qdd = std::move(sg.second);
}

}  // namespace inertial
