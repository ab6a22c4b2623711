/// @file command_line.hpp
/// The command line of `inertial` and `inertiald` parsed by CLI11, with usage errors a person can act
/// on: the program and subcommand named, every unknown option or subcommand named with the nearest
/// known one, `--version`. Shared by both programs (tools/ only: CLI11 is the programs' library).
#pragma once

#include <CLI/CLI.hpp>

#include "numeric_options.hpp"

#include <algorithm>
#include <cctype>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

namespace inertial::cli {

/// Levenshtein distance (insertions, deletions, substitutions), for "did you mean".
inline std::size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

/// The candidate nearest to `word` if it is close (at most a third of the word's letters differ,
/// and at least one letter is kept), else empty.
inline std::string Nearest(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_distance = word.size() / 3 + 1;
  for (const std::string& c : candidates) {
    const std::size_t d = EditDistance(word, c);
    if (d < best_distance) best_distance = d, best = c;
  }
  return best;
}

inline std::string DidYouMean(const std::string& word, const std::vector<std::string>& candidates) {
  const std::string nearest = Nearest(word, candidates);
  return nearest.empty() ? "" : " (did you mean " + nearest + "?)";
}

/// Every long and short name of the app's options ("--model", "-h", ...).
inline std::vector<std::string> OptionNames(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::Option* option : app.get_options()) {
    for (const std::string& n : option->get_lnames()) names.push_back("--" + n);
    for (const std::string& n : option->get_snames()) names.push_back("-" + n);
  }
  return names;
}

inline std::string SubcommandList(const CLI::App& app) {
  std::string list;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    list += (list.empty() ? "" : ", ") + sub->get_name();
  }
  return list;
}

/// Every subcommand of the app, parsed or not.
inline std::vector<const CLI::App*> AllSubcommands(const CLI::App& app) {
  return app.get_subcommands([](const CLI::App*) { return true; });
}

/// The subcommand that was parsed, or the app itself.
inline const CLI::App* ParsedCommand(CLI::App& app) {
  const CLI::App* where = &app;
  for (CLI::App* sub : app.get_subcommands()) where = sub;
  return where;
}

/// "inertial" or "inertial convert": who a message is from.
inline std::string CommandName(const CLI::App& app, const CLI::App* where) {
  return where == &app ? app.get_name() : app.get_name() + " " + where->get_name();
}

/// Before parsing: the first word that is not an option of the program itself must name a
/// subcommand. Prints the error and returns false if it does not.
inline bool FirstWordIsASubcommand(const CLI::App& app, const std::vector<std::string>& args) {
  for (const std::string& a : args) {
    if (!a.empty() && a[0] == '-') continue;
    std::vector<std::string> names;
    for (const CLI::App* sub : AllSubcommands(app)) names.push_back(sub->get_name());
    if (std::find(names.begin(), names.end(), a) != names.end()) return true;
    std::cerr << "Error: " << app.get_name() << ": unknown subcommand '" << a << "'" << DidYouMean(a, names)
              << "; the subcommands are " << SubcommandList(app) << "\n";
    return false;
  }
  return true;
}

/// The hint for an option `where` does not know: the nearest name it knows, else the other
/// subcommands that have it; empty if neither.
inline std::string UnknownOptionHint(const CLI::App& app, const CLI::App* where, const std::string& name,
                                     const std::vector<std::string>& known) {
  std::string hint = DidYouMean(name, known);
  if (!hint.empty() || where == &app) return hint;
  std::string others;  // the subcommands that do have it
  for (const CLI::App* sub : AllSubcommands(app)) {
    const std::vector<std::string> theirs = OptionNames(*sub);
    if (sub != where && std::find(theirs.begin(), theirs.end(), name) != theirs.end()) {
      others += (others.empty() ? "" : ", ") + app.get_name() + " " + sub->get_name();
    }
  }
  return others.empty() ? "" : " (it is an option of " + others + ")";
}

/// Prints an "unknown option" error for each argument of `args` that looks like an option `where`
/// does not know (not a negative number, not an option of the program itself); true if any.
inline bool ReportUnknownOptions(const CLI::App& app, const CLI::App* where, const std::vector<std::string>& args) {
  const std::vector<std::string> known = OptionNames(*where);
  const std::vector<std::string> program_options = OptionNames(app);  // e.g. --help before the subcommand
  bool named = false;
  for (const std::string& a : args) {
    if (a.size() < 2 || a[0] != '-' || a == "--") continue;
    const std::string name = a.substr(0, a.find('='));
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    if (std::find(program_options.begin(), program_options.end(), name) != program_options.end()) continue;
    if (std::isdigit(static_cast<unsigned char>(name[1])) || name[1] == '.') continue;  // a negative number
    std::cerr << "Error: " << CommandName(app, where) << ": unknown option " << name
              << UnknownOptionHint(app, where, name, known) << "\n";
    named = true;
  }
  return named;
}

/// CLI11's ExtrasError: each unknown option named with a hint, or else the unexpected arguments.
inline void ReportExtras(CLI::App& app, const std::vector<std::string>& args, const CLI::ExtrasError& e) {
  const CLI::App* where = ParsedCommand(app);
  const std::string who = CommandName(app, where);
  if (!ReportUnknownOptions(app, where, args)) {
    std::string values;
    for (const std::string& v : where->remaining()) values += (values.empty() ? "'" : " '") + v + "'";
    if (values.empty()) values = e.what();
    std::cerr << "Error: " << who << ": unexpected argument" << (where->remaining().size() > 1 ? "s " : " ")
              << values << "\n";
  }
  std::cerr << "Run " << who << " --help for the options.\n";
}

/// CLI11's RequiredError: a missing subcommand listed with the subcommands, else CLI11's message.
inline void ReportRequired(CLI::App& app, const CLI::RequiredError& e) {
  const CLI::App* where = ParsedCommand(app);
  const std::string program = app.get_name();
  if (!AllSubcommands(app).empty() && where == &app) {
    std::cerr << "Error: " << program << ": a subcommand is required: " << SubcommandList(app) << "\n"
              << "Run " << program << " --help for what each does.\n";
  } else {
    std::cerr << "Error: " << CommandName(app, where) << ": " << e.what() << "\n";
  }
}

/// Parses; returns std::nullopt to go on, or the exit code (0 after --help or --version, `usage`
/// after a usage error, which is printed to stderr as one "Error: ..." line and a hint).
/// `app` must have its name (app.name("inertial")): it starts every message.
inline std::optional<int> ParseCommandLine(CLI::App& app, int argc, char** argv, int usage) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (!AllSubcommands(app).empty() && !FirstWordIsASubcommand(app, args)) return usage;
  try {
    // The options taking several numbers, given as separate arguments, joined (numeric_options.hpp).
    std::vector<std::string> joined = JoinNumberArguments(args);
    std::vector<char*> joined_argv = {argv[0]};
    for (std::string& a : joined) joined_argv.push_back(a.data());
    app.parse(static_cast<int>(joined_argv.size()), joined_argv.data());
    return std::nullopt;
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    std::cout << e.what() << "\n";
    return 0;
  } catch (const CLI::ExtrasError& e) {
    ReportExtras(app, args, e);
    return usage;
  } catch (const CLI::RequiredError& e) {
    ReportRequired(app, e);
    return usage;
  } catch (const CLI::ParseError& e) {
    const std::string who = CommandName(app, ParsedCommand(app));
    std::cerr << "Error: " << who << ": " << e.what() << "\nRun " << who << " --help for the options.\n";
    return usage;
  }
}

}  // namespace inertial::cli
