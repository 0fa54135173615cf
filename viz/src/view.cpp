// The offline viewer: the page, its script and the vendored Leaflet come from the executable
// (embedded at build time); the data is the GeoJSON export wrapped in a script, since browsers
// refuse fetch() of file:// URLs but load <script src> from them.
#include "roadcross/viz/view.hpp"

#include <cairo.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string_view>
#include <utility>
#include <vector>

#include "hillshade.hpp"
#include "roadcross/files/atomic_file.hpp"
#include "roadcross/schema/reasons.hpp"
#include "roadcross/viz/colors.hpp"
#include "roadcross/viz/export.hpp"

namespace roadcross::viz {

namespace assets {
const std::vector<std::pair<std::string_view, std::string_view>>& embedded_files();
}  // namespace assets

namespace {

// Distance within which assess looks for a road (AssessOptions' default).
constexpr double kMaxDistanceM = AssessOptions{}.max_distance_m;

/// The folders a view writes into, created when missing; the ones this run created are
/// removed again if the view fails, so that a failure leaves no folder behind.
class OutputFolder {
 public:
  explicit OutputFolder(const std::string& dir) {
    if (dir.empty()) throw std::runtime_error("no output folder given (an empty name)");
    create(dir);
    create((std::filesystem::path(dir) / "leaflet").string());
  }
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;
  ~OutputFolder() {
    if (kept_) return;
    for (auto it = created_.rbegin(); it != created_.rend(); ++it) ::rmdir(it->c_str());
  }
  void keep() { kept_ = true; }

 private:
  void create(const std::string& path) {
    struct stat st {};
    if (::lstat(path.c_str(), &st) == 0) {
      if (!S_ISDIR(st.st_mode)) {
        throw std::runtime_error("cannot write " + path + ": it exists and is not a folder");
      }
      return;
    }
    if (::mkdir(path.c_str(), 0777) != 0) {
      throw std::runtime_error("cannot create folder " + path + ": " + std::strerror(errno));
    }
    created_.push_back(path);
  }

  std::vector<std::string> created_;
  bool kept_ = false;
};

/// The view's files, each complete in a temporary file beside its target before any is renamed
/// into place: a failure while writing (a full disk) leaves the folder as it was.
class StagedFiles {
 public:
  explicit StagedFiles(std::filesystem::path dir) : dir_(std::move(dir)) {}

  /// A new temporary file for `name` (relative to the folder) to be written by the caller.
  files::AtomicFile& add(const std::string& name) {
    staged_.push_back(std::make_unique<files::AtomicFile>((dir_ / name).string()));
    names_.push_back(name);
    return *staged_.back();
  }
  void add(const std::string& name, std::string_view bytes) { add(name).append(bytes); }

  /// Renames every file into place once all are on disk; returns their names.
  std::vector<std::string> commit() {
    for (const auto& file : staged_) file->sync();
    for (const auto& file : staged_) file->commit();
    return names_;
  }

 private:
  std::filesystem::path dir_;
  std::vector<std::unique_ptr<files::AtomicFile>> staged_;
  std::vector<std::string> names_;
};

// Writes the hillshade, in Web Mercator as Leaflet draws it, to DIR/hillshade.png; its WGS84
// bounds for L.imageOverlay, or null when the DB holds no terrain.
nlohmann::ordered_json write_hillshade(const ViewOptions& options, const MapLayers& layers,
                                       StagedFiles& staged) {
  constexpr int kMaxWidthPx = 2000;
  if (!layers.has_terrain) return nullptr;
  std::optional<MercatorShade> shade =
      mercator_hillshade(options.db_path, layers.area, layers.info.zone, kMaxWidthPx);
  if (!shade) return nullptr;
  ShadeImage& image = shade->image;
  cairo_surface_t* surface = cairo_image_surface_create_for_data(
      reinterpret_cast<unsigned char*>(image.argb.data()), CAIRO_FORMAT_ARGB32, image.width,
      image.height, image.width * 4);
  files::AtomicFile& png = staged.add("hillshade.png");
  const cairo_status_t status = cairo_surface_write_to_png(surface, png.temp_path().c_str());
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS) {
    throw std::runtime_error("cannot write " + png.target_path() + ": " +
                             cairo_status_to_string(status));
  }
  return {
      {"file", "hillshade.png"},
      {"bounds",
       {{shade->south_lat_deg, shade->west_lon_deg}, {shade->north_lat_deg, shade->east_lon_deg}}}};
}

nlohmann::ordered_json meta_json(const MapLayers& layers, const nlohmann::ordered_json& hillshade) {
  nlohmann::ordered_json meta;
  meta["db"] = std::filesystem::path(layers.info.path).filename().string();
  meta["epsg"] = layers.info.epsg;
  const Assessment* any = layers.segments.empty() ? nullptr : &layers.segments[0].assessment;
  meta["threshold"] = any ? any->threshold : 20.0;
  meta["valid_distance_m"] = any ? any->valid_distance_m : 10.0;
  meta["max_distance_m"] = kMaxDistanceM;
  meta["colors"] = {{"suitable", kSuitableColor.hex()}, {"unsuitable", kUnsuitableColor.hex()}};
  meta["attribution"] = "\u00a9 OpenStreetMap contributors";
  meta["hillshade"] = hillshade;
  nlohmann::ordered_json reasons;
  for (const schema::ReasonSpec& reason : schema::kReasons)
    reasons[std::string(reason.code)] = std::string(reason.sentence);
  meta["reasons"] = reasons;
  return meta;
}

std::string data_script(const ViewOptions& options, const MapLayers& layers,
                        const nlohmann::ordered_json& hillshade) {
  ExportOptions segments{options.db_path, "", "geojson", "segments", options.bbox};
  ExportOptions crossings{options.db_path, "", "geojson", "crossings", options.bbox};
  return "// Generated by roadcross view: the map's segments and crossings (GeoJSON, WGS84).\n"
         "window.ROADCROSS_DATA = {\n\"meta\": " +
         meta_json(layers, hillshade)
             .dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) +
         ",\n\"segments\": " + export_geojson_text(segments) +
         ",\n\"crossings\": " + export_geojson_text(crossings) + "\n};\n";
}

}  // namespace

ViewSummary write_view(const ViewOptions& options) {
  // Read (and check the bbox) first: a failure leaves no empty folder behind.
  const MapLayers layers = load_layers(options.db_path, options.bbox);
  OutputFolder folder(options.output_dir);
  StagedFiles staged{std::filesystem::path(options.output_dir)};
  for (const auto& [name, bytes] : assets::embedded_files()) {
    staged.add(name == "view.html" ? "index.html" : std::string(name), bytes);
  }
  const nlohmann::ordered_json hillshade = write_hillshade(options, layers, staged);
  staged.add("data.js", data_script(options, layers, hillshade));
  ViewSummary summary;
  summary.files = staged.commit();
  folder.keep();
  summary.segments = layers.segments.size();
  summary.crossings = layers.crossings.size();
  return summary;
}

}  // namespace roadcross::viz
