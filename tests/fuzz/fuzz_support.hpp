// What the fuzz harnesses share: the bundled leg as the model inputs are fed to, and checks that
// abort (a finding, as a crash is) when an input that was accepted left an estimate that is not
// finite or not physically consistent. Each harness catches only the exceptions its input's
// reader documents; anything else escaping is a finding too.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>

#include "inertial/estimation/online/online_joint_estimator.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inertial/formats/model_file.hpp"
#include "inertial/formats/urdf_model.hpp"
#include "source_dir.hpp"

namespace inertial::fuzz {

/// A file of this process for harnesses whose reader takes a path: in /dev/shm when there is one
/// (memory, so that a million inputs do not wear a disk), else /tmp.
inline std::string TempPath(const std::string& extension) {
  static const std::string dir = ::access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
  return dir + "/inertial-fuzz-" + std::to_string(::getpid()) + "." + extension;
}

inline std::string Text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

[[noreturn]] inline void Fail(const std::string& what) {
  std::fprintf(stderr, "fuzz finding: %s\n", what.c_str());
  std::abort();
}

/// The bundled 3-DOF leg (examples/leg3.urdf; joints abad, hip, knee), loaded once.
inline const RobotModel& Leg() {
  static const RobotModel robot = LoadUrdf(std::string(InertialSourceDir()) + "/examples/leg3.urdf");
  return robot;
}

inline const RobotDynamics& LegDynamics() {
  static const RobotDynamics model = MakeRobotDynamics(Leg(), {});
  return model;
}

/// The prior of the single-body harnesses: 1 kg at the origin, unit second moments.
inline InertialParams UnitBody() {
  return InertialParams::FromVector((Vector10() << 1, 0, 0, 0, 1, 1, 1, 0, 0, 0).finished());
}

/// Every body of the estimate finite and physically consistent (the estimator's promise), by the
/// definition every tool uses (CheckConsistency's default: margins
/// above 1e-12 of the body's scale, rounding's reach). The harnesses once asked 1e-9, a thousand times
/// more than the product promises; the larger inputs of issue 35 drove the leg's estimate on garbage
/// logs to a body of 1e-8 kg m^2 whose J had a margin of 2.4e-11 of its scale, consistent, and found it.
inline void RequireConsistent(const OnlineJointEstimator& e, const char* after) {
  if (!e.coefficients().allFinite()) Fail(std::string("a coefficient is not finite after ") + after);
  for (int b = 0; b < static_cast<int>(e.model().bodies().size()); ++b) {
    const InertialParams body = e.Body(b);
    if (!body.vector().allFinite()) Fail(std::string("a body is not finite after ") + after);
    const ConsistencyReport r = CheckConsistency(body);
    if (!r.fully_consistent()) Fail(std::string("a body is not consistent after ") + after + ": " + r.reason);
  }
}

}  // namespace inertial::fuzz
