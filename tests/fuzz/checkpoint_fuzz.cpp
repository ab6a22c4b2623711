// Fuzz harness: an inertiald checkpoint (estimator_state_file.hpp) read and restored into the leg's
// Gauss-Newton estimator as the daemon does at start; a state that is restored must leave a finite,
// consistent estimate that later samples keep so.
#include "fuzz_support.hpp"
#include "inertial/formats/estimator_state_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace inertial;
  EstimatorState state;
  std::string description;
  try {
    state = EstimatorStateFromJson(fuzz::Text(data, size), "fuzz.json", &description);
  } catch (const StateFileError&) {
    return 0;
  }
  OnlineJointEstimator e(fuzz::LegDynamics(), Eigen::VectorXd::Zero(fuzz::LegDynamics().num_parameters()));
  std::string why;
  if (!e.estimator().Restore(state, &why)) {
    if (why.empty()) fuzz::Fail("a state refused without a reason");
    fuzz::RequireConsistent(e, "a refused state");
    return 0;
  }
  fuzz::RequireConsistent(e, "a restored state");
  JointSample s;
  s.q = s.qd = s.qdd = Eigen::VectorXd::Constant(3, 0.2);
  s.tau = Eigen::VectorXd::Constant(3, 1.0);
  for (int k = 1; k <= 5; ++k) {
    s.t = state.last_time + 0.001 * k;
    e.Update(s);
  }
  fuzz::RequireConsistent(e, "samples after a restored state");
  return 0;
}
