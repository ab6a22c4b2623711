// The shared properties of parameterization.hpp (parameterization_tester.hpp) for every map.
#include "inertial/inertia/parameterization.hpp"

#include "inertial/inertia/eigenvalue_parameterization.hpp"
#include "inertial/inertia/exponential_parameterization.hpp"
#include "inertial/inertia/linear_parameterization.hpp"
#include "inertial/inertia/log_cholesky.hpp"
#include "inertial/inertia/positive_eigenvalue_parameterization.hpp"
#include "parameterization_tester.hpp"

namespace inertial::testing {
namespace {

struct Linear {
  static LinearParameterization Make() { return {}; }
  static constexpr bool kConsistent = false;
  static constexpr bool kToleratesRounding = false;
};
struct Eigenvalue {
  static EigenvalueParameterization Make() { return {}; }
  static constexpr bool kConsistent = true;
  static constexpr bool kToleratesRounding = false;
};
struct PositiveEigenvalue {
  static PositiveEigenvalueParameterization Make() { return {}; }
  static constexpr bool kConsistent = true;
  static constexpr bool kToleratesRounding = false;
};
struct Exponential {
  static ExponentialParameterization Make() { return {}; }
  static constexpr bool kConsistent = true;
  static constexpr bool kToleratesRounding = false;
};
struct LogCholesky {
  static LogCholeskyParameterization Make() { return {}; }
  static constexpr bool kConsistent = true;
  static constexpr bool kToleratesRounding = true;
};
// Relative to a reference body (eq. 11), as the identification uses it.
struct LogCholeskyRelative {
  static LogCholeskyParameterization Make() {
    return LogCholeskyParameterization(SolidBox(2.0, 0.3, 0.2, 0.1, Pose{Matrix3::Identity(), Vector3(0.1, 0, -0.05)}));
  }
  static constexpr bool kConsistent = true;
  static constexpr bool kToleratesRounding = true;
};

using Maps = ::testing::Types<Linear, Eigenvalue, PositiveEigenvalue, Exponential, LogCholesky, LogCholeskyRelative>;
INSTANTIATE_TYPED_TEST_SUITE_P(Every, ParameterizationTester, Maps);

// CTest registers the tests it finds in this file (gtest_add_tests, tests/CMakeLists.txt), not in
// the header that defines them; one entry per test of the tester, each running every map:
//   TYPED_TEST_P(ParameterizationTester, JacobianMatchesCentralDifferences)
//   TYPED_TEST_P(ParameterizationTester, RoundTripPiXPi)
//   TYPED_TEST_P(ParameterizationTester, RefusesBodiesOutsideItsImageAndLeavesXUntouched)

}  // namespace
}  // namespace inertial::testing
