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

#include <regex>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

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
  };
  return table;
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
      o->description(d);
    }
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) DescribeNumericOptions(*sub);
}

}  // namespace inertial::cli
