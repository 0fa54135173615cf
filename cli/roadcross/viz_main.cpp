// roadcross-viz: the drawing subcommands of roadcross (render, export, view). Users run them as
// `roadcross render ...`, which hands its arguments on to this program; it is a program of its
// own so that `roadcross` does not load Cairo and GDAL for every query.
#include <CLI/CLI.hpp>

#include <memory>
#include <vector>

#include "cli_conventions.hpp"
#include "roadcross/version.hpp"
#include "viz_commands.hpp"

int main(int argc, char** argv) {
  // Named "roadcross": its usage lines and messages read as those of `roadcross render` etc.
  CLI::App app{
      "roadcross-viz: the drawing subcommands of roadcross, run as `roadcross render`, "
      "`roadcross export` and `roadcross view`.",
      "roadcross"};
  app.set_version_flag("--version", std::string("roadcross-viz ") + roadcross::kVersion);
  app.require_subcommand(1);
  std::vector<std::unique_ptr<roadcross::cli::Command>> commands;
  commands.push_back(std::make_unique<roadcross::cli::RenderCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::ExportCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::ViewCommand>(app));
  if (const std::optional<int> status =
          roadcross::cli::parse_command_line(app, argc, argv, "roadcross")) {
    return *status;
  }
  for (const auto& command : commands) {
    if (command->app()->parsed()) return command->run();
  }
  return 1;
}
