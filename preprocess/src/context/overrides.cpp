#include "roadcross/preprocess/context/overrides.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string_view>

#include "roadcross/preprocess/common/errors.hpp"

namespace roadcross::preprocess {

namespace {

using nlohmann::json;

/// Throws InputError naming the file and the feature.
[[noreturn]] void fail(const std::string& name, std::size_t feature, const std::string& what) {
  throw InputError(name, "feature " + std::to_string(feature) + ": " + what);
}

LonLatRing parse_ring(const json& ring, const std::string& name, std::size_t feature) {
  if (!ring.is_array() || ring.size() < 4) {
    fail(name, feature, "a polygon ring must be an array of at least 4 positions");
  }
  LonLatRing out;
  for (const json& position : ring) {
    if (!position.is_array() || position.size() < 2 || position.size() > 3 ||
        !position[0].is_number() || !position[1].is_number()) {
      fail(name, feature, "a position must be [longitude, latitude] in degrees");
    }
    const double lon = position[0].get<double>(), lat = position[1].get<double>();
    if (!(lon >= -180.0 && lon <= 180.0 && lat >= -90.0 && lat <= 90.0)) {
      fail(name, feature,
           "position [" + position[0].dump() + ", " + position[1].dump() +
               "] is not a WGS84 longitude/latitude");
    }
    out.push_back({lat, lon});
  }
  if (out.front().lat_deg != out.back().lat_deg || out.front().lon_deg != out.back().lon_deg) {
    fail(name, feature, "a polygon ring must be closed (first position = last position)");
  }
  double twice_area = 0.0;  // shoelace, in degrees: only its being non-zero matters
  for (std::size_t i = 1; i < out.size(); ++i) {
    twice_area += out[i - 1].lon_deg * out[i].lat_deg - out[i].lon_deg * out[i - 1].lat_deg;
  }
  if (std::abs(twice_area) < 1e-18) fail(name, feature, "a polygon ring has no area");
  return out;
}

LonLatPolygon parse_polygon(const json& rings, const std::string& name, std::size_t feature) {
  if (!rings.is_array() || rings.empty()) {
    fail(name, feature, "Polygon coordinates must be a non-empty array of rings");
  }
  LonLatPolygon polygon;
  for (const json& ring : rings) polygon.push_back(parse_ring(ring, name, feature));
  return polygon;
}

void parse_geometry(const json& geometry, Override& out, const std::string& name) {
  const std::size_t f = out.feature_index;
  if (geometry.is_null()) return;
  if (!geometry.is_object() || !geometry.contains("type") || !geometry["type"].is_string() ||
      !geometry.contains("coordinates")) {
    fail(name, f, "geometry must be a GeoJSON object with \"type\" and \"coordinates\"");
  }
  const std::string type = geometry["type"].get<std::string>();
  const json& coordinates = geometry["coordinates"];
  if (type == "Polygon") {
    out.polygons.push_back(parse_polygon(coordinates, name, f));
  } else if (type == "MultiPolygon") {
    if (!coordinates.is_array() || coordinates.empty()) {
      fail(name, f, "MultiPolygon coordinates must be a non-empty array of polygons");
    }
    for (const json& polygon : coordinates) out.polygons.push_back(parse_polygon(polygon, name, f));
  } else {
    fail(name, f, "geometry type " + type + " is not Polygon or MultiPolygon");
  }
}

std::int64_t way_id(const json& value, const std::string& name, std::size_t feature) {
  if (!value.is_number_integer() ||
      (value.is_number_unsigned() &&
       value.get<std::uint64_t>() > std::uint64_t(std::numeric_limits<std::int64_t>::max())) ||
      value.get<std::int64_t>() <= 0) {
    fail(name, feature,
         "osm_way_id must be a positive integer or an array of them, got " + value.dump());
  }
  return value.get<std::int64_t>();
}

/// context_delta: an integer in [-kMaxContextDelta, kMaxContextDelta]. (JSON's unsigned
/// integers above INT64_MAX must not wrap: 2^64 - 1 is not -1.)
int context_delta(const json& value, const std::string& name, std::size_t feature) {
  const bool in_range =
      (value.is_number_unsigned() && value.get<std::uint64_t>() <= kMaxContextDelta) ||
      (value.is_number_integer() && !value.is_number_unsigned() &&
       value.get<std::int64_t>() >= -kMaxContextDelta &&
       value.get<std::int64_t>() <= kMaxContextDelta);
  if (!in_range) {
    fail(name, feature,
         "context_delta must be an integer in [-" + std::to_string(kMaxContextDelta) + ", " +
             std::to_string(kMaxContextDelta) + "], got " + value.dump());
  }
  return static_cast<int>(value.get<std::int64_t>());
}

bool true_or_false(const json& value, const char* key, const std::string& name, std::size_t f) {
  if (!value.is_boolean())
    fail(name, f, std::string(key) + " must be true or false, got " + value.dump());
  return value.get<bool>();
}

void parse_properties(const json& properties, Override& out, const std::string& name) {
  const std::size_t f = out.feature_index;
  if (properties.is_null()) return;
  if (!properties.is_object()) fail(name, f, "properties must be an object");
  for (const auto& [key, value] : properties.items()) {
    if (key == "osm_way_id") {
      if (value.is_array()) {
        if (value.empty()) fail(name, f, "osm_way_id must not be an empty array");
        for (const json& id : value) out.osm_way_ids.push_back(way_id(id, name, f));
      } else {
        out.osm_way_ids.push_back(way_id(value, name, f));
      }
    } else if (key == "context_delta") {
      out.context_delta = context_delta(value, name, f);
    } else if (key == "no_crossing") {
      out.no_crossing = true_or_false(value, "no_crossing", name, f);
    } else if (key == "force_suitable") {
      out.force_suitable = true_or_false(value, "force_suitable", name, f);
    } else if (key == "note") {
      if (!value.is_string()) fail(name, f, "note must be a string, got " + value.dump());
      out.note = value.get<std::string>();
      if (out.note.size() > kMaxOverrideNoteBytes) {
        fail(name, f,
             "note is " + std::to_string(out.note.size()) + " bytes long; at most " +
                 std::to_string(kMaxOverrideNoteBytes) + " (it is stored on every segment)");
      }
    } else {
      fail(name, f,
           "unknown property \"" + key +
               "\" (known: osm_way_id, context_delta, no_crossing, force_suitable, note)");
    }
  }
}

Override parse_feature(const json& feature, std::size_t index, const std::string& name) {
  Override out;
  out.source = name;
  out.feature_index = index;
  if (!feature.is_object() || feature.value("type", json()) != "Feature") {
    fail(name, index, "not a GeoJSON Feature (\"type\": \"Feature\")");
  }
  parse_geometry(feature.value("geometry", json()), out, name);
  parse_properties(feature.value("properties", json()), out, name);
  if (out.polygons.empty() && out.osm_way_ids.empty()) {
    fail(name, index, "selects nothing: give a Polygon/MultiPolygon geometry or osm_way_id");
  }
  if (out.context_delta == 0 && !out.no_crossing && !out.force_suitable) {
    fail(name, index, "has no effect: give context_delta, no_crossing or force_suitable");
  }
  if (out.no_crossing && out.force_suitable) {
    fail(name, index, "no_crossing and force_suitable contradict each other");
  }
  if (out.note.empty()) out.note = "override feature " + std::to_string(index);
  return out;
}

std::vector<std::vector<PlanePoint>> project_rings(const LonLatPolygon& polygon,
                                                   geo::UtmZone zone) {
  std::vector<std::vector<PlanePoint>> rings;
  for (const LonLatRing& ring : polygon) {
    std::vector<PlanePoint>& out = rings.emplace_back();
    for (const geo::LatLon& p : ring) {
      const geo::UtmPoint u = geo::wgs84_to_utm(p.lat_deg, p.lon_deg, zone);
      out.push_back({u.easting_m, u.northing_m});
    }
  }
  return rings;
}

bool inside(PlanePoint p, const std::vector<std::vector<PlanePoint>>& rings) {
  bool in = false;  // even-odd over all rings: holes flip it back
  for (const auto& ring : rings) {
    for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
      const PlanePoint a = ring[i], b = ring[j];
      if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x)
        in = !in;
    }
  }
  return in;
}

bool edges_cross(PlanePoint p1, PlanePoint p2, PlanePoint q1, PlanePoint q2) {
  const auto side = [](PlanePoint a, PlanePoint b, PlanePoint c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  };
  const double d1 = side(q1, q2, p1), d2 = side(q1, q2, p2);
  const double d3 = side(p1, p2, q1), d4 = side(p1, p2, q2);
  return ((d1 >= 0) != (d2 >= 0) || d1 == 0 || d2 == 0) &&
         ((d3 >= 0) != (d4 >= 0) || d3 == 0 || d4 == 0) && !(d1 == 0 && d2 == 0 && d3 == 0);
}

/// `earlier; note`, at most kMaxSegmentNoteBytes (cut at a UTF-8 character boundary).
std::string joined_note(const std::string* earlier, const std::string& note) {
  std::string joined = earlier ? *earlier + "; " + note : note;
  if (joined.size() <= kMaxSegmentNoteBytes) return joined;
  constexpr std::string_view kEllipsis = "...";
  std::size_t cut = kMaxSegmentNoteBytes - kEllipsis.size();
  while (cut > 0 && (static_cast<unsigned char>(joined[cut]) & 0xC0) == 0x80) --cut;
  joined.resize(cut);
  return joined + std::string(kEllipsis);
}

void apply_one(RoadGraph& graph, Segment& s, const Override& o) {
  if (s.context_score) {
    // Summed in 64 bits and clamped: thousands of overlapping features must not overflow int
    // (undefined behaviour), here or where a reader adds the score to it.
    const std::int64_t sum = std::int64_t{*s.context_score} + o.context_delta;
    s.context_score =
        static_cast<int>(std::clamp<std::int64_t>(sum, -kMaxContextScore, kMaxContextScore));
  }
  if (o.no_crossing) {
    s.override_no_crossing = true;
    s.reasons.add("OVERRIDE");
  }
  if (o.force_suitable) s.override_force_suitable = true;
  const std::string* note = graph.override_note(s);
  graph.set_override_note(s, graph.text.intern(joined_note(note, o.note)));
}

}  // namespace

std::vector<Override> parse_overrides(const std::string& text, const std::string& name) {
  json document;
  try {
    document = json::parse(text);
  } catch (const json::exception& e) {
    // parse_error, and out_of_range for a number beyond a double (999E99999): found by the
    // overrides fuzz target (tests/fuzz/regressions/overrides/).
    throw InputError(name, std::string("not valid JSON: ") + e.what());
  }
  if (!document.is_object() || document.value("type", json()) != "FeatureCollection" ||
      !document.contains("features") || !document["features"].is_array()) {
    throw InputError(name, "not a GeoJSON FeatureCollection with a \"features\" array");
  }
  std::vector<Override> out;
  const json& features = document["features"];
  for (std::size_t i = 0; i < features.size(); ++i)
    out.push_back(parse_feature(features[i], i, name));
  return out;
}

std::vector<Override> read_overrides(const std::string& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::is_regular_file(status)) {
    throw InputError(path, std::filesystem::is_directory(status)
                               ? "is a folder, not an overrides file"
                               : "cannot open the overrides file (not a regular file)");
  }
  if (std::filesystem::file_size(path, ec) > kMaxOverridesFileBytes) {
    throw InputError(path, "larger than " + std::to_string(kMaxOverridesFileBytes >> 20) +
                               " MiB; an overrides file is a list of polygons and notes");
  }
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path, "cannot open the overrides file");
  std::stringstream text;
  text << file.rdbuf();
  return parse_overrides(text.str(), path);
}

bool polyline_touches_polygon(std::span<const PlanePoint> line,
                              const std::vector<std::vector<PlanePoint>>& rings) {
  for (const PlanePoint& p : line) {
    if (inside(p, rings)) return true;
  }
  for (std::size_t i = 1; i < line.size(); ++i) {
    for (const auto& ring : rings) {
      for (std::size_t k = 1; k < ring.size(); ++k) {
        if (edges_cross(line[i - 1], line[i], ring[k - 1], ring[k])) return true;
      }
    }
  }
  return false;
}

std::vector<std::uint64_t> apply_overrides(RoadGraph& graph,
                                           const std::vector<Override>& overrides) {
  std::vector<std::uint64_t> touched(overrides.size(), 0);
  for (std::size_t i = 0; i < overrides.size(); ++i) {
    const Override& o = overrides[i];
    std::vector<std::vector<std::vector<PlanePoint>>> polygons;
    std::vector<schema::Envelope> boxes;
    for (const LonLatPolygon& polygon : o.polygons) {
      try {
        polygons.push_back(project_rings(polygon, graph.zone));
      } catch (const std::invalid_argument& e) {
        fail(o.source, o.feature_index,
             std::string("polygon outside the map's UTM zone: ") + e.what());
      }
      boxes.push_back(schema::envelope_of(polygons.back().front()));
    }
    for (Segment& s : graph.segments) {
      const bool way_ok =
          o.osm_way_ids.empty() || std::find(o.osm_way_ids.begin(), o.osm_way_ids.end(),
                                             graph.osm_way_id(s)) != o.osm_way_ids.end();
      if (!way_ok) continue;
      bool area_ok = polygons.empty();
      const schema::Envelope e = schema::envelope_of(graph.line(s));
      for (std::size_t k = 0; k < polygons.size() && !area_ok; ++k) {
        const schema::Envelope& b = boxes[k];
        if (e.max_x < b.min_x || e.min_x > b.max_x || e.max_y < b.min_y || e.min_y > b.max_y)
          continue;
        area_ok = polyline_touches_polygon(graph.line(s), polygons[k]);
      }
      if (!area_ok) continue;
      apply_one(graph, s, o);
      ++touched[i];
    }
  }
  return touched;
}

}  // namespace roadcross::preprocess
