// roadcross: query a roadcross map before or during a mission.
#include <CLI/CLI.hpp>

#include <memory>
#include <vector>

#include "commands.hpp"
#ifdef ROADCROSS_WITH_VIZ
#include "viz_commands.hpp"
#endif
#include "roadcross/version.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "roadcross: ask a roadcross map where and how to cross a road.\n\n"
      "Examples:\n"
      "  roadcross info prague.gpkg\n"
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
  commands.push_back(std::make_unique<roadcross::cli::NearestCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::HeadingCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::AssessCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::BetterCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::MonitorCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::BatchCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::GapCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::SimulateCommand>(app));
#ifdef ROADCROSS_WITH_VIZ
  commands.push_back(std::make_unique<roadcross::cli::RenderCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::ExportCommand>(app));
  commands.push_back(std::make_unique<roadcross::cli::ViewCommand>(app));
#endif
  CLI11_PARSE(app, argc, argv);
  for (const auto& command : commands) {
    if (command->app()->parsed()) return command->run();
  }
  return 1;
}
