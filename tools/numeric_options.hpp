/// @file numeric_options.hpp
/// Every numeric option of `inertial` and `inertiald`, shown the same way in --help:
///   --sg-window FLOAT [s]=0.1     Savitzky-Golay window
/// type (INT, FLOAT, or a count of FLOATs), unit in brackets (none for pure numbers), and the
/// default after "=" (the value used when the option is absent; "=" with words when it depends
/// on another option). The options are parsed as text by option_parsing.hpp (so that a bad value
/// gets our message, not CLI11's): this table gives --help what the parser knows.
/// A test (command_line_e2e_test.cpp) checks that no option of either program still shows TEXT
/// unless it is a path, a name or a list of words.
#pragma once

#include <cstdlib>
#include <regex>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "inertial/formats/number_parsing.hpp"

namespace inertial::cli {

struct NumericOption {
  const char* name;     ///< "--sg-window"
  const char* type;     ///< "INT", "FLOAT", "3 FLOATS", "10 FLOATS", "FLOATS"
  const char* unit;     ///< "s", "Hz", ... or "" for a pure number
  const char* fallback; ///< the default when CLI11 has none to show ("" : no default, optional)
};

inline const std::vector<NumericOption>& NumericOptions() {
  static const std::vector<NumericOption> table = {
      {"--bodies", "INT", "", ""},
      {"--seed", "INT", "", ""},
      {"--truth-seed", "INT", "", ""},
      {"--threads", "INT", "", "0: one per core"},
      {"--max-iterations", "INT", "", ""},
      {"--sg-order", "INT", "", "4"},
      {"--harmonics", "INT", "", ""},
      {"--folds", "INT", "", "5"},
      {"--iterate", "INT", "", "0"},
      {"--prior-weight", "FLOAT", "", "0.01"},
      {"--gravity", "3 FLOATS", "m/s^2", "0 0 -9.81"},
      {"--sg-window", "FLOAT", "s", "0.1"},
      {"--time-scale", "FLOAT", "s per unit", ""},
      {"--outlier-threshold", "FLOAT", "robust std", ""},
      {"--effect-values", "FLOATS", "", ""},
      {"--perturb", "FLOAT", "", ""},
      {"--duration", "FLOAT", "s", ""},
      {"--rate", "FLOAT", "Hz", ""},
      {"--start-time", "FLOAT", "s", ""},
      {"--base-frequency", "FLOAT", "Hz", ""},
      {"--amplitude", "FLOAT", "rad or m", ""},
      {"--noise-q", "FLOAT", "rad or m", ""},
      {"--noise-qd", "FLOAT", "rad/s or m/s", ""},
      {"--noise-tau", "FLOAT", "N m or N", "--config's or 1"},
      {"--pi", "10 FLOATS", "kg, kg m, kg m^2", ""},
      {"--prior", "10 FLOATS", "kg, kg m, kg m^2", "1 kg, 1 kg m^2 at the origin"},
      {"--reference", "10 FLOATS", "kg, kg m, kg m^2", ""},
      {"--holdout", "FLOAT", "fraction", "0.3 for robots"},
      {"--prior-tolerance", "FLOAT", "factor - 1", "0.75"},
      {"--min-explained", "FLOAT", "fraction", ""},
      {"--publish-rate", "FLOAT", "Hz", "--config's or 10"},
      {"--checkpoint-interval", "FLOAT", "s", "5"},
      {"--max-mismatch-torque", "FLOAT", "fraction", "0.1"},
      {"--total-mass", "FLOAT", "kg", ""},
  };
  return table;
}

/// How many numbers an option of the table takes: 1 for INT and FLOAT, N for "N FLOATS", 0 for
/// "FLOATS" (one or more); -1 for an option not in the table.
inline int NumberCount(const std::string& option) {
  for (const NumericOption& n : NumericOptions()) {
    if (option != n.name) continue;
    const std::string type = n.type;
    if (type == "FLOATS") return 0;
    if (type.size() > 7 && type.compare(type.size() - 7, 7, " FLOATS") == 0) return std::atoi(type.c_str());
    return 1;
  }
  return -1;
}

/// How every option taking several numbers is given, said once in --help.
inline constexpr const char* kNumberListHelp =
    "the numbers as separate arguments or as one quoted list separated by spaces or commas";

/// The options taking several numbers accept them as separate arguments (`--pi 1 0 0 0 1 1 1 0 0
/// 0`, `--gravity 0 0 -9.81`) as well as one list (`--pi "1,0,0,..."`): the separate arguments are
/// joined here into the one text the option parses (ParseNumberList: spaces and/or commas). After
/// such an option, the arguments that each read as one number are taken, up to the option's count
/// (all of them for FLOATS); a first argument that is already a list (or --option=TEXT) is left
/// alone, and nothing after "--" is touched.
inline std::vector<std::string> JoinNumberArguments(const std::vector<std::string>& args) {
  auto is_number = [](const std::string& text) {
    try {
      ParseDouble(text, "", true);
      return true;
    } catch (const InvalidNumber&) {
      return false;
    }
  };
  std::vector<std::string> out;
  for (std::size_t i = 0; i < args.size(); ++i) {
    out.push_back(args[i]);
    if (args[i] == "--") {
      out.insert(out.end(), args.begin() + static_cast<std::ptrdiff_t>(i) + 1, args.end());
      break;
    }
    const int count = NumberCount(args[i]);
    if (count != 0 && count < 2) continue;
    std::string joined;
    std::size_t taken = 0;
    while (i + 1 < args.size() && (count == 0 || taken < static_cast<std::size_t>(count)) && is_number(args[i + 1])) {
      joined += (taken++ ? " " : "") + args[++i];
    }
    if (taken > 0) out.push_back(joined);
  }
  return out;
}

/// Shows every numeric option of `app` and its subcommands as the table says: type and unit as
/// CLI11's type name, the default after "=", and a "(default ...)" clause in the description
/// removed (the default is shown once, in one place).
inline void DescribeNumericOptions(CLI::App& app) {
  static const std::regex default_clause(R"(\s*\((robots: |--body: )?default:? [^()]*(\([^()]*\)[^()]*)*\))");
  for (CLI::Option* o : app.get_options()) {
    for (const NumericOption& n : NumericOptions()) {
      if (o->get_name() != n.name) continue;
      o->type_name(std::string(n.type) + (*n.unit ? std::string(" [") + n.unit + "]" : ""));
      if (o->get_default_str().empty() && *n.fallback) o->default_str(n.fallback);
      std::string d = std::regex_replace(o->get_description(), default_clause, "");
      for (const char* unit : {n.unit, "s", "Hz", "m/s^2", "N m"}) {  // the unit is shown once, by the type
        const std::string bracket = std::string(" [") + unit + "]";
        if (*n.unit && (unit == n.unit || std::string(n.unit).find(unit) == 0)) {
          for (std::size_t at = d.find(bracket); at != std::string::npos; at = d.find(bracket)) d.erase(at, bracket.size());
        }
      }
      if (NumberCount(n.name) != 1) d += "; " + std::string(kNumberListHelp);
      o->description(d);
    }
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) DescribeNumericOptions(*sub);
}

}  // namespace inertial::cli
