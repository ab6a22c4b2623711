// Google Benchmark: one single-body Gauss-Newton (Levenberg-Marquardt) iteration on 63 samples
// (62 midpoint residuals of eq. 13, 372 rows), per parameterization, on a Section VI body.
#include <benchmark/benchmark.h>

#include "inertial/estimation/batch/levenberg_marquardt.hpp"
#include "inertial/estimation/batch/linear_least_squares.hpp"
#include "inertial/inertia/eigenvalue_parameterization.hpp"
#include "inertial/inertia/exponential_parameterization.hpp"
#include "inertial/inertia/linear_parameterization.hpp"
#include "inertial/inertia/log_cholesky.hpp"
#include "inertial/study/paper_study.hpp"

namespace inertial {
namespace {

const LinearRegression& StudyRegression() {
  static const LinearRegression reg = [] {
    const StudyOptions options;
    const InertialParams body = SampleTableIBody(1, 0);
    return BuildMidpointRegression(SimulateStudyBody(body, 1, 0, options));
  }();
  return reg;
}

template <typename P>
void BM_OneIteration(benchmark::State& state) {
  const P p;
  const LinearRegression& reg = StudyRegression();
  Vector10 pi0;
  pi0 << 1, 0, 0, 0, 1, 1, 1, 0, 0, 0;
  Vector10 x0;
  p.FromPi(pi0, &x0);
  LevenbergMarquardtOptions one;
  one.max_iterations = 1;
  for (auto _ : state) {
    LevenbergMarquardtResult r = FitLevenbergMarquardt(p, reg, x0, one);
    benchmark::DoNotOptimize(r);
  }
  state.counters["rows"] = static_cast<double>(reg.A.rows());
}
BENCHMARK(BM_OneIteration<LinearParameterization>)->Name("BM_GaussNewtonIteration63Samples/linear");
BENCHMARK(BM_OneIteration<EigenvalueParameterization>)->Name("BM_GaussNewtonIteration63Samples/eigenvalue");
BENCHMARK(BM_OneIteration<ExponentialParameterization>)->Name("BM_GaussNewtonIteration63Samples/exponential");
BENCHMARK(BM_OneIteration<LogCholeskyParameterization>)->Name("BM_GaussNewtonIteration63Samples/log_cholesky");

void BM_LinearLeastSquares63Samples(benchmark::State& state) {
  const LinearRegression& reg = StudyRegression();
  for (auto _ : state) {
    LinearLeastSquaresResult r = SolveLinearLeastSquares(reg);
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_LinearLeastSquares63Samples);

void BM_BuildMidpointRegression63Samples(benchmark::State& state) {
  const StudyOptions options;
  const std::vector<TwistWrenchSample> samples = SimulateStudyBody(SampleTableIBody(1, 0), 1, 0, options);
  for (auto _ : state) {
    LinearRegression reg = BuildMidpointRegression(samples);
    benchmark::DoNotOptimize(reg);
  }
}
BENCHMARK(BM_BuildMidpointRegression63Samples);

}  // namespace
}  // namespace inertial
