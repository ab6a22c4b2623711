// Data preparation costs: reading a 30 s, 1 kHz, 7-joint CSV log (29 columns of 17-digit numbers)
// and Savitzky-Golay differentiation (order 4, 100 ms window) of its 7 position columns.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "inertial/signal/savitzky_golay.hpp"
#include "inertial/formats/joint_csv.hpp"

namespace inertial {
namespace {

JointSamples Log(int rows) {
  JointSamples s;
  for (int j = 0; j < 7; ++j) s.joint_names.push_back("j" + std::to_string(j));
  s.t = Eigen::VectorXd::LinSpaced(rows, 0.0, 1e-3 * (rows - 1));
  s.q.resize(rows, 7);
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < 7; ++j) s.q(i, j) = std::sin(0.7 * (j + 1) * s.t[i]) + 1e-3 * std::cos(91.0 * i);
  }
  s.qd = 1.1 * s.q;
  s.qdd = 2.3 * s.q;
  s.tau = -0.7 * s.q;
  return s;
}

void ReadCsv30s(benchmark::State& state) {
  const JointSamples s = Log(30000);
  const std::string path = (std::filesystem::temp_directory_path() / "inertial_bench_30s.csv").string();
  WriteJointCsv(path, s);
  for (auto _ : state) benchmark::DoNotOptimize(ReadJointCsv(path, s.joint_names).q.data());
  std::remove(path.c_str());
}
BENCHMARK(ReadCsv30s)->Unit(benchmark::kMillisecond);

void SavitzkyGolay30s(benchmark::State& state) {
  const JointSamples s = Log(30000);
  for (auto _ : state) benchmark::DoNotOptimize(SavitzkyGolay(s.t, s.q).second.data());
}
BENCHMARK(SavitzkyGolay30s)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace inertial
