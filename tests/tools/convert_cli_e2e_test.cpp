// End-to-end tests of the `inertial` command-line tool: run the built binary (INERTIAL_CLI) as a
// subprocess, and check its output against the library computed in this process.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inertial/inertia/inertial_params.hpp"
#include "inertial/inertia/log_cholesky.hpp"
#include "inertial/model/number_text.hpp"
#include "inertial/study/paper_study.hpp"
#include "cli_support.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

namespace fs = std::filesystem;
using testing::Rng;

// Exit codes of tools/inertial/exit_codes.hpp, restated: the test checks the documented contract.
constexpr int kExitOk = 0;
constexpr int kExitUsage = 2;
constexpr int kExitInvalidValue = 3;
constexpr int kExitInconsistentBody = 4;
constexpr int kExitIoError = 5;

// ---------------------------------------------------------------------------------------------
// Subprocess helpers.

using testing::CliRun;
using testing::Contains;
using testing::Describe;
using testing::ReadFile;
using testing::RunCli;
using testing::UniqueTempPath;

// Shortest text that reads back to exactly x.
std::string Num(double x) { return FormatNumberExact(x); }

template <typename Derived>
std::vector<std::string> Args(const Eigen::MatrixBase<Derived>& v) {
  std::vector<std::string> out;
  for (Eigen::Index i = 0; i < v.size(); ++i) out.push_back(Num(v(i)));
  return out;
}

// Row-major text of a matrix, entries separated by ", " and rows by newlines (the stdin form).
template <typename Derived>
std::string RowsText(const Eigen::MatrixBase<Derived>& M) {
  std::string s;
  for (Eigen::Index i = 0; i < M.rows(); ++i) {
    for (Eigen::Index j = 0; j < M.cols(); ++j) s += Num(M(i, j)) + (j + 1 < M.cols() ? ", " : "\n");
  }
  return s;
}

std::vector<std::string> Concat(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

nlohmann::json ParseJson(const CliRun& r) {
  try {
    return nlohmann::json::parse(r.out);
  } catch (const std::exception& e) {
    ADD_FAILURE() << "stdout is not JSON (" << e.what() << ")\n" << Describe(r);
    return nlohmann::json();
  }
}

Vector10 JsonVector10(const nlohmann::json& j, const std::string& key) {
  Vector10 v = Vector10::Constant(std::nan(""));
  if (!j.contains(key) || !j[key].is_array() || j[key].size() != 10) {
    ADD_FAILURE() << "no 10-number array '" << key << "' in " << j.dump();
    return v;
  }
  for (int i = 0; i < 10; ++i) v[i] = j[key][i].get<double>();
  return v;
}

template <int R, int C>
Eigen::Matrix<double, R, C> JsonMatrix(const nlohmann::json& j, const std::string& key) {
  Eigen::Matrix<double, R, C> M = Eigen::Matrix<double, R, C>::Constant(std::nan(""));
  if (!j.contains(key) || !j[key].is_array() || j[key].size() != static_cast<std::size_t>(R)) {
    ADD_FAILURE() << "no " << R << "-row array '" << key << "' in " << j.dump();
    return M;
  }
  for (int i = 0; i < R; ++i) {
    if (j[key][i].size() != static_cast<std::size_t>(C)) {
      ADD_FAILURE() << "row " << i << " of '" << key << "' does not have " << C << " entries";
      return M;
    }
    for (int k = 0; k < C; ++k) M(i, k) = j[key][i][k].get<double>();
  }
  return M;
}

// The plain-text output "<name>: v1 v2 ..." (matrices continue on further lines).
std::vector<double> ParseText(const CliRun& r, const std::string& name) {
  std::vector<double> values;
  if (r.out.rfind(name + ":", 0) != 0) {
    ADD_FAILURE() << "stdout does not start with '" << name << ":'\n" << Describe(r);
    return values;
  }
  std::istringstream in(r.out.substr(name.size() + 1));
  std::string token;
  while (in >> token) values.push_back(std::strtod(token.c_str(), nullptr));
  return values;
}

// Entry-wise |a - b| <= tol * max(1, max |b|).
template <typename A, typename B>
::testing::AssertionResult Near(const A& a, const B& b, double tol) {
  const double err = testing::RelativeError(a, b);
  if (err <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "relative error " << err << " > " << tol << "\n  got      " << a.transpose()
                                       << "\n  expected " << b.transpose();
}

// pi of a box of mass m and sides a, b, c whose centroid sits at p with axes along the frame's:
// textbook, independent of the library (I_Bo = I_com + m (|p|^2 1 - p p^T)).
Vector10 TextbookBoxPi(double m, double a, double b, double c, const Vector3& p) {
  Matrix3 I = Vector3(m / 12 * (b * b + c * c), m / 12 * (a * a + c * c), m / 12 * (a * a + b * b)).asDiagonal();
  I += m * (p.squaredNorm() * Matrix3::Identity() - p * p.transpose());
  Vector10 pi;
  pi << m, m * p.x(), m * p.y(), m * p.z(), I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(1, 2), I(0, 2);
  return pi;
}

Pose RandomPose(Rng& rng) {
  const Pose pose = rng.RandomPose<Pose>(0.8);
  return pose;
}

class ConvertCli : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::getenv("INERTIAL_CLI") == nullptr) GTEST_SKIP() << "INERTIAL_CLI (path of the inertial binary) not set";
  }
};

using StudyCli = ConvertCli;

// ---------------------------------------------------------------------------------------------
// theta <-> pi.

TEST_F(ConvertCli, ThetaToPiEqualsPiFromLogCholesky) {
  Rng rng(101);
  for (int n = 0; n < 6; ++n) {
    Vector10 theta = rng.UniformVector<10>(-1.5, 1.5);
    theta[0] = -std::abs(theta[0]);  // negative first value: must come after "--"
    const CliRun r = RunCli(Concat({"convert", "--from", "theta", "--to", "pi", "--json", "--"}, Args(theta)));
    ASSERT_EQ(r.exit_code, kExitOk) << Describe(r);
    const nlohmann::json j = ParseJson(r);
    const Vector10 pi = JsonVector10(j, "pi");
    const Vector10 expected = PiFromLogCholesky(theta);
    for (int i = 0; i < 10; ++i) {
      EXPECT_LE(std::abs(pi[i] - expected[i]), 1e-15 * std::abs(expected[i])) << "entry " << i << "\n" << Describe(r);
    }
    ASSERT_TRUE(j.contains("consistency"));
    EXPECT_TRUE(j["consistency"]["fully_consistent"].get<bool>());
    EXPECT_EQ(j["consistency"]["reason"].get<std::string>(), "");
    EXPECT_NEAR(j["consistency"]["mass"].get<double>(), std::exp(2 * theta[0]), 1e-15 * std::exp(2 * theta[0]));
  }
}

TEST_F(ConvertCli, PiToThetaOfClosedFormBodies) {
  Rng rng(102);
  const LogCholeskyParameterization lc;
  const std::vector<InertialParams> bodies = {
      SolidBox(2.5, 0.3, 0.2, 0.1, RandomPose(rng)), SolidBox(0.05, 0.01, 0.5, 0.03, RandomPose(rng)),
      SolidCylinder(1.2, 0.05, 0.6, RandomPose(rng)), SolidCylinder(7.0, 0.4, 0.02, RandomPose(rng))};
  for (const InertialParams& body : bodies) {
    const CliRun r = RunCli(Concat({"convert", "--from", "pi", "--to", "theta", "--json", "--"}, Args(body.vector())));
    ASSERT_EQ(r.exit_code, kExitOk) << Describe(r);
    const Vector10 theta = JsonVector10(ParseJson(r), "theta");
    EXPECT_TRUE(Near(theta, lc.ThetaOf(body), 1e-12));
    // And theta maps back to the body (independent of ThetaOf).
    EXPECT_TRUE(Near(PiFromLogCholesky(theta), body.vector(), 1e-12));
  }
}

// theta -> pi -> theta -> pi -> theta through the CLI: every leg keeps full double precision.
TEST_F(ConvertCli, RoundTripThroughTheCliTwice) {
  Rng rng(103);
  for (int n = 0; n < 3; ++n) {
    const Vector10 theta0 = rng.UniformVector<10>(-1.0, 1.0);
    Vector10 theta = theta0, first_pi = Vector10::Zero();
    for (int leg = 0; leg < 2; ++leg) {
      // theta -> pi as plain text (17 significant digits).
      const CliRun to_pi = RunCli(Concat({"convert", "--from", "theta", "--to", "pi", "--"}, Args(theta)));
      ASSERT_EQ(to_pi.exit_code, kExitOk) << Describe(to_pi);
      const std::vector<double> pv = ParseText(to_pi, "pi");
      ASSERT_EQ(pv.size(), 10u) << Describe(to_pi);
      const Vector10 pi = Eigen::Map<const Vector10>(pv.data());
      EXPECT_TRUE(Near(pi, PiFromLogCholesky(theta), 1e-15));
      if (leg == 0) first_pi = pi;
      else EXPECT_TRUE(Near(pi, first_pi, 1e-13));
      // pi -> theta as JSON.
      const CliRun to_theta = RunCli(Concat({"convert", "--from", "pi", "--to", "theta", "--json", "--"}, Args(pi)));
      ASSERT_EQ(to_theta.exit_code, kExitOk) << Describe(to_theta);
      theta = JsonVector10(ParseJson(to_theta), "theta");
      EXPECT_TRUE(Near(theta, theta0, 1e-12)) << "leg " << leg;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// mci, pseudo, spatial.

TEST_F(ConvertCli, MciToPiMatchesTheTextbookBox) {
  const double m = 3.0, a = 0.4, b = 0.3, c = 0.2;
  const Vector3 p(0.5, -0.25, 0.125);
  // mci: [m, c, Ixx, Iyy, Izz, Ixy, Iyz, Ixz] about the COM.
  const std::vector<std::string> mci = {Num(m), Num(p.x()), Num(p.y()), Num(p.z()), Num(m / 12 * (b * b + c * c)),
                                        Num(m / 12 * (a * a + c * c)), Num(m / 12 * (a * a + b * b)), "0", "0", "0"};
  const CliRun r = RunCli(Concat({"convert", "--from", "mci", "--to", "pi", "--json", "--"}, mci));
  ASSERT_EQ(r.exit_code, kExitOk) << Describe(r);
  EXPECT_TRUE(Near(JsonVector10(ParseJson(r), "pi"), TextbookBoxPi(m, a, b, c, p), 1e-14));
}

TEST_F(ConvertCli, MciBothWaysForARotatedBody) {
  Rng rng(104);
  const InertialParams body = SolidBox(1.7, 0.5, 0.15, 0.3, RandomPose(rng));
  const Vector3 com = body.com();
  const Matrix3 I = body.rotational_inertia_about_com();
  Vector10 mci;
  mci << body.mass(), com, I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(1, 2), I(0, 2);

  const CliRun to_mci = RunCli(Concat({"convert", "--from", "pi", "--to", "mci", "--json", "--"}, Args(body.vector())));
  ASSERT_EQ(to_mci.exit_code, kExitOk) << Describe(to_mci);
  EXPECT_TRUE(Near(JsonVector10(ParseJson(to_mci), "mci"), mci, 1e-13));

  const CliRun to_pi = RunCli(Concat({"convert", "--from", "mci", "--to", "pi", "--json", "--"}, Args(mci)));
  ASSERT_EQ(to_pi.exit_code, kExitOk) << Describe(to_pi);
  EXPECT_TRUE(Near(JsonVector10(ParseJson(to_pi), "pi"), body.vector(), 1e-13));
}

TEST_F(ConvertCli, PseudoInertiaBothWays) {
  Rng rng(105);
  const InertialParams body = SolidCylinder(0.9, 0.12, 0.45, RandomPose(rng));
  // J = [[Sigma, h], [h^T, m]] with Sigma = tr(I)/2 1 - I, built here from pi.
  const Vector10& pi = body.vector();
  Matrix3 I;
  I << pi[4], pi[7], pi[9], pi[7], pi[5], pi[8], pi[9], pi[8], pi[6];
  Matrix4 J = Matrix4::Zero();
  J.topLeftCorner<3, 3>() = 0.5 * I.trace() * Matrix3::Identity() - I;
  J.topRightCorner<3, 1>() = pi.segment<3>(1);
  J.bottomLeftCorner<1, 3>() = pi.segment<3>(1).transpose();
  J(3, 3) = pi[0];

  const CliRun to_pseudo = RunCli(Concat({"convert", "--from", "pi", "--to", "pseudo", "--json", "--"}, Args(pi)));
  ASSERT_EQ(to_pseudo.exit_code, kExitOk) << Describe(to_pseudo);
  const Matrix4 J_cli = JsonMatrix<4, 4>(ParseJson(to_pseudo), "pseudo");
  EXPECT_LT(testing::RelativeError(J_cli, J), 1e-14) << J_cli << "\nexpected\n" << J;

  // From stdin: rows on separate lines, entries separated by commas.
  const CliRun to_pi = RunCli({"convert", "--from", "pseudo", "--to", "pi", "--json"}, RowsText(J));
  ASSERT_EQ(to_pi.exit_code, kExitOk) << Describe(to_pi);
  EXPECT_TRUE(Near(JsonVector10(ParseJson(to_pi), "pi"), pi, 1e-14));
}

TEST_F(ConvertCli, SpatialInertiaBothWays) {
  Rng rng(106);
  const InertialParams body = SolidBox(4.0, 0.2, 0.6, 0.35, RandomPose(rng));
  const Vector10& pi = body.vector();
  Matrix3 I;
  I << pi[4], pi[7], pi[9], pi[7], pi[5], pi[8], pi[9], pi[8], pi[6];
  const Vector3 h = pi.segment<3>(1);
  Matrix3 Sh;  // h cross
  Sh << 0, -h.z(), h.y(), h.z(), 0, -h.x(), -h.y(), h.x(), 0;
  Matrix6 M;
  M << I, Sh, Sh.transpose(), pi[0] * Matrix3::Identity();

  const CliRun to_spatial = RunCli(Concat({"convert", "--from", "pi", "--to", "spatial", "--json", "--"}, Args(pi)));
  ASSERT_EQ(to_spatial.exit_code, kExitOk) << Describe(to_spatial);
  const Matrix6 M_cli = JsonMatrix<6, 6>(ParseJson(to_spatial), "spatial");
  EXPECT_LT(testing::RelativeError(M_cli, M), 1e-15) << M_cli << "\nexpected\n" << M;

  // From stdin, one number per line.
  std::string lines;
  for (int i = 0; i < 6; ++i)
    for (int k = 0; k < 6; ++k) lines += Num(M(i, k)) + "\n";
  const CliRun to_pi = RunCli({"convert", "--from", "spatial", "--to", "pi", "--json"}, lines);
  ASSERT_EQ(to_pi.exit_code, kExitOk) << Describe(to_pi);
  EXPECT_TRUE(Near(JsonVector10(ParseJson(to_pi), "pi"), pi, 1e-15));

  // Plain text: 6 lines of 6 numbers after "spatial:".
  const CliRun text = RunCli(Concat({"convert", "--from", "pi", "--to", "spatial", "--"}, Args(pi)));
  ASSERT_EQ(text.exit_code, kExitOk) << Describe(text);
  const std::vector<double> flat = ParseText(text, "spatial");
  ASSERT_EQ(flat.size(), 36u) << Describe(text);
  EXPECT_LT(testing::RelativeError(Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(flat.data()), M), 1e-15);
  EXPECT_EQ(std::count(text.out.begin(), text.out.end(), '\n'), 6) << Describe(text);
}

TEST_F(ConvertCli, NumbersFromStdinWithCommasAndNewlines) {
  Rng rng(107);
  const Vector10 theta = rng.UniformVector<10>(-1.0, 1.0);
  std::string input;
  for (int i = 0; i < 10; ++i) input += Num(theta[i]) + (i % 3 == 2 ? "\n" : ",");
  const CliRun r = RunCli({"convert", "--from", "theta", "--to", "pi", "--json"}, input);
  ASSERT_EQ(r.exit_code, kExitOk) << Describe(r);
  EXPECT_TRUE(Near(JsonVector10(ParseJson(r), "pi"), PiFromLogCholesky(theta), 1e-15));
}

// ---------------------------------------------------------------------------------------------
// --reference (eq. 11).

TEST_F(ConvertCli, ReferenceBodyHasThetaZero) {
  Rng rng(108);
  const InertialParams reference = SolidCylinder(2.2, 0.15, 0.7, RandomPose(rng));
  std::string ref_text;
  for (int i = 0; i < 10; ++i) ref_text += (i ? "," : "") + Num(reference.vector()[i]);
  const CliRun r = RunCli(Concat({"convert", "--from", "pi", "--to", "theta", "--json", "--reference", ref_text, "--"},
                                 Args(reference.vector())));
  ASSERT_EQ(r.exit_code, kExitOk) << Describe(r);
  const Vector10 theta = JsonVector10(ParseJson(r), "theta");
  EXPECT_LE(theta.cwiseAbs().maxCoeff(), 1e-12) << theta.transpose();
}

TEST_F(ConvertCli, ReferenceBodyBothWaysForAnotherBody) {
  Rng rng(109);
  const InertialParams reference = SolidBox(1.5, 0.3, 0.4, 0.5, RandomPose(rng));
  const InertialParams body = SolidCylinder(0.6, 0.08, 0.3, RandomPose(rng));
  std::string ref_text;
  for (int i = 0; i < 10; ++i) ref_text += (i ? " " : "") + Num(reference.vector()[i]);  // space separated
  const Vector10 expected_theta = LogCholeskyParameterization(reference).ThetaOf(body);

  const CliRun to_theta = RunCli(Concat(
      {"convert", "--from", "pi", "--to", "theta", "--json", "--reference", ref_text, "--"}, Args(body.vector())));
  ASSERT_EQ(to_theta.exit_code, kExitOk) << Describe(to_theta);
  const Vector10 theta = JsonVector10(ParseJson(to_theta), "theta");
  EXPECT_TRUE(Near(theta, expected_theta, 1e-12));
  // Not the identity-reference theta.
  EXPECT_FALSE(Near(theta, LogCholeskyParameterization().ThetaOf(body), 1e-6));

  const CliRun to_pi = RunCli(
      Concat({"convert", "--from", "theta", "--to", "pi", "--json", "--reference", ref_text, "--"}, Args(theta)));
  ASSERT_EQ(to_pi.exit_code, kExitOk) << Describe(to_pi);
  EXPECT_TRUE(Near(JsonVector10(ParseJson(to_pi), "pi"), body.vector(), 1e-12));
}

// --reference as ten separate arguments is the same reference as one list of them.
TEST_F(ConvertCli, ReferenceAsSeparateArgumentsOrAsOneList) {
  Rng rng(110);
  const InertialParams reference = SolidBox(1.5, 0.3, 0.4, 0.5, RandomPose(rng));
  const InertialParams body = SolidCylinder(0.6, 0.08, 0.3, RandomPose(rng));
  const std::vector<std::string> ref = Args(reference.vector());
  std::string ref_text;
  for (int i = 0; i < 10; ++i) ref_text += (i ? "," : "") + ref[static_cast<std::size_t>(i)];
  const CliRun list = RunCli(Concat({"convert", "--from", "pi", "--to", "theta", "--json", "--reference", ref_text, "--"},
                                    Args(body.vector())));
  std::vector<std::string> separate_args = {"convert", "--from", "pi", "--to", "theta", "--json", "--reference"};
  separate_args.insert(separate_args.end(), ref.begin(), ref.end());
  separate_args.push_back("--");
  const CliRun separate = RunCli(Concat(separate_args, Args(body.vector())));
  ASSERT_EQ(list.exit_code, kExitOk) << Describe(list);
  ASSERT_EQ(separate.exit_code, kExitOk) << Describe(separate);
  EXPECT_EQ(separate.out, list.out);
  EXPECT_TRUE(Near(JsonVector10(ParseJson(separate), "theta"), LogCholeskyParameterization(reference).ThetaOf(body), 1e-12));
}

TEST_F(ConvertCli, InconsistentReferenceIsRefused) {
  const CliRun r = RunCli({"convert", "--from", "pi", "--to", "theta", "--reference=-1 0 0 0 1 1 1 0 0 0", "1", "0", "0", "0", "1", "1", "1", "0", "0", "0"});
  EXPECT_EQ(r.exit_code, kExitInconsistentBody) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "--reference")) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "mass not positive")) << Describe(r);
  const CliRun short_ref =
      RunCli({"convert", "--from", "pi", "--to", "theta", "--reference", "1 0 0", "1", "0", "0", "0", "1", "1", "1", "0",
              "0", "0"});
  EXPECT_EQ(short_ref.exit_code, kExitUsage) << Describe(short_ref);
  EXPECT_TRUE(Contains(short_ref.err, "10")) << Describe(short_ref);
}

// ---------------------------------------------------------------------------------------------
// Bad input.

const std::vector<std::string> kUnitBody = {"1", "0", "0", "0", "2", "2", "2", "0", "0", "0"};

TEST_F(ConvertCli, WrongCountIsAUsageErrorNamingTheExpectedCount) {
  std::vector<std::string> nine(kUnitBody.begin(), kUnitBody.end() - 1);
  const CliRun r = RunCli(Concat({"convert", "--from", "pi", "--to", "theta"}, nine));
  EXPECT_EQ(r.exit_code, kExitUsage) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "10")) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "9")) << Describe(r);
  EXPECT_TRUE(r.out.empty()) << Describe(r);

  std::vector<std::string> eleven = kUnitBody;
  eleven.push_back("0");
  EXPECT_EQ(RunCli(Concat({"convert", "--from", "pi", "--to", "theta"}, eleven)).exit_code, kExitUsage);

  // pseudo takes 16, spatial 36: 10 numbers are wrong for them.
  const CliRun pseudo = RunCli(Concat({"convert", "--from", "pseudo", "--to", "pi"}, kUnitBody));
  EXPECT_EQ(pseudo.exit_code, kExitUsage) << Describe(pseudo);
  EXPECT_TRUE(Contains(pseudo.err, "16")) << Describe(pseudo);
  const CliRun spatial = RunCli({"convert", "--from", "spatial", "--to", "pi"}, "1 2 3\n");
  EXPECT_EQ(spatial.exit_code, kExitUsage) << Describe(spatial);
  EXPECT_TRUE(Contains(spatial.err, "36")) << Describe(spatial);
  // Nothing at all on stdin.
  const CliRun empty = RunCli({"convert", "--from", "theta", "--to", "pi"}, "");
  EXPECT_EQ(empty.exit_code, kExitUsage) << Describe(empty);
  EXPECT_TRUE(Contains(empty.err, "10")) << Describe(empty);
}

TEST_F(ConvertCli, NotANumberIsAnInvalidValueNamingTheArgument) {
  std::vector<std::string> args = kUnitBody;
  args[3] = "abc";
  CliRun r = RunCli(Concat({"convert", "--from", "pi", "--to", "theta"}, args));
  EXPECT_EQ(r.exit_code, kExitInvalidValue) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "argument 4")) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "'abc'")) << Describe(r);
  EXPECT_TRUE(r.out.empty()) << Describe(r);

  args = kUnitBody;
  args[6] = "nan";
  r = RunCli(Concat({"convert", "--from", "pi", "--to", "pi"}, args));
  EXPECT_EQ(r.exit_code, kExitInvalidValue) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "argument 7")) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "'nan'")) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "not finite")) << Describe(r);

  args = kUnitBody;
  args[0] = "inf";
  r = RunCli(Concat({"convert", "--from", "pi", "--to", "pi", "--allow-inconsistent"}, args));
  EXPECT_EQ(r.exit_code, kExitInvalidValue) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "argument 1")) << Describe(r);

  args = kUnitBody;
  args[9] = "1e999";
  r = RunCli(Concat({"convert", "--from", "pi", "--to", "pi"}, args));
  EXPECT_EQ(r.exit_code, kExitInvalidValue) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "argument 10")) << Describe(r);

  // From stdin: the position of the bad value.
  r = RunCli({"convert", "--from", "pi", "--to", "pi"}, "1, 0, 0\n0, 2, x2\n2, 0, 0, 0\n");
  EXPECT_EQ(r.exit_code, kExitInvalidValue) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "stdin, value 6")) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "'x2'")) << Describe(r);
}

TEST_F(ConvertCli, InconsistentBodyIsRefusedWithTheReason) {
  // Negative mass.
  const std::vector<std::string> negative_mass = {"-1", "0", "0", "0", "2", "2", "2", "0", "0", "0"};
  CliRun r = RunCli(Concat({"convert", "--from", "pi", "--to", "theta", "--"}, negative_mass));
  EXPECT_EQ(r.exit_code, kExitInconsistentBody) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "mass not positive")) << Describe(r);
  EXPECT_TRUE(r.out.empty()) << Describe(r);

  // A plate in the xy-plane (second moment along z is zero): Ixx + Iyy = Izz, triangle equality.
  const std::vector<std::string> plate = {"1", "0", "0", "0", "0.25", "0.5", "0.75", "0", "0", "0"};
  r = RunCli(Concat({"convert", "--from", "pi", "--to", "theta"}, plate));
  EXPECT_EQ(r.exit_code, kExitInconsistentBody) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "triangle")) << Describe(r);

  // A clear triangle violation, given as mci.
  const std::vector<std::string> violation = {"2", "0.1", "0.2", "0.3", "1", "1", "3", "0", "0", "0"};
  r = RunCli(Concat({"convert", "--from", "mci", "--to", "theta"}, violation));
  EXPECT_EQ(r.exit_code, kExitInconsistentBody) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "triangle")) << Describe(r);

  // Zero mass in mci: the COM is undefined.
  const std::vector<std::string> zero_mass = {"0", "0.1", "0.2", "0.3", "1", "1", "1", "0", "0", "0"};
  r = RunCli(Concat({"convert", "--from", "mci", "--to", "pi"}, zero_mass));
  EXPECT_EQ(r.exit_code, kExitInconsistentBody) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "mass")) << Describe(r);
}

TEST_F(ConvertCli, AllowInconsistentConvertsExceptToTheta) {
  const std::vector<std::string> negative_mass = {"-1", "0", "0", "0", "2", "2", "2", "0", "0", "0"};
  CliRun r = RunCli(Concat({"convert", "--from", "pi", "--to", "pi", "--"}, negative_mass));
  EXPECT_EQ(r.exit_code, kExitInconsistentBody) << Describe(r);

  r = RunCli(Concat({"convert", "--from", "pi", "--to", "pi", "--json", "--allow-inconsistent", "--"}, negative_mass));
  ASSERT_EQ(r.exit_code, kExitOk) << Describe(r);
  const nlohmann::json j = ParseJson(r);
  Vector10 expected;
  expected << -1, 0, 0, 0, 2, 2, 2, 0, 0, 0;
  EXPECT_EQ(JsonVector10(j, "pi"), expected);
  EXPECT_FALSE(j["consistency"]["fully_consistent"].get<bool>());
  EXPECT_TRUE(Contains(j["consistency"]["reason"].get<std::string>(), "mass not positive")) << j.dump();

  // Plain-text output warns on stderr.
  r = RunCli(Concat({"convert", "--from", "pi", "--to", "pseudo", "--allow-inconsistent", "--"}, negative_mass));
  ASSERT_EQ(r.exit_code, kExitOk) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "mass not positive")) << Describe(r);

  r = RunCli(Concat({"convert", "--from", "pi", "--to", "theta", "--allow-inconsistent", "--"}, negative_mass));
  EXPECT_EQ(r.exit_code, kExitInconsistentBody) << Describe(r);
}

// --allow-inconsistent converts only "where the target exists": mci of a massless body does not
// (its COM is undefined), so it is refused like --from mci with zero mass, not printed as NaN.
TEST_F(ConvertCli, AllowInconsistentDoesNotPrintAnUndefinedComForZeroMass) {
  const std::vector<std::string> massless = {"0", "0", "0", "0", "1", "1", "1", "0", "0", "0"};
  const CliRun r = RunCli(Concat({"convert", "--from", "pi", "--to", "mci", "--allow-inconsistent"}, massless));
  EXPECT_EQ(r.exit_code, kExitInconsistentBody) << Describe(r);
  EXPECT_FALSE(Contains(r.out, "nan")) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "mass")) << Describe(r);
}

TEST_F(ConvertCli, UnknownOptionsAndRepresentationsAreUsageErrors) {
  EXPECT_EQ(RunCli(Concat({"convert", "--from", "pi", "--to", "theta", "--frobnicate"}, kUnitBody)).exit_code,
            kExitUsage);
  EXPECT_EQ(RunCli(Concat({"convert", "--from", "quaternion", "--to", "theta"}, kUnitBody)).exit_code, kExitUsage);
  EXPECT_EQ(RunCli(Concat({"convert", "--to", "theta"}, kUnitBody)).exit_code, kExitUsage);  // --from missing
  EXPECT_EQ(RunCli(Concat({"convert", "--from", "pi"}, kUnitBody)).exit_code, kExitUsage);  // --to missing
  EXPECT_EQ(RunCli({"frobnicate"}).exit_code, kExitUsage);
  EXPECT_EQ(RunCli({}).exit_code, kExitUsage);  // a subcommand is required
  const CliRun r = RunCli({"--frobnicate"});
  EXPECT_EQ(r.exit_code, kExitUsage) << Describe(r);
  EXPECT_FALSE(r.err.empty()) << Describe(r);
}

TEST_F(ConvertCli, HelpGoesToStdoutWithExitZero) {
  CliRun r = RunCli({"--help"});
  EXPECT_EQ(r.exit_code, kExitOk) << Describe(r);
  EXPECT_TRUE(Contains(r.out, "Usage")) << Describe(r);
  EXPECT_TRUE(Contains(r.out, "convert")) << Describe(r);
  EXPECT_TRUE(Contains(r.out, "study")) << Describe(r);
  EXPECT_TRUE(Contains(r.out, "Exit codes")) << Describe(r);

  r = RunCli({"convert", "--help"});
  EXPECT_EQ(r.exit_code, kExitOk) << Describe(r);
  EXPECT_TRUE(Contains(r.out, "Usage")) << Describe(r);
  EXPECT_TRUE(Contains(r.out, "--from")) << Describe(r);
  EXPECT_TRUE(Contains(r.out, "--to")) << Describe(r);
  EXPECT_TRUE(Contains(r.out, "--reference")) << Describe(r);

  r = RunCli({"study", "--help"});
  EXPECT_EQ(r.exit_code, kExitOk) << Describe(r);
  EXPECT_TRUE(Contains(r.out, "--bodies")) << Describe(r);
}

// ---------------------------------------------------------------------------------------------
// study.

TEST_F(StudyCli, SmallStudyAsJsonMatchesTheLibrary) {
  const CliRun r = RunCli({"study", "--bodies", "5", "--seed", "2", "--json"});
  ASSERT_EQ(r.exit_code, kExitOk) << Describe(r);
  const nlohmann::json j = ParseJson(r);
  ASSERT_TRUE(j.contains("bodies")) << j.dump();
  EXPECT_EQ(j["bodies"].get<int>(), 5);
  EXPECT_EQ(j["seed"].get<int>(), 2);
  ASSERT_TRUE(j["methods"]["log_cholesky"]["iterations"].is_array());
  ASSERT_EQ(j["methods"]["log_cholesky"]["iterations"].size(), 5u);

  // The same study in this process: per-body results do not depend on the thread count.
  StudyOptions options;
  options.bodies = 5;
  options.seed = 2;
  options.threads = 1;
  const StudyResult result = RunStudy(options);
  for (int k = 0; k < kStudyMethods; ++k) {
    const std::string name(StudyMethodName(k));
    const nlohmann::json& m = j["methods"][name];
    ASSERT_EQ(m["iterations"].size(), 5u) << name;
    for (int i = 0; i < 5; ++i) EXPECT_EQ(m["iterations"][i].get<int>(), result.bodies[i].methods[k].iterations) << name;
    EXPECT_EQ(m["failures"].get<int>(), result.summary.methods[k].failures) << name;
  }
  EXPECT_EQ(j["linear_ls"]["nonphysical"].get<int>(), result.summary.nonphysical);
  EXPECT_EQ(j["linear_ls"]["triangle_violations"].get<int>(), result.summary.triangle_violations);
}

TEST_F(StudyCli, TableOutputShowsThePapersFigures) {
  const CliRun r = RunCli({"study", "--bodies", "3", "--seed", "4", "--threads", "1"});
  ASSERT_EQ(r.exit_code, kExitOk) << Describe(r);
  EXPECT_TRUE(Contains(r.out, "3 random bodies")) << Describe(r);
  EXPECT_TRUE(Contains(r.out, "151")) << Describe(r);
  EXPECT_TRUE(Contains(r.out, "log_cholesky")) << Describe(r);
}

TEST_F(StudyCli, BadArgumentsAreUsageErrors) {
  CliRun r = RunCli({"study", "--bodies", "0"});
  EXPECT_EQ(r.exit_code, kExitUsage) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "--bodies")) << Describe(r);
  EXPECT_TRUE(r.out.empty()) << Describe(r);
  EXPECT_EQ(RunCli({"study", "--bodies", "-3"}).exit_code, kExitUsage);
  EXPECT_EQ(RunCli({"study", "--threads", "-1", "--bodies", "1"}).exit_code, kExitUsage);
  EXPECT_EQ(RunCli({"study", "--max-iterations", "0", "--bodies", "1"}).exit_code, kExitUsage);
  EXPECT_EQ(RunCli({"study", "--bodies", "2", "--frobnicate"}).exit_code, kExitUsage);
}

TEST_F(StudyCli, ReportDirectoryThatCannotBeCreatedIsAnIoError) {
  const fs::path file = UniqueTempPath("regular_file");
  { std::ofstream(file) << "x"; }
  const std::string dir = (file / "report").string();
  const CliRun r = RunCli({"study", "--bodies", "1", "--seed", "1", "--threads", "1", "--report", dir});
  std::error_code ec;
  fs::remove(file, ec);
  EXPECT_EQ(r.exit_code, kExitIoError) << Describe(r);
  EXPECT_TRUE(Contains(r.err, dir)) << Describe(r);
  EXPECT_TRUE(r.out.empty()) << "the directory is checked before the study runs: " << Describe(r);
}

// Integers are parsed strictly: not a number -> 3, a number out of range -> 2 (never wrapped).
TEST_F(StudyCli, IntegerOptionsAreParsedStrictly) {
  for (const char* bad : {"1.5", "abc", "", "1e3", "0x10"}) {
    for (const char* option : {"--seed", "--bodies", "--threads", "--max-iterations"}) {
      const CliRun r = RunCli({"study", option, bad});
      EXPECT_EQ(r.exit_code, kExitInvalidValue) << option << " " << bad << " " << Describe(r);
      EXPECT_TRUE(Contains(r.err, option)) << Describe(r);
      EXPECT_TRUE(Contains(r.err, "not an integer")) << Describe(r);
      EXPECT_TRUE(r.out.empty()) << Describe(r);
    }
  }
  for (const char* bad : {"-1", "99999999999999999999999"}) {
    const CliRun r = RunCli({"study", "--bodies", "1", "--seed", bad});
    EXPECT_EQ(r.exit_code, kExitUsage) << bad << " " << Describe(r);
    EXPECT_TRUE(Contains(r.err, "--seed")) << Describe(r);
    EXPECT_TRUE(Contains(r.err, "out of range")) << Describe(r);
    EXPECT_TRUE(r.out.empty()) << Describe(r);
  }
  const CliRun ok = RunCli({"study", "--bodies", "2", "--seed", "18446744073709551615", "--json"});
  ASSERT_EQ(ok.exit_code, kExitOk) << Describe(ok);
  EXPECT_EQ(ParseJson(ok)["seed"].get<std::uint64_t>(), 18446744073709551615ull);
}

// A finite theta is a consistent body by construction, however thin: convert never refuses it, even
// where the numerical margins fall below the checker's tolerance (it says so on stderr).
TEST_F(ConvertCli, ThinButFiniteThetaIsAccepted) {
  Vector10 theta;
  theta << -0.206, -3.74, 4.74, -4.71, 2.84, -0.366, -0.948, -4.45, 2.28, 4.25;
  ASSERT_FALSE(CheckConsistency(InertialParams::FromVector(PiFromLogCholesky(theta))).fully_consistent());
  const CliRun r = RunCli(Concat({"convert", "--from", "theta", "--to", "pi", "--json", "--"}, Args(theta)));
  ASSERT_EQ(r.exit_code, kExitOk) << Describe(r);
  EXPECT_TRUE(Near(JsonVector10(ParseJson(r), "pi"), PiFromLogCholesky(theta), 1e-15)) << Describe(r);
  EXPECT_TRUE(ParseJson(r)["consistency"]["fully_consistent"].get<bool>());
  EXPECT_FALSE(ParseJson(r)["consistency"]["margins_above_tolerance"].get<bool>());
  // Overflow is named as such.
  const CliRun huge = RunCli({"convert", "--from", "theta", "--to", "pi", "400", "0", "0", "0", "0", "0", "0", "0", "0", "0"});
  EXPECT_EQ(huge.exit_code, kExitInconsistentBody) << Describe(huge);
  EXPECT_TRUE(Contains(huge.err, "range of double")) << Describe(huge);
}

TEST_F(ConvertCli, ReferenceWithoutThetaIsAUsageErrorAndNoNegativeZero) {
  const CliRun r = RunCli({"convert", "--from", "pi", "--to", "mci", "--reference", "1 0 0 0 1 1 1 0 0 0", "1", "0", "0",
                           "0", "1", "1", "1", "0", "0", "0"});
  EXPECT_EQ(r.exit_code, kExitUsage) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "--reference")) << Describe(r);
  const CliRun spatial = RunCli({"convert", "--from", "pi", "--to", "spatial", "1", "0", "0", "0", "1", "1", "1", "0", "0", "0"});
  ASSERT_EQ(spatial.exit_code, kExitOk) << Describe(spatial);
  EXPECT_FALSE(Contains(spatial.out, "-0")) << Describe(spatial);
}

}  // namespace
}  // namespace inertial
