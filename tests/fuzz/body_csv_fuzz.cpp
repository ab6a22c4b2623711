// Fuzz harness: a single-body CSV (body_csv.hpp) as `diagnose --body` and `validate --body` read
// it, then the glitch screen and the online body estimator on what was accepted.
#include <sstream>

#include "fuzz_support.hpp"
#include "inertial/estimation/online/online_body_estimator.hpp"
#include "inertial/estimation/batch/robust_identification.hpp"
#include "inertial/signal/sample_glitches.hpp"
#include "inertial/formats/body_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace inertial;
  std::istringstream in(fuzz::Text(data, size));
  BodyLog log;
  try {
    log = ParseBodyCsv(in, "fuzz.csv");
  } catch (const CsvError&) {
    return 0;
  }
  const std::size_t N = log.samples.size();
  if (N < 2) fuzz::Fail("a log of fewer than 2 samples was accepted");
  if (!log.gravity.empty() && log.gravity.size() != N) fuzz::Fail("gravity and samples disagree");
  for (std::size_t i = 0; i < N; ++i) {
    if (!log.samples[i].twist.allFinite() || !log.samples[i].wrench.allFinite()) fuzz::Fail("a value is not finite");
    if (i > 0 && !(log.samples[i].t > log.samples[i - 1].t)) fuzz::Fail("time does not increase");
  }
  const GlitchScreen screen = FindGlitches(BodySignals(log));
  const BodyLog kept = SelectBodySamples(log, RowsExcept(static_cast<int>(N), screen.Rows()));
  OnlineBodyEstimator e(fuzz::UnitBody());
  for (std::size_t i = 0; i < std::min<std::size_t>(kept.samples.size(), 32); ++i) {
    BodySample s;
    s.t = kept.samples[i].t;
    s.twist = kept.samples[i].twist;
    s.wrench = kept.samples[i].wrench;
    if (!kept.gravity.empty()) s.gravity = kept.gravity[i];
    e.Update(s);
  }
  const InertialParams body = e.Body();
  if (!body.vector().allFinite()) fuzz::Fail("the body estimate is not finite");
  if (!CheckConsistency(body).fully_consistent()) fuzz::Fail("the body estimate is not consistent");
  return 0;
}
