// Google Benchmark: the log-Cholesky map and its inverse (issue: theta -> pi, with Jacobian, pi -> theta).
#include <benchmark/benchmark.h>

#include <random>

#include "inertial/inertia/eigenvalue_parameterization.hpp"
#include "inertial/inertia/exponential_parameterization.hpp"
#include "inertial/inertia/log_cholesky.hpp"

namespace inertial {
namespace {

// A fixed pool of seeded random theta, cycled through so the work is not constant-folded.
const std::vector<Vector10>& ThetaPool() {
  static const std::vector<Vector10> pool = [] {
    std::mt19937 gen(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<Vector10> v(256);
    for (Vector10& t : v)
      for (int i = 0; i < 10; ++i) t[i] = u(gen);
    return v;
  }();
  return pool;
}

void BM_LogCholeskyThetaToPi(benchmark::State& state) {
  const auto& pool = ThetaPool();
  std::size_t i = 0;
  for (auto _ : state) {
    Vector10 pi = PiFromLogCholesky(pool[i++ & 255]);
    benchmark::DoNotOptimize(pi);
  }
}
BENCHMARK(BM_LogCholeskyThetaToPi);

void BM_LogCholeskyThetaToPiWithJacobian(benchmark::State& state) {
  const auto& pool = ThetaPool();
  std::size_t i = 0;
  Matrix10 J;
  for (auto _ : state) {
    Vector10 pi = PiFromLogCholesky(pool[i++ & 255], &J);
    benchmark::DoNotOptimize(pi);
    benchmark::DoNotOptimize(J);
  }
}
BENCHMARK(BM_LogCholeskyThetaToPiWithJacobian);

void BM_LogCholeskyPiToTheta(benchmark::State& state) {
  const LogCholeskyParameterization lc;
  std::vector<Vector10> pis;
  for (const Vector10& t : ThetaPool()) pis.push_back(lc.ToPi(t));
  std::size_t i = 0;
  Vector10 theta;
  for (auto _ : state) {
    bool ok = lc.FromPi(pis[i++ & 255], &theta);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(theta);
  }
}
BENCHMARK(BM_LogCholeskyPiToTheta);

// Relative to a prior (eq. 11), general path.
void BM_LogCholeskyRelativeThetaToPiWithJacobian(benchmark::State& state) {
  const LogCholeskyParameterization lc(InertialParams::FromPseudoInertia(Matrix4(Vector4(0.2, 0.3, 0.1, 1.5).asDiagonal())));
  const auto& pool = ThetaPool();
  std::size_t i = 0;
  Matrix10 J;
  for (auto _ : state) {
    Vector10 pi = lc.ToPi(pool[i++ & 255], &J);
    benchmark::DoNotOptimize(pi);
    benchmark::DoNotOptimize(J);
  }
}
BENCHMARK(BM_LogCholeskyRelativeThetaToPiWithJacobian);

// The other parameterizations, for comparison (map with Jacobian).
template <typename P>
void BM_MapWithJacobian(benchmark::State& state) {
  const P p;
  const auto& pool = ThetaPool();
  std::size_t i = 0;
  Matrix10 J;
  for (auto _ : state) {
    Vector10 x = pool[i++ & 255];
    x[0] = 0.5 + 0.25 * x[0];  // eigenvalue map: keep m > 0
    Vector10 pi = p.ToPi(x, &J);
    benchmark::DoNotOptimize(pi);
    benchmark::DoNotOptimize(J);
  }
}
BENCHMARK(BM_MapWithJacobian<EigenvalueParameterization>)->Name("BM_EigenvalueThetaToPiWithJacobian");
BENCHMARK(BM_MapWithJacobian<ExponentialParameterization>)->Name("BM_ExponentialThetaToPiWithJacobian");

}  // namespace
}  // namespace inertial
