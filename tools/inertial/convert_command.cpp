// `inertial convert`: one body between representations.
#include <iomanip>
#include <iostream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inertial/inertia/log_cholesky.hpp"
#include "inertial/formats/number_parsing.hpp"

namespace inertial::cli {
namespace {

// Representations and how many numbers each takes.
const std::map<std::string, int> kRepresentations = {
    {"pi", 10}, {"theta", 10}, {"mci", 10}, {"pseudo", 16}, {"spatial", 36}};

const char* kRepresentationHelp =
    "pi: [m hx hy hz Ixx Iyy Izz Ixy Iyz Ixz] about the frame origin (h = m c); "
    "theta: log-Cholesky [alpha d1 d2 d3 s12 s23 s13 t1 t2 t3] (eq. 8, relative to --reference if given, eq. 11); "
    "mci: [m cx cy cz Ixx Iyy Izz Ixy Iyz Ixz] with the inertia about the center of mass; "
    "pseudo: the 4x4 pseudo-inertia J, 16 numbers row by row; "
    "spatial: the 6x6 spatial inertia (eq. 2), 36 numbers row by row";

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
struct InconsistentInput : std::runtime_error {
  using std::runtime_error::runtime_error;
};

Vector10 ToPi(const std::string& from, const std::vector<double>& v, const LogCholeskyParameterization& lc) {
  if (from == "pi") return Eigen::Map<const Vector10>(v.data());
  if (from == "theta") return lc.ToPi(Eigen::Map<const Vector10>(v.data()));
  if (from == "mci") {
    Vector10 in = Eigen::Map<const Vector10>(v.data());
    Matrix3 I;
    I << in[4], in[7], in[9], in[7], in[5], in[8], in[9], in[8], in[6];
    if (!(in[0] != 0.0)) throw InconsistentInput("mci: mass is zero, the center of mass is undefined");
    return InertialParams::FromMassComInertia(in[0], in.segment<3>(1), I).vector();
  }
  if (from == "pseudo") {
    const Matrix4 J = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(v.data());
    return InertialParams::FromPseudoInertia(J).vector();
  }
  const Matrix6 M = Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(v.data());
  return InertialParams::FromSpatialInertia(M).vector();
}

nlohmann::json MatrixJson(const Eigen::MatrixXd& M) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < M.rows(); ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index j = 0; j < M.cols(); ++j) row.push_back(M(i, j));
    rows.push_back(row);
  }
  return rows;
}

std::vector<double> Flatten(const Eigen::MatrixXd& M) {
  std::vector<double> out;
  for (Eigen::Index i = 0; i < M.rows(); ++i)
    for (Eigen::Index j = 0; j < M.cols(); ++j) out.push_back(M(i, j));
  return out;
}

}  // namespace

CLI::App* AddConvertCommand(CLI::App& app, ConvertCommand* c) {
  CLI::App* sub = app.add_subcommand(
      "convert",
      std::string("Convert one body between representations. Numbers come from the arguments, or from stdin if "
                  "none are given (separated by spaces, commas or newlines). Refuses physically inconsistent input "
                  "(exit 4) unless --allow-inconsistent (never for --to theta). Representations: ") +
          kRepresentationHelp);
  std::vector<std::string> names;
  for (const auto& kv : kRepresentations) names.push_back(kv.first);
  sub->add_option("--from", c->from, "representation of the input")->required()->check(CLI::IsMember(names));
  sub->add_option("--to", c->to, "representation of the output")->required()->check(CLI::IsMember(names));
  sub->add_option("--reference", c->reference,
                  "pi of the reference body for theta (eq. 11), 10 numbers separated by commas or spaces");
  sub->add_flag("--json", c->json, "print a JSON object (key = the --to name, plus 'consistency')");
  sub->add_flag("--allow-inconsistent", c->allow_inconsistent,
                "convert an inconsistent body where the target exists (pi, mci, pseudo, spatial)");
  sub->add_option("values", c->values, "the input numbers (use -- before them if the first is negative)");
  return sub;
}

int RunConvertCommand(const ConvertCommand& c) {
  try {
    // Input numbers.
    std::vector<double> v;
    if (c.values.empty()) {
      const std::string text((std::istreambuf_iterator<char>(std::cin)), std::istreambuf_iterator<char>());
      v = ParseNumberList(text, "stdin");
    } else {
      for (std::size_t i = 0; i < c.values.size(); ++i) {
        v.push_back(ParseDouble(c.values[i], "argument " + std::to_string(i + 1) + " (" + c.from + ")"));
      }
    }
    const int expected = kRepresentations.at(c.from);
    if (static_cast<int>(v.size()) != expected) {
      throw UsageError("--from " + c.from + " takes " + std::to_string(expected) + " numbers, got " +
                       std::to_string(v.size()));
    }

    // Reference body for theta.
    LogCholeskyParameterization lc;
    if (!c.reference.empty()) {
      const std::vector<double> r = ParseNumberList(c.reference, "--reference");
      if (r.size() != 10) throw UsageError("--reference takes 10 numbers (pi), got " + std::to_string(r.size()));
      const InertialParams reference = InertialParams::FromVector(Eigen::Map<const Vector10>(r.data()));
      const ConsistencyReport report = CheckConsistency(reference);
      if (!report.fully_consistent()) throw InconsistentInput("--reference is not fully physically consistent: " + report.reason);
      lc = LogCholeskyParameterization(reference);
    }

    if (!c.reference.empty() && c.from != "theta" && c.to != "theta") {
      throw UsageError("--reference applies to theta only, and neither --from nor --to is theta");
    }
    const InertialParams body = InertialParams::FromVector(ToPi(c.from, v, lc));
    if (c.from == "theta" && !body.AllFinite()) {
      throw InconsistentInput("theta gives a body beyond the range of double precision (e^{2 alpha} or a product overflows)");
    }
    const ConsistencyReport report = CheckConsistency(body);
    // Every finite theta is a consistent body by construction (Section IV-B), even where it is so thin
    // that its numerical margins fall below the checker's tolerance: never refuse it.
    const bool consistent = report.fully_consistent() || (c.from == "theta" && lc.YieldsConsistentBody(Eigen::Map<const Vector10>(v.data())));
    if (!consistent && (!c.allow_inconsistent || c.to == "theta")) {
      throw InconsistentInput("input (" + c.from + ") is not a fully physically consistent body: " + report.reason);
    }

    // Output.
    Eigen::MatrixXd out;
    if (c.to == "pi") out = body.vector();
    else if (c.to == "theta") {
      Vector10 theta;
      if (c.from == "theta" && !c.reference.empty()) {
        theta = Eigen::Map<const Vector10>(v.data());  // identity conversion
      } else if (!lc.FromPi(body.vector(), &theta)) {
        throw InconsistentInput("the body has no log-Cholesky parameters (its pseudo-inertia has no Cholesky factor)");
      }
      out = theta;
    }
    else if (c.to == "mci") {
      if (!(body.mass() != 0.0)) throw InconsistentInput("--to mci: the mass is zero, so there is no center of mass");
      const Matrix3 I = body.rotational_inertia_about_com();
      Vector10 m;
      m << body.mass(), body.com(), I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(1, 2), I(0, 2);
      out = m;
    } else if (c.to == "pseudo") out = body.pseudo_inertia();
    else out = body.spatial_inertia();

    if (c.json) {
      nlohmann::json j;
      j[c.to] = out.cols() == 1 ? nlohmann::json(Flatten(out)) : MatrixJson(out);
      j["consistency"] = {{"fully_consistent", consistent},
                          {"margins_above_tolerance", report.fully_consistent()},
                          {"mass", report.mass},
                          {"min_inertia_eigenvalue_com", report.min_inertia_eigenvalue_com},
                          {"min_triangle_margin", report.min_triangle_margin},
                          {"min_pseudo_inertia_eigenvalue", report.min_pseudo_inertia_eigenvalue},
                          {"reason", report.reason}};
      std::cout << j.dump(2) << "\n";  // nlohmann prints doubles with round-trip precision
    } else {
      std::ostringstream os;
      os << std::setprecision(17);
      os << c.to << ":";
      const std::vector<double> flat = Flatten(out);
      for (std::size_t i = 0; i < flat.size(); ++i) {
        // Matrices: one row per line, rows after the first indented to line up under the first.
        const bool new_row = out.cols() > 1 && i > 0 && i % out.cols() == 0;
        os << (new_row ? "\n" + std::string(c.to.size() + 2, ' ') : std::string(i == 0 ? " " : " "))
           << flat[i] + 0.0;  // + 0.0 turns -0 into 0
      }
      std::cout << os.str() << "\n";
      if (!report.fully_consistent()) {
        if (consistent) {
          std::cerr << "note: consistent by construction (finite theta), but so thin that the numerical check "
                       "cannot confirm it: "
                    << report.reason << "\n";
        } else {
          std::cerr << "warning: " << report.reason << "\n";
        }
      }
    }
    return kOk;
  } catch (const UsageError& e) {
    std::cerr << "Error: convert: " << e.what() << "\n";
    return kUsage;
  } catch (const InvalidNumber& e) {
    std::cerr << "Error: convert: " << e.what() << "\n";
    return kInvalidValue;
  } catch (const InconsistentInput& e) {
    std::cerr << "Error: convert: " << e.what() << "\n";
    return kInconsistentBody;
  } catch (const std::invalid_argument& e) {  // malformed pseudo/spatial matrix
    std::cerr << "Error: convert: " << e.what() << "\n";
    return kInconsistentBody;
  }
}

}  // namespace inertial::cli
