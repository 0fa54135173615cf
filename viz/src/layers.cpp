// Reading what a picture draws: segment geometries (SQLite) and their judgement (runtime).
#include "roadcross/viz/layers.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "roadcross/geo.hpp"
#include "roadcross/schema/reasons.hpp"
#include "roadcross/schema/schema.hpp"
#include "roadcross/schema/sqlite.hpp"
#include "roadcross/schema/verdict.hpp"

namespace roadcross::viz {

namespace {

std::string format_box(const LonLatBox& b) {
  char text[128];
  std::snprintf(text, sizeof text, "%.6f,%.6f,%.6f,%.6f", b.min_lon_deg, b.min_lat_deg,
                b.max_lon_deg, b.max_lat_deg);
  return text;
}

LonLatBox map_lon_lat_box(const MapInfo& info) {
  const geo::LatLon sw = geo::utm_to_wgs84(info.min_easting_m, info.min_northing_m, info.zone);
  const geo::LatLon ne = geo::utm_to_wgs84(info.max_easting_m, info.max_northing_m, info.zone);
  return {sw.lon_deg, sw.lat_deg, ne.lon_deg, ne.lat_deg};
}

bool has_table(sqlite::Database& db, std::string_view name) {
  auto query = db.prepare("SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = ?1");
  query.bind(1, name);
  query.step();
  return query.column_int64(0) > 0;
}

void require_table(sqlite::Database& db, const std::string& path, std::string_view name) {
  if (!has_table(db, name)) {
    throw std::runtime_error(path + ": no table '" + std::string(name) +
                             "' (not a complete roadcross map; rebuild it with roadcross-build)");
  }
}

bool meets(const UtmBox& box, const schema::Envelope& e) {
  return e.max_x >= box.min_e_m && e.min_x <= box.max_e_m && e.max_y >= box.min_n_m &&
         e.min_y <= box.max_n_m;
}

std::vector<std::string> split_codes(const std::string& codes) {
  std::vector<std::string> out;
  std::stringstream in(codes);
  for (std::string code; std::getline(in, code, ',');) {
    if (!code.empty()) out.push_back(code);
  }
  return out;
}

// The map's LIMITED_VISIBILITY rule (param.sight.limited_visibility_unsuitable, default on).
bool limited_visibility_forbids(const MapInfo& info) {
  for (const auto& [key, value] : info.metadata) {
    if (key == schema::meta::kLimitedVisibilityUnsuitableParam) return value != "0";
  }
  return true;
}

std::string deciding_reason_of(const schema::Verdict& verdict, const Assessment& a) {
  if (a.suitable) return "";
  const std::vector<std::string_view> codes = schema::forbidding_codes(verdict);
  if (!codes.empty()) return std::string(codes.front());
  // The segment passes the judge: a robot rule forbids it (assess_segment knows no side, so
  // only the kerb can).
  for (const std::string& code : a.reasons) {
    const schema::ReasonSpec* spec = schema::find_reason(code);
    if (spec && spec->makes_unsuitable && !spec->stored_by_build) return code;
  }
  return "LOW_SCORE";  // unreachable while assess_segment and the judge agree
}

std::vector<SegmentLayer> read_segments(sqlite::Database& db, Map& map, const UtmBox& area) {
  using C = schema::SegmentColumn;
  static const schema::SegmentSelection kColumns(
      {C::from_node_id, C::to_node_id, C::score, C::context_score, C::reasons, C::tunnel,
       C::override_no_crossing, C::override_force_suitable},
      2);
  const MapInfo& info = map.info();
  const bool limited_visibility_unsuitable = limited_visibility_forbids(info);
  std::vector<SegmentLayer> out;
  auto rows = db.prepare("SELECT fid, geom, " + kColumns.sql("", info.schema_version) + " FROM " +
                         std::string(schema::kSegmentsTable) + " ORDER BY fid");
  while (rows.step()) {
    SegmentLayer s;
    s.fid = rows.column_int64(0);
    if (!schema::decode_linestring(rows.column_blob(1), s.line)) {
      throw std::runtime_error("segment " + std::to_string(s.fid) + " has a malformed geometry");
    }
    if (!meets(area, schema::envelope_of(s.line))) continue;
    Result<Assessment> a = map.assess_segment(s.fid);
    if (!a.ok()) throw std::runtime_error(a.status.message);
    s.assessment = std::move(*a);
    s.from_node_id = rows.column_int64(kColumns[C::from_node_id]);
    s.to_node_id = rows.column_int64(kColumns[C::to_node_id]);
    const std::string reasons = rows.column_text(kColumns[C::reasons]);
    s.verdict =
        schema::judge_segment({s.assessment.score, s.assessment.context_score, reasons,
                               rows.column_int64(kColumns[C::tunnel]) != 0,
                               rows.column_int64(kColumns[C::override_no_crossing]) != 0,
                               rows.column_int64(kColumns[C::override_force_suitable]) != 0},
                              {s.assessment.threshold, limited_visibility_unsuitable});
    s.deciding_reason = deciding_reason_of(s.verdict, s.assessment);
    s.stored_reasons = split_codes(reasons);
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<CrossingLayer> read_crossings(sqlite::Database& db, const UtmBox& area) {
  std::vector<CrossingLayer> out;
  auto rows = db.prepare("SELECT fid, geom, designated, crossing_type FROM " +
                         std::string(schema::kCrossingsTable) + " ORDER BY fid");
  while (rows.step()) {
    const std::optional<schema::PlanePoint> p = schema::decode_point(rows.column_blob(1));
    if (!p) continue;
    if (p->x < area.min_e_m || p->x > area.max_e_m || p->y < area.min_n_m || p->y > area.max_n_m)
      continue;
    out.push_back({rows.column_int64(0), *p, rows.column_int64(2) != 0, rows.column_text(3)});
  }
  return out;
}

bool has_terrain_coverage(sqlite::Database& db) {
  auto query = db.prepare(
      "SELECT count(*) FROM gpkg_contents WHERE table_name = ?1 AND data_type = "
      "'2d-gridded-coverage'");
  query.bind(1, std::string_view(kTerrainTable));
  query.step();
  return query.column_int64(0) > 0;
}

}  // namespace

bool UtmBox::intersects(const UtmBox& other) const noexcept {
  return other.max_e_m >= min_e_m && other.min_e_m <= max_e_m && other.max_n_m >= min_n_m &&
         other.min_n_m <= max_n_m;
}

LonLatBox parse_bbox(const std::string& text) {
  double v[4];
  std::istringstream in(text);
  for (int i = 0; i < 4; ++i) {
    char comma = ',';
    if (i > 0) in >> comma;
    if (!(in >> v[i]) || comma != ',') {
      throw std::invalid_argument("--bbox '" + text +
                                  "': expected MINLON,MINLAT,MAXLON,MAXLAT in degrees");
    }
  }
  in >> std::ws;
  if (!in.eof()) {
    throw std::invalid_argument("--bbox '" + text + "': trailing text after four numbers");
  }
  const LonLatBox b{v[0], v[1], v[2], v[3]};
  if (!(b.min_lon_deg < b.max_lon_deg && b.min_lat_deg < b.max_lat_deg)) {
    throw std::invalid_argument("--bbox '" + text +
                                "': MINLON must be < MAXLON and MINLAT < MAXLAT");
  }
  if (!geo::is_valid_utm_lat_lon(b.min_lat_deg, b.min_lon_deg) ||
      !geo::is_valid_utm_lat_lon(b.max_lat_deg, b.max_lon_deg)) {
    throw std::invalid_argument("--bbox '" + text +
                                "': longitudes must be in -180..180, latitudes in -80..84");
  }
  return b;
}

UtmBox bbox_in_map(const LonLatBox& bbox, const MapInfo& info) {
  UtmBox box{INFINITY, INFINITY, -INFINITY, -INFINITY};
  const LonLatBox map_box = map_lon_lat_box(info);
  const std::string outside = "--bbox " + format_box(bbox) + " lies outside the map (it covers " +
                              format_box(map_box) + ")";
  try {
    for (double lon : {bbox.min_lon_deg, bbox.max_lon_deg}) {
      for (double lat : {bbox.min_lat_deg, bbox.max_lat_deg}) {
        const geo::UtmPoint p = geo::wgs84_to_utm(lat, lon, info.zone);
        box.min_e_m = std::min(box.min_e_m, p.easting_m);
        box.max_e_m = std::max(box.max_e_m, p.easting_m);
        box.min_n_m = std::min(box.min_n_m, p.northing_m);
        box.max_n_m = std::max(box.max_n_m, p.northing_m);
      }
    }
  } catch (const std::invalid_argument&) {
    throw std::invalid_argument(outside);  // too far from the map's zone to project
  }
  const UtmBox extent{info.min_easting_m, info.min_northing_m, info.max_easting_m,
                      info.max_northing_m};
  if (!box.intersects(extent)) throw std::invalid_argument(outside);
  return box;
}

MapLayers load_layers(const std::string& db_path, const std::optional<LonLatBox>& bbox) {
  Result<Map> map = Map::open(db_path);
  if (!map.ok()) throw std::runtime_error(map.status.message);
  sqlite::Database db(db_path, SQLITE_OPEN_READONLY);
  require_table(db, db_path, schema::kSegmentsTable);
  require_table(db, db_path, schema::kCrossingsTable);
  MapLayers layers;
  layers.info = map->info();
  if (layers.info.segment_count == 0)
    throw std::runtime_error(db_path + ": the map has no segments");
  layers.area = bbox ? bbox_in_map(*bbox, layers.info)
                     : UtmBox{layers.info.min_easting_m, layers.info.min_northing_m,
                              layers.info.max_easting_m, layers.info.max_northing_m};
  layers.segments = read_segments(db, *map, layers.area);
  layers.crossings = read_crossings(db, layers.area);
  layers.has_terrain = has_table(db, "gpkg_contents") && has_terrain_coverage(db);
  return layers;
}

}  // namespace roadcross::viz
