// The offline viewer: the page, its script and the vendored Leaflet come from the executable
// (embedded at build time); the data is a script (browsers refuse fetch() of file:// URLs but
// load <script src> from them) holding only what the page draws and shows, as columns.
#include "roadcross/viz/view.hpp"

#include <cairo.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "hillshade.hpp"
#include "roadcross/files/atomic_file.hpp"
#include "roadcross/schema/reasons.hpp"
#include "roadcross/viz/colors.hpp"

namespace roadcross::viz {

namespace assets {
const std::vector<std::pair<std::string_view, std::string_view>>& embedded_files();
}  // namespace assets

namespace {

// Map data is untrusted: a name with invalid UTF-8 becomes U+FFFD on the page instead of
// aborting the writer.
template <class Json>
std::string compact_json(const Json& value) {
  return value.dump(-1, ' ', false, Json::error_handler_t::replace);
}

// Where the page's positions count from, centimetres in the map's UTM zone.
struct Origin {
  std::int64_t x_cm = 0, y_cm = 0;
};

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

// Values are carried as integers in the unit the page needs, so that it stays small: distances
// it shows in decimetres (what the eye reads of a sight distance), positions in centimetres (the
// page computes the runtime's answers from them: at 0.1 m a 10 m edge's direction would move by
// up to 0.6 degrees, at 0.01 m by 0.06).
std::int64_t decimetres(double metres) {
  return std::llround(metres * 10.0);
}
std::int64_t centimetres(double metres) {
  return std::llround(metres * 100.0);
}

nlohmann::json optional_decimetres(const std::optional<double>& metres) {
  return metres ? nlohmann::json(decimetres(*metres)) : nlohmann::json(nullptr);
}

nlohmann::json optional_number(const std::optional<int>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

nlohmann::json optional_flag(const std::optional<bool>& value) {
  return value ? nlohmann::json(*value ? 1 : 0) : nlohmann::json(nullptr);
}

/// Distinct strings, each stored once in the page; a column holds their indices.
class StringTable {
 public:
  StringTable() { index(""); }
  int index(const std::string& text) {
    const auto [it, added] = positions_.try_emplace(text, static_cast<int>(strings_.size()));
    if (added) strings_.push_back(text);
    return it->second;
  }
  const std::vector<std::string>& strings() const { return strings_; }

 private:
  std::map<std::string, int> positions_;
  std::vector<std::string> strings_;
};

std::string joined(const std::vector<std::string>& codes) {
  std::string out;
  for (const std::string& code : codes) out += (out.empty() ? "" : ",") + code;
  return out;
}

bool contains(const std::vector<std::string>& codes, std::string_view code) {
  return std::find(codes.begin(), codes.end(), code) != codes.end();
}

// How many codes at the end of assess_segment's reasons the runtime appends after
// NO_PAVEMENT_FAR_SIDE (LOW_SCORE, and OVERRIDE when the build did not store it): the page
// inserts NO_PAVEMENT_FAR_SIDE before them, where assess does.
int codes_after_pavement(const SegmentLayer& s) {
  const std::vector<std::string>& reasons = s.assessment.reasons;
  int tail = 0;
  if (!reasons.empty() && reasons.back() == "OVERRIDE" && !contains(s.stored_reasons, "OVERRIDE"))
    ++tail;
  if (static_cast<int>(reasons.size()) > tail &&
      reasons[reasons.size() - 1 - static_cast<std::size_t>(tail)] == "LOW_SCORE")
    ++tail;
  return tail;
}

// The segments as columns (one array per property, entry i for segment i) with what the page
// draws, shows and needs to answer assess, better_place and road_heading as the runtime does.
nlohmann::json segments_json(const MapLayers& layers, const Origin& origin, StringTable& strings) {
  std::unordered_map<std::int64_t, int> node_index;
  const auto node = [&](std::int64_t id) {
    return node_index.try_emplace(id, static_cast<int>(node_index.size())).first->second;
  };
  nlohmann::json fid = nlohmann::json::array(), count = nlohmann::json::array(),
                 xy = nlohmann::json::array(), from = nlohmann::json::array(),
                 to = nlohmann::json::array(), length_cm = nlohmann::json::array();
  nlohmann::json name = nlohmann::json::array(), highway = nlohmann::json::array(),
                 suitable = nlohmann::json::array(), decide = nlohmann::json::array(),
                 offered = nlohmann::json::array(), score = nlohmann::json::array(),
                 context = nlohmann::json::array(), rank = nlohmann::json::array();
  nlohmann::json sight_forward = nlohmann::json::array(), sight_backward = nlohmann::json::array(),
                 required_sight = nlohmann::json::array(), junction = nlohmann::json::array(),
                 radius = nlohmann::json::array(), designated = nlohmann::json::array(),
                 kerb_too_high = nlohmann::json::array(), left = nlohmann::json::array(),
                 right = nlohmann::json::array(), reasons = nlohmann::json::array(),
                 stored = nlohmann::json::array(), tail = nlohmann::json::array();
  for (const SegmentLayer& s : layers.segments) {
    const Assessment& a = s.assessment;
    fid.push_back(s.fid);
    count.push_back(s.line.size());
    // The first point from the origin, the others from the point before (short numbers).
    std::int64_t x = origin.x_cm, y = origin.y_cm;
    for (const schema::PlanePoint& p : s.line) {
      const std::int64_t px = centimetres(p.x), py = centimetres(p.y);
      xy.push_back(px - x);
      xy.push_back(py - y);
      x = px;
      y = py;
    }
    from.push_back(node(s.from_node_id));
    to.push_back(node(s.to_node_id));
    length_cm.push_back(std::llround(a.road.segment_length_m * 100.0));
    name.push_back(strings.index(a.road.name));
    highway.push_back(strings.index(a.road.highway));
    suitable.push_back(a.suitable ? 1 : 0);
    decide.push_back(strings.index(s.deciding_reason));
    // better_place never offers what can never be crossed, nor a place near a junction.
    const bool never = s.verdict.not_crossable_class || s.verdict.tunnel || s.verdict.no_crossing;
    offered.push_back(never || contains(s.stored_reasons, "NEAR_JUNCTION") ? 0 : 1);
    score.push_back(optional_number(a.score));
    context.push_back(optional_number(a.context_score));
    rank.push_back(optional_number(a.rank));
    sight_forward.push_back(optional_decimetres(a.sight_forward_m));
    sight_backward.push_back(optional_decimetres(a.sight_backward_m));
    required_sight.push_back(optional_decimetres(a.required_sight_m));
    junction.push_back(optional_decimetres(a.junction_distance_m));
    radius.push_back(optional_decimetres(a.radius_m));
    designated.push_back(a.crossing_distance_m && *a.crossing_distance_m <= 5.0 ? 1 : 0);
    kerb_too_high.push_back(contains(a.reasons, "KERB_TOO_HIGH") ? 1 : 0);
    left.push_back(optional_flag(a.sidewalk_left));
    right.push_back(optional_flag(a.sidewalk_right));
    reasons.push_back(strings.index(joined(a.reasons)));
    stored.push_back(strings.index(joined(s.stored_reasons)));
    tail.push_back(codes_after_pavement(s));
  }
  return {{"fid", fid},
          {"count", count},
          {"xy_cm", xy},
          {"from", from},
          {"to", to},
          {"length_cm", length_cm},
          {"name", name},
          {"highway", highway},
          {"suitable", suitable},
          {"decide", decide},
          {"offered", offered},
          {"score", score},
          {"context", context},
          {"rank", rank},
          {"sight_forward_dm", sight_forward},
          {"sight_backward_dm", sight_backward},
          {"required_sight_dm", required_sight},
          {"junction_dm", junction},
          {"radius_dm", radius},
          {"designated", designated},
          {"kerb_too_high", kerb_too_high},
          {"sidewalk_left", left},
          {"sidewalk_right", right},
          {"reasons", reasons},
          {"stored_reasons", stored},
          {"codes_after_pavement", tail}};
}

nlohmann::json crossings_json(const MapLayers& layers, const Origin& origin, StringTable& strings) {
  nlohmann::json xy = nlohmann::json::array(), type = nlohmann::json::array();
  for (const CrossingLayer& c : layers.crossings) {
    if (!c.designated) continue;
    xy.push_back(centimetres(c.point.x) - origin.x_cm);
    xy.push_back(centimetres(c.point.y) - origin.y_cm);
    type.push_back(strings.index(c.crossing_type));
  }
  return {{"xy_cm", xy}, {"type", type}};
}

nlohmann::ordered_json meta_json(const MapLayers& layers, const Origin& origin,
                                 const nlohmann::ordered_json& hillshade) {
  nlohmann::ordered_json meta;
  meta["db"] = std::filesystem::path(layers.info.path).filename().string();
  meta["epsg"] = layers.info.epsg;
  meta["utm_zone"] = layers.info.zone.zone;
  meta["utm_northern"] = layers.info.zone.northern;
  meta["origin_cm"] = {origin.x_cm, origin.y_cm};
  const Assessment* any = layers.segments.empty() ? nullptr : &layers.segments[0].assessment;
  meta["threshold"] = any ? any->threshold : 20.0;
  meta["valid_distance_m"] = any ? any->valid_distance_m : 10.0;
  meta["max_distance_m"] = kMaxDistanceM;
  meta["search_radius_m"] = BetterPlaceOptions{}.search_radius_m;
  meta["max_candidates"] = BetterPlaceOptions{}.max_candidates;
  meta["colors"] = {{"suitable", kSuitableColor.hex()}, {"unsuitable", kUnsuitableColor.hex()}};
  nlohmann::ordered_json reason_colors;
  for (std::string_view code : reason_color_codes())
    reason_colors[std::string(code)] = reason_color(code).hex();
  meta["reason_colors"] = reason_colors;
  meta["attribution"] = "\u00a9 OpenStreetMap contributors";
  meta["hillshade"] = hillshade;
  nlohmann::ordered_json reasons;
  for (const schema::ReasonSpec& reason : schema::kReasons)
    reasons[std::string(reason.code)] = std::string(reason.sentence);
  meta["reasons"] = reasons;
  return meta;
}

std::string data_script(const MapLayers& layers, const nlohmann::ordered_json& hillshade) {
  const Origin origin{centimetres(layers.area.min_e_m), centimetres(layers.area.min_n_m)};
  StringTable strings;
  const nlohmann::json segments = segments_json(layers, origin, strings);
  const nlohmann::json crossings = crossings_json(layers, origin, strings);
  const std::string json = "{\"meta\":" + compact_json(meta_json(layers, origin, hillshade)) +
                           ",\"strings\":" + compact_json(nlohmann::json(strings.strings())) +
                           ",\"segments\":" + compact_json(segments) +
                           ",\"crossings\":" + compact_json(crossings) + "}";
  // A JSON text inside JSON.parse: browsers parse JSON several times faster than the same data
  // as a JavaScript literal.
  return "// Generated by roadcross view: the map's segments and designated crossings as columns,\n"
         "// UTM positions in centimetres from meta.origin_cm (docs/user-guide.md, \"view\").\n"
         "window.ROADCROSS_DATA = JSON.parse(" +
         compact_json(nlohmann::json(json)) + ");\n";
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
  staged.add("data.js", data_script(layers, hillshade));
  ViewSummary summary;
  summary.files = staged.commit();
  folder.keep();
  summary.segments = layers.segments.size();
  summary.crossings = layers.crossings.size();
  return summary;
}

}  // namespace roadcross::viz
