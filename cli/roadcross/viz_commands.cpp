#include "viz_commands.hpp"

#include <cstdio>
#include <exception>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_conventions.hpp"
#include "json_output.hpp"
#include "viz_command_list.hpp"

namespace roadcross::cli {

namespace {

constexpr const char* kBboxHelp =
    "only the area MINLON,MINLAT,MAXLON,MAXLAT (WGS84 degrees, as osmium extract -b)";

std::optional<viz::LonLatBox> bbox_or_none(const std::string& text) {
  if (text.empty()) return std::nullopt;
  return viz::parse_bbox(text);
}

// Every viz error is a sentence for the user: print it and fail.
template <typename Work>
int report_errors(const char* command, Work&& work) {
  try {
    return work();
  } catch (const std::exception& e) {
    print_error(std::string("roadcross ") + command, e.what(), "error");
    return 1;
  }
}

}  // namespace

RenderCommand::RenderCommand(CLI::App& parent) {
  app_ = parent.add_subcommand(kVizCommands[0].name, kVizCommands[0].description);
  app_->add_option("--db", options_.db_path, "roadcross GeoPackage")->required();
  app_->add_option("-o,--output", options_.output_path, "PNG to write")->required();
  app_->add_option("--bbox", bbox_, kBboxHelp);
  app_->add_option("--width", options_.width_px, "picture width in pixels (200..10000)")
      ->capture_default_str();
  app_->add_option("--color-by", color_by_, "suitable, rank, landform, context or reason")
      ->capture_default_str();
  app_->add_flag("--no-street-names", no_street_names_,
                 "draw no street names (by default they go along the roads where they fit)");
  app_->add_flag("--json", json_, "print a JSON summary (size, extent, metres per pixel)");
  app_->footer(
      "Example:\n  roadcross render --db prague.gpkg -o prague.png --width 1600 --color-by rank");
}

int RenderCommand::run() {
  return report_errors("render", [&] {
    const std::optional<viz::ColorBy> by = viz::parse_color_by(color_by_);
    if (!by) {
      throw std::invalid_argument("unknown --color-by '" + color_by_ +
                                  "' (expected suitable, rank, landform, context or reason)");
    }
    options_.color_by = *by;
    options_.bbox = bbox_or_none(bbox_);
    options_.street_names = !no_street_names_;
    const viz::RenderSummary s = viz::render_png(options_);
    if (json_) {
      nlohmann::ordered_json out;
      out["output"] = options_.output_path;
      out["world_file"] = s.world_file;
      out["width_px"] = s.width_px;
      out["height_px"] = s.height_px;
      out["map_height_px"] = s.map_height_px;
      out["metres_per_px"] = s.metres_per_px;
      out["extent_utm_m"] = {s.area.min_e_m, s.area.min_n_m, s.area.max_e_m, s.area.max_n_m};
      out["segments"] = s.segments;
      out["designated_crossings"] = s.crossings;
      out["hillshade"] = s.hillshade;
      out["street_names"] = s.street_names;
      std::cout << json_text(out, 2) << "\n";
    } else {
      std::printf("wrote %s (%d x %d px, %.2f m/px, %zu segments, %zu crossings%s)\n",
                  options_.output_path.c_str(), s.width_px, s.height_px, s.metres_per_px,
                  s.segments, s.crossings, s.hillshade ? ", hillshade" : "");
    }
    return 0;
  });
}

ExportCommand::ExportCommand(CLI::App& parent) {
  app_ = parent.add_subcommand(kVizCommands[1].name, kVizCommands[1].description);
  app_->add_option("--db", options_.db_path, "roadcross GeoPackage")->required();
  app_->add_option("-o,--output", options_.output_path, "file to write")->required();
  app_->add_option("--format", options_.format, "output format (geojson)")->capture_default_str();
  app_->add_option("--layer", options_.layer, "segments or crossings")->capture_default_str();
  app_->add_option("--bbox", bbox_, kBboxHelp);
  app_->footer(
      "Example:\n  roadcross export --db prague.gpkg --format geojson -o prague.geojson\n"
      "Same geometry and columns as:\n"
      "  ogr2ogr -f GeoJSON -t_srs EPSG:4326 -lco RFC7946=YES out.geojson prague.gpkg segments");
}

int ExportCommand::run() {
  return report_errors("export", [&] {
    options_.bbox = bbox_or_none(bbox_);
    const viz::ExportSummary s = viz::export_features(options_);
    std::printf("wrote %s (%zu %s)\n", options_.output_path.c_str(), s.features,
                options_.layer.c_str());
    return 0;
  });
}

ViewCommand::ViewCommand(CLI::App& parent) {
  app_ = parent.add_subcommand(kVizCommands[2].name, kVizCommands[2].description);
  app_->add_option("--db", options_.db_path, "roadcross GeoPackage")->required();
  app_->add_option("-o,--output", options_.output_dir, "folder to write (created if missing)")
      ->required();
  app_->add_option("--bbox", bbox_, kBboxHelp);
  app_->footer(
      "Example:\n  roadcross view --db prague.gpkg -o prague-view && xdg-open "
      "prague-view/index.html\n"
      "Open index.html#LAT,LON to assess a place on load.");
}

int ViewCommand::run() {
  return report_errors("view", [&] {
    options_.bbox = bbox_or_none(bbox_);
    const viz::ViewSummary s = viz::write_view(options_);
    std::printf("wrote %s/index.html (%zu segments, %zu crossings, %zu files)\n",
                options_.output_dir.c_str(), s.segments, s.crossings, s.files.size());
    return 0;
  });
}

}  // namespace roadcross::cli
