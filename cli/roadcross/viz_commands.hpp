// The subcommands that draw a map (render, export, view), run by the program roadcross-viz
// (viz_main.cpp): they link Cairo and GDAL through roadcross::viz, whose loading would slow
// every `roadcross` call (docs/performance.md, "CLI start-up"). `roadcross render ...` hands its
// arguments on to `roadcross-viz render ...` (main.cpp). Full build only.
#pragma once

#include <optional>
#include <string>

#include "commands.hpp"
#include "roadcross/viz/export.hpp"
#include "roadcross/viz/render.hpp"
#include "roadcross/viz/view.hpp"

namespace roadcross::cli {

/// roadcross render: a PNG of the segments coloured by a cost term, over a hillshade.
class RenderCommand : public Command {
 public:
  explicit RenderCommand(CLI::App& parent);
  int run() override;

 private:
  viz::RenderOptions options_;
  std::string bbox_, color_by_ = "suitable";
  bool json_ = false;
  bool no_street_names_ = false;
};

/// roadcross export: a feature table as GeoJSON in WGS84, every term a property.
class ExportCommand : public Command {
 public:
  explicit ExportCommand(CLI::App& parent);
  int run() override;

 private:
  viz::ExportOptions options_;
  std::string bbox_;
};

/// roadcross view: a self-contained offline HTML page of the map.
class ViewCommand : public Command {
 public:
  explicit ViewCommand(CLI::App& parent);
  int run() override;

 private:
  viz::ViewOptions options_;
  std::string bbox_;
};

}  // namespace roadcross::cli
