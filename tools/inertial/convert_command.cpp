// `inertial convert`: one body between representations (body_representation.hpp).
#include <iostream>
#include <iterator>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "option_parsing.hpp"
#include "inertial/formats/body_representation.hpp"
#include "inertial/formats/number_parsing.hpp"
#include "inertial/report/body_conversion_report.hpp"

namespace inertial::cli {
namespace {

const char* kRepresentationHelp =
    "pi: [m hx hy hz Ixx Iyy Izz Ixy Iyz Ixz] about the frame origin (h = m c); "
    "theta: log-Cholesky [alpha d1 d2 d3 s12 s23 s13 t1 t2 t3] (eq. 8, relative to --reference if given, eq. 11); "
    "mci: [m cx cy cz Ixx Iyy Izz Ixy Iyz Ixz] with the inertia about the center of mass; "
    "pseudo: the 4x4 pseudo-inertia J, 16 numbers row by row; "
    "spatial: the 6x6 spatial inertia (eq. 2), 36 numbers row by row";

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The input numbers: the arguments, or stdin if none are given; as many as --from takes.
std::vector<double> ReadInputNumbers(const ConvertCommand& c) {
  std::vector<double> v;
  if (c.values.empty()) {
    const std::string text((std::istreambuf_iterator<char>(std::cin)), std::istreambuf_iterator<char>());
    v = ParseNumberList(text, "stdin");
  }
  for (std::size_t i = 0; i < c.values.size(); ++i) {
    v.push_back(ParseDouble(c.values[i], "argument " + std::to_string(i + 1) + " (" + c.from + ")"));
  }
  const int expected = BodyRepresentationSizes().at(c.from);
  if (static_cast<int>(v.size()) != expected) {
    throw UsageError("--from " + c.from + " takes " + std::to_string(expected) + " numbers, got " +
                     std::to_string(v.size()));
  }
  return v;
}

// --reference: the pi of a fully consistent body, for theta only; none if not given.
std::optional<InertialParams> ReadReference(const ConvertCommand& c) {
  if (c.reference.empty()) return std::nullopt;
  const std::vector<double> r = ParseNumberList(c.reference, "--reference");
  if (r.size() != 10) throw UsageError(NumberCountError("--reference", 10, r.size(), c.reference));
  const InertialParams reference = InertialParams::FromVector(Eigen::Map<const Vector10>(r.data()));
  const ConsistencyReport report = CheckConsistency(reference);
  if (!report.fully_consistent()) {
    throw std::invalid_argument("--reference is not fully physically consistent: " + report.reason);
  }
  if (c.from != "theta" && c.to != "theta") {
    throw UsageError("--reference applies to theta only, and neither --from nor --to is theta");
  }
  return reference;
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
  for (const auto& kv : BodyRepresentationSizes()) names.push_back(kv.first);
  sub->add_option("--from", c->from, "representation of the input")->required()->check(CLI::IsMember(names));
  sub->add_option("--to", c->to, "representation of the output")->required()->check(CLI::IsMember(names));
  sub->add_option("--reference", c->reference,
                  "pi of the reference body for theta (eq. 11)");
  sub->add_flag("--json", c->json, "print a JSON object (key = the --to name, plus 'consistency')");
  sub->add_flag("--allow-inconsistent", c->allow_inconsistent,
                "convert an inconsistent body where the target exists (pi, mci, pseudo, spatial)");
  sub->add_option("values", c->values, "the input numbers (use -- before them if the first is negative)");
  return sub;
}

int RunConvertCommand(const ConvertCommand& c) {
  try {
    BodyConversionRequest request;
    request.from = c.from;
    request.to = c.to;
    request.values = ReadInputNumbers(c);
    request.reference = ReadReference(c);
    request.allow_inconsistent = c.allow_inconsistent;
    const BodyConversion conversion = ConvertBody(request);
    if (c.json) {
      std::cout << BodyConversionJson(conversion).dump(2) << "\n";  // nlohmann prints doubles with round-trip precision
    } else {
      std::cout << BodyConversionText(conversion);
      std::cerr << BodyConversionNote(conversion);
    }
    return kOk;
  } catch (const UsageError& e) {
    std::cerr << "Error: convert: " << e.what() << "\n";
    return kUsage;
  } catch (const InvalidNumber& e) {
    std::cerr << "Error: convert: " << e.what() << "\n";
    return kInvalidValue;
  } catch (const std::invalid_argument& e) {  // no body, or an inconsistent one (body_representation.hpp)
    std::cerr << "Error: convert: " << e.what() << "\n";
    return kInconsistentBody;
  }
}

}  // namespace inertial::cli
