// Conventions shared by roadcross, roadcross-viz and roadcross-build (osmium-tool's and OSRM's):
// usage errors exit 2 with the program's name and a "did you mean" for a misspelt subcommand or
// option; under --json every error is one JSON object {"error": ..., "code": ...} on stdout;
// counts and rates are printed for people ("95,620", not "9.562e+04").
#pragma once

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace roadcross::cli {

/// Exit status of a usage error (bad or missing arguments), as osmium and the BSD tools.
inline constexpr int kUsageExitStatus = 2;

/// Whether errors are printed as JSON objects (set once from the command line by
/// parse_command_line: any --json argument).
inline bool& json_errors() {
  static bool enabled = false;
  return enabled;
}

/// Prints an error the way the command line asked for: "PROGRAM: MESSAGE" on stderr, or under
/// --json {"error": MESSAGE, "code": CODE} on stdout (where a script reads the answers).
/// `code`: a stable snake_case name (the runtime's status codes, "usage", ...).
inline void print_error(std::string_view program, std::string_view message, std::string_view code) {
  if (json_errors()) {
    nlohmann::ordered_json out;
    out["error"] = std::string(message);
    out["code"] = std::string(code);
    // A message may carry any bytes (a path in another encoding): replaced, never fatal.
    std::cout << out.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) << "\n";
    std::cout.flush();
    return;
  }
  std::cerr << program << ": " << message << "\n";
}

/// Levenshtein distance between two words (insertions, deletions and substitutions cost 1).
inline std::size_t edit_distance(std::string_view a, std::string_view b) {
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

/// The candidate closest to `word` when it is close enough to be a typo (at most a third of the
/// word's letters, at least 2, changed), else nullopt.
inline std::optional<std::string> closest_name(std::string_view word,
                                               const std::vector<std::string>& candidates) {
  std::optional<std::string> best;
  std::size_t best_distance = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const std::string& candidate : candidates) {
    const std::size_t distance = edit_distance(word, candidate);
    if (distance < best_distance) best_distance = distance, best = candidate;
  }
  return best;
}

/// "--name" for every long option of `app` (and of its parents: --help, --version).
inline std::vector<std::string> long_option_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* a = &app; a; a = a->get_parent()) {
    for (const CLI::Option* option : a->get_options()) {
      for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
    }
  }
  return names;
}

/// The subcommand named on the command line, or `app` itself.
inline CLI::App& named_command(CLI::App& app, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
      if (sub->get_name() == argv[i]) return *sub;
    }
  }
  return app;
}

/// A "did you mean" for the first word of the command line that names no subcommand or no option
/// of `command`, or an empty string.
inline std::string suggestion_for(CLI::App& root, CLI::App& command, int argc, char** argv) {
  const bool has_subcommands = !root.get_subcommands([](CLI::App*) { return true; }).empty();
  if (has_subcommands && argc > 1 && argv[1][0] != '-' && &command == &root) {
    std::vector<std::string> names;
    for (CLI::App* sub : root.get_subcommands([](CLI::App*) { return true; })) {
      names.push_back(sub->get_name());
    }
    const auto best = closest_name(argv[1], names);
    return "unknown command '" + std::string(argv[1]) + "'" +
           (best ? "; did you mean '" + *best + "'?" : "");
  }
  const std::vector<std::string> names = long_option_names(command);
  for (int i = 1; i < argc; ++i) {
    const std::string_view word = argv[i];
    if (word == "--") break;
    if (word.substr(0, 2) != "--") continue;
    const std::string name(word.substr(0, word.find('=')));
    if (std::find(names.begin(), names.end(), name) != names.end()) continue;
    const auto best = closest_name(name, names);
    return "unknown option " + name + (best ? "; did you mean " + *best + "?" : "");
  }
  return {};
}

/// Parses the command line. Returns nullopt when the program should go on, else its exit status:
/// 0 after --help or --version, kUsageExitStatus after a usage error (printed with the program's
/// name, a "did you mean" where one fits and a pointer to --help; as JSON under --json).
inline std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv,
                                             std::string_view program) {
  json_errors() = std::any_of(argv + 1, argv + argc,
                              [](const char* arg) { return std::string_view(arg) == "--json"; });
  try {
    app.parse(argc, argv);
    return std::nullopt;
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    CLI::App& command = named_command(app, argc, argv);
    const std::string who =
        &command == &app ? std::string(program) : std::string(program) + " " + command.get_name();
    const std::string hint = suggestion_for(app, command, argc, argv);
    const std::string message = hint.empty() ? std::string(e.what()) : hint;
    print_error(who, message, "usage");
    if (!json_errors()) std::cerr << "Run '" << who << " --help' for the usage.\n";
    return kUsageExitStatus;
  }
}

}  // namespace roadcross::cli
