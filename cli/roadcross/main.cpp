// roadcross: query a roadcross map before or during a mission.
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli_conventions.hpp"
#include "commands.hpp"
#include "roadcross/version.hpp"
#include "viz_command_list.hpp"

namespace {

#ifdef ROADCROSS_WITH_VIZ
/// Runs `roadcross-viz COMMAND ARGS...` from this program's directory in place of this
/// process (so its output and exit status are the command's); returns only on failure.
int run_viz_command(const std::string& command, const std::vector<std::string>& args) {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  const std::filesystem::path program =
      (error ? std::filesystem::path(".") : self.parent_path()) / roadcross::cli::kVizProgram;
  std::vector<std::string> words{program.string(), command};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  ::execv(program.c_str(), argv.data());
  roadcross::cli::print_error("roadcross " + command,
                              "cannot run " + program.string() + " (" + std::strerror(errno) +
                                  "); the drawing commands come with the full build (cmake "
                                  "--preset release) and the roadcross-tools package",
                              "not_installed");
  return 1;
}
#endif

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "roadcross: ask a roadcross map where and how to cross a road.\n\n"
      "Examples:\n"
      "  roadcross info --db prague.gpkg\n"
      "  roadcross verify --db prague.gpkg --expect-id 3f1c...\n"
      "  roadcross install new-prague.gpkg /var/lib/robot/prague.gpkg\n"
      "  roadcross nearest --db prague.gpkg --lat 50.0755 --lon 14.4186\n"
      "  roadcross heading --db prague.gpkg --utm 458803 5546712 --json\n"
      "  roadcross assess --db prague.gpkg --lat 50.075769 --lon 14.416015\n"
      "  roadcross gap --db prague.gpkg --utm 458803 5546712 < vehicles.jsonl\n"
      "  roadcross simulate --lanes 2 --width 7 --maxspeed 50 --volume 150,300,600\n"
#ifdef ROADCROSS_WITH_VIZ
      "  roadcross render --db prague.gpkg -o prague.png\n"
      "  roadcross view --db prague.gpkg -o prague-view\n"
#endif
      ,
      "roadcross"};
  app.set_version_flag("--version", std::string("roadcross ") + roadcross::kVersion);
  app.require_subcommand(1);
  std::vector<std::unique_ptr<roadcross::cli::Command>> commands;
  commands.push_back(std::make_unique<roadcross::cli::InfoCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::VerifyCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::InstallCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::NearestCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::HeadingCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::AssessCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::BetterCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::MonitorCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::BatchCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::GapCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::SimulateCommand>(app));
#ifdef ROADCROSS_WITH_VIZ
  // Listed here, run by roadcross-viz: every argument after the name (--help too) goes to it.
  std::vector<CLI::App*> viz_commands;
  for (const auto& viz : roadcross::cli::kVizCommands) {
    CLI::App* sub = app.add_subcommand(viz.name, viz.description);
    sub->prefix_command();
    sub->set_help_flag();
    viz_commands.push_back(sub);
  }
#endif
  if (const std::optional<int> status =
          roadcross::cli::parse_command_line(app, argc, argv, "roadcross")) {
    return *status;
  }
  for (const auto& command : commands) {
    if (command->app()->parsed()) return command->run();
  }
#ifdef ROADCROSS_WITH_VIZ
  for (CLI::App* sub : viz_commands) {
    if (sub->parsed()) return run_viz_command(sub->get_name(), sub->remaining());
  }
#endif
  return 1;
}
