// Fuzz harness: a joint CSV (joint_csv.hpp) as `identify`, `diagnose` and `replay` read it, for the
// leg's joints; what is accepted must be a valid log, and must keep the online estimate consistent.
// Byte 0 chooses the options (bit 0: --skip-bad-rows, bit 1: time stamps in ms), the rest is the file.
#include <sstream>

#include "fuzz_support.hpp"
#include "inertial/formats/joint_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace inertial;
  if (size < 1) return 0;
  JointCsvOptions options;
  options.skip_bad_rows = (data[0] & 1) != 0;
  options.time_scale = (data[0] & 2) != 0 ? 1e-3 : 0.0;
  std::istringstream in(fuzz::Text(data + 1, size - 1));
  JointSamples log;
  try {
    log = ParseJointLog(in, "fuzz.csv", fuzz::Leg().dof_names, options);
  } catch (const CsvError&) {
    return 0;
  }
  const int N = log.size();
  if (N < 2) fuzz::Fail("a log of fewer than 2 samples was accepted");
  for (const Eigen::MatrixXd* m : {&log.q, &log.qd, &log.qdd, &log.tau}) {
    if (m->rows() != N || m->cols() != 3) fuzz::Fail("sizes disagree");
    if (!m->allFinite()) fuzz::Fail("a value is not finite");
  }
  for (int i = 1; i < N; ++i) {
    if (!(log.t[i] > log.t[i - 1])) fuzz::Fail("time does not increase");
  }
  OnlineJointEstimator e(fuzz::LegDynamics(), Eigen::VectorXd::Zero(fuzz::LegDynamics().num_parameters()));
  JointSample s;
  for (int i = 0; i < std::min(N, 32); ++i) {  // enough to reach the estimator; more only slows fuzzing
    CopySample(log, i, &s);
    e.Update(s);
  }
  fuzz::RequireConsistent(e, "a joint CSV");
  return 0;
}
