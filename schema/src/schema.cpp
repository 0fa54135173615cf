#include "roadcross/schema/schema.hpp"

#include <stdexcept>

namespace roadcross::schema {

namespace {

std::vector<Column> make_segment_columns() {
  // Order matters: it is the table's order and SegmentColumn's. Later schema versions append.
  std::vector<Column> columns = {
      // Identity and topology (foundation).
      {"osm_way_id", "INTEGER NOT NULL", "OSM way the segment was cut from"},
      {"highway", "TEXT NOT NULL", "OSM highway=* value of the way"},
      {"name", "TEXT", "OSM name of the way, NULL when untagged"},
      {"length_m", "REAL NOT NULL", "length along the centreline, metres"},
      {"from_node_id", "INTEGER NOT NULL",
       "road-graph node at the first vertex: the OSM node id, or a negative id for a split point "
       "inside a way"},
      {"to_node_id", "INTEGER NOT NULL", "road-graph node at the last vertex (same convention)"},
      {"oneway", "BOOLEAN NOT NULL",
       "1 when the way is one-way (oneway=yes/1/true/-1, roundabout)"},
      {"tunnel", "BOOLEAN NOT NULL", "1 in a tunnel, building passage or covered=yes"},
      {"bridge", "BOOLEAN NOT NULL", "1 on a bridge"},
      // Geometry cost (road class, junctions, curvature).
      {"class_cost", "INTEGER", "road class cost 0..5 (primary 5 .. unclassified 1)"},
      {"junction_distance_m", "REAL",
       "distance along the road to the nearest junction (graph degree >= 3), metres; NULL when "
       "the connected road has no junction"},
      {"radius_m", "REAL", "smallest circumradius over the segment, metres (10000 = straight)"},
      {"curvature_level", "INTEGER", "0..5, 5 = at a junction"},
      {"curvature_cost", "INTEGER", "0..14, windowed over +-100 m of road"},
      // Terrain.
      {"elevation_m", "REAL", "terrain elevation at the segment midpoint, metres"},
      {"slope_deg", "REAL", "terrain slope at the midpoint, degrees"},
      {"grade_percent", "REAL", "road grade along the segment, percent"},
      {"tpi_small_m", "REAL", "topographic position index at the small scale, metres"},
      {"tpi_large_m", "REAL", "topographic position index at the large scale, metres"},
      {"landform", "TEXT", "Weiss (2001) landform class name"},
      {"elevation_cost", "INTEGER", "0..9, windowed over +-100 m of road"},
      // Context from OSM tags.
      {"maxspeed_kmh", "REAL", "speed limit used, km/h"},
      {"lanes", "INTEGER", "number of lanes used"},
      {"width_m", "REAL", "carriageway width used, metres"},
      {"context_score", "INTEGER", "context score from tags"},
      {"crossing_distance_m", "REAL",
       "distance along the road to the nearest designated crossing, metres"},
      {"context_defaulted", "TEXT", "comma-separated context inputs that took a default"},
      {"override_note", "TEXT", "note of the operator override applied to this segment"},
      {"override_no_crossing", "BOOLEAN NOT NULL DEFAULT 0",
       "1 when an operator override forbids crossing here (never suitable)"},
      {"override_force_suitable", "BOOLEAN NOT NULL DEFAULT 0",
       "1 when an operator override declares this segment suitable whatever its score"},
      // Result.
      {"rank", "INTEGER", "0..14, higher is worse"},
      {"score", "INTEGER", "15 - rank"},
      {"reasons", "TEXT", "comma-separated reason codes"},
      // Sight distance (schema version 2).
      {"sight_forward_m", "REAL",
       "sight distance along the road looking in the OSM way's direction (vehicles approaching "
       "from ahead), from the worse kerb, metres; NULL in tunnels"},
      {"sight_backward_m", "REAL",
       "sight distance looking against the way's direction (same convention), metres"},
      {"sight_min_m", "REAL", "the smaller of sight_forward_m and sight_backward_m, metres"},
      {"required_sight_m", "REAL",
       "distance a vehicle at the road's speed covers while the robot crosses, metres"},
      // Kerbs, refuge islands and pavements (schema version 3).
      {"kerb", "TEXT",
       "kerb=* value of the highest kerb at a crossing or kerb node on or within 5 m of the "
       "segment (raised, lowered, flush, rolled, no, ...; 'yes' for barrier=kerb without "
       "kerb=*); NULL when none is tagged"},
      {"kerb_height_m", "REAL",
       "height of that kerb: kerb:height, else the usual height of its kerb=* value (flush, no "
       "0; lowered, rolled 0.03; raised 0.12), metres; NULL when unknown"},
      {"crossing_island", "INTEGER",
       "1: the crossing here has a refuge island (crossing:island=yes, traffic_calming=island), "
       "0: crossing:island=no; NULL when unknown"},
      {"sidewalk_left", "INTEGER",
       "1: a pavement on the left of the OSM way's direction (sidewalk=*, sidewalk:left, "
       "sidewalk:both, or a footway=sidewalk way alongside), 0: tagged without one; NULL when "
       "unknown"},
      {"sidewalk_right", "INTEGER", "the same on the right of the way's direction"},
      // The verdict, stored for GIS users (schema version 4).
      {"suitable", "BOOLEAN",
       "1: the runtime calls the segment's centreline a suitable place to cross under the map's "
       "default thresholds and robot profile (roadcross assess_segment: the same judge), 0: not; "
       "a robot's own thresholds and its side of the road (NO_PAVEMENT_FAR_SIDE) may differ"},
  };
  for (Column& column : columns) {
    if (column.name.rfind("sight_", 0) == 0 || column.name == "required_sight_m") {
      column.since_version = 2;
    }
    if (column.name.rfind("kerb", 0) == 0 || column.name == "crossing_island" ||
        column.name.rfind("sidewalk_", 0) == 0) {
      column.since_version = 3;
    }
    if (column.name == "suitable") column.since_version = 4;
  }
  return columns;
}

}  // namespace

const std::vector<Column>& segment_columns() {
  static const std::vector<Column> columns = make_segment_columns();
  return columns;
}

const Column& column_spec(SegmentColumn column) {
  return segment_columns().at(static_cast<std::size_t>(column));
}

SegmentSelection::SegmentSelection(std::initializer_list<SegmentColumn> columns, int first_position)
    : columns_(columns), position_(kSegmentColumnCount, -1) {
  int position = first_position;
  for (SegmentColumn column : columns_) position_[static_cast<std::size_t>(column)] = position++;
}

std::string SegmentSelection::sql(std::string_view table_alias, int schema_version) const {
  std::string out;
  for (SegmentColumn column : columns_) {
    if (!out.empty()) out += ", ";
    const Column& spec = column_spec(column);
    if (spec.since_version > schema_version) {
      out += "NULL";
      continue;
    }
    if (!table_alias.empty()) out.append(table_alias).append(".");
    out += spec.name;
  }
  return out;
}

int SegmentSelection::operator[](SegmentColumn column) const {
  const int position = position_[static_cast<std::size_t>(column)];
  if (position < 0) {
    throw std::logic_error("segments column " + std::string(column_spec(column).name) +
                           " read but not selected");
  }
  return position;
}

const std::vector<Column>& crossing_columns() {
  static const std::vector<Column> columns = {
      {"osm_id", "INTEGER NOT NULL", "OSM id of the crossing node, or of the crossing way"},
      {"osm_type", "TEXT NOT NULL",
       "'node' (a crossing node on a road) or 'way' (where a "
       "footway=crossing / cycleway=crossing way meets a road)"},
      {"crossing_type", "TEXT NOT NULL",
       "crossing=* value (zebra, marked, uncontrolled, traffic_signals, unmarked, informal, no, "
       "...), else crossing_ref, else marked/unmarked from crossing:markings, else "
       "'unspecified'"},
      {"signals", "BOOLEAN NOT NULL", "1 when controlled by traffic signals"},
      {"designated", "BOOLEAN NOT NULL",
       "1 when it earns the crossing bonus (0 for crossing=informal and crossing=no)"},
      {"segment_id", "INTEGER NOT NULL", "fid of the segment the crossing lies on"},
  };
  return columns;
}

int utm_epsg(int zone, bool northern) {
  if (zone < 1 || zone > 60) throw std::invalid_argument("UTM zone must be in 1..60");
  return (northern ? 32600 : 32700) + zone;
}

std::string utm_wkt(int zone, bool northern) {
  const int epsg = utm_epsg(zone, northern);
  const int central_meridian_deg = 6 * zone - 183;
  const std::string name = "WGS 84 / UTM zone " + std::to_string(zone) + (northern ? "N" : "S");
  return "PROJCS[\"" + name +
         "\",GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563,"
         "AUTHORITY[\"EPSG\",\"7030\"]],AUTHORITY[\"EPSG\",\"6326\"]],PRIMEM[\"Greenwich\",0,"
         "AUTHORITY[\"EPSG\",\"8901\"]],UNIT[\"degree\",0.0174532925199433,AUTHORITY[\"EPSG\","
         "\"9122\"]],AUTHORITY[\"EPSG\",\"4326\"]],PROJECTION[\"Transverse_Mercator\"],"
         "PARAMETER[\"latitude_of_origin\",0],PARAMETER[\"central_meridian\"," +
         std::to_string(central_meridian_deg) +
         "],PARAMETER[\"scale_factor\",0.9996],PARAMETER[\"false_easting\",500000],"
         "PARAMETER[\"false_northing\"," +
         (northern ? std::string("0") : std::string("10000000")) +
         "],UNIT[\"metre\",1,AUTHORITY[\"EPSG\",\"9001\"]],AXIS[\"Easting\",EAST],"
         "AXIS[\"Northing\",NORTH],AUTHORITY[\"EPSG\",\"" +
         std::to_string(epsg) + "\"]]";
}

namespace {

std::string quote(std::string_view text) {
  std::string out = "'";
  for (char c : text) {
    if (c == '\'') out += '\'';
    out += c;
  }
  return out + "'";
}

std::string feature_table_ddl(std::string_view table, std::string_view geometry_type,
                              const std::vector<Column>& columns) {
  std::string ddl = "CREATE TABLE " + std::string(table) + " (fid INTEGER PRIMARY KEY NOT NULL, " +
                    std::string(kGeometryColumn) + " " + std::string(geometry_type) + " NOT NULL";
  for (const Column& column : columns) {
    ddl += ", " + std::string(column.name) + " " + std::string(column.sql_type);
  }
  return ddl + ")";
}

/// A feature table with its gpkg_contents and gpkg_geometry_columns rows, its R*Tree and the
/// R*Tree extension row: everything GeoPackage readers need to find it (spec 1.3, 1.1.3, F.3).
std::vector<std::string> feature_table_statements(std::string_view table, std::string_view rtree,
                                                  std::string_view geometry_type,
                                                  const std::vector<Column>& columns,
                                                  std::string_view description,
                                                  const std::string& srs,
                                                  std::string_view last_change) {
  return {
      feature_table_ddl(table, geometry_type, columns),
      "INSERT INTO gpkg_contents (table_name, data_type, identifier, description, last_change, "
      "srs_id) VALUES (" +
          quote(table) + ", 'features', " + quote(table) + ", " + quote(description) + ", " +
          quote(last_change) + ", " + srs + ")",
      "INSERT INTO gpkg_geometry_columns VALUES (" + quote(table) + ", " + quote(kGeometryColumn) +
          ", " + quote(geometry_type) + ", " + srs + ", 0, 0)",
      "CREATE VIRTUAL TABLE " + std::string(rtree) + " USING rtree(id, minx, maxx, miny, maxy)",
      "INSERT INTO gpkg_extensions VALUES (" + quote(table) + ", " + quote(kGeometryColumn) +
          ", 'gpkg_rtree_index', 'http://www.geopackage.org/spec120/#extension_rtree', "
          "'write-only')",
  };
}

/// One gpkg_data_columns row per attribute column of `table`: its description (with unit) for
/// GIS programs (GeoPackage schema extension, spec 1.3 F.9). `name` is the column's own name.
std::vector<std::string> data_column_statements(std::string_view table,
                                                const std::vector<Column>& columns) {
  std::vector<std::string> statements;
  const auto row = [&](std::string_view column, std::string_view description) {
    statements.push_back(
        "INSERT INTO gpkg_data_columns (table_name, column_name, name, title, "
        "description) VALUES (" +
        quote(table) + ", " + quote(column) + ", " + quote(column) + ", " + quote(column) + ", " +
        quote(description) + ")");
  };
  if (table == kMetadataTable) {
    row("id", "row number (GeoPackage wants an integer key; look rows up by key)");
  } else {
    row("fid", table == kSegmentsTable ? "feature id (segment_id in the runtime's answers)"
                                       : "feature id");
    row(kGeometryColumn, "geometry in the map's UTM zone, metres");
  }
  for (const Column& column : columns) row(column.name, column.description);
  return statements;
}

/// The six GeoPackage R*Tree triggers of `table`.geom (spec 1.3, F.3).
std::vector<std::string> rtree_triggers(const std::string& t, const std::string& r) {
  const std::string c(kGeometryColumn);
  const std::string bbox = "(NEW.fid, ST_MinX(NEW." + c + "), ST_MaxX(NEW." + c +
                           "), ST_MinY(NEW." + c + "), ST_MaxY(NEW." + c + "))";
  const std::string prefix = "CREATE TRIGGER " + r + "_";
  return {
      prefix + "insert AFTER INSERT ON " + t + " WHEN (new." + c +
          " NOT NULL AND NOT ST_IsEmpty(NEW." + c + ")) BEGIN INSERT OR REPLACE INTO " + r +
          " VALUES " + bbox + "; END",
      prefix + "update1 AFTER UPDATE OF " + c + " ON " + t + " WHEN OLD.fid = NEW.fid AND (NEW." +
          c + " NOTNULL AND NOT ST_IsEmpty(NEW." + c + ")) BEGIN INSERT OR REPLACE INTO " + r +
          " VALUES " + bbox + "; END",
      prefix + "update2 AFTER UPDATE OF " + c + " ON " + t + " WHEN OLD.fid = NEW.fid AND (NEW." +
          c + " ISNULL OR ST_IsEmpty(NEW." + c + ")) BEGIN DELETE FROM " + r +
          " WHERE id = OLD.fid; END",
      prefix + "update3 AFTER UPDATE ON " + t + " WHEN OLD.fid != NEW.fid AND (NEW." + c +
          " NOTNULL AND NOT ST_IsEmpty(NEW." + c + ")) BEGIN DELETE FROM " + r +
          " WHERE id = OLD.fid; INSERT OR REPLACE INTO " + r + " VALUES " + bbox + "; END",
      prefix + "update4 AFTER UPDATE ON " + t + " WHEN OLD.fid != NEW.fid AND (NEW." + c +
          " ISNULL OR ST_IsEmpty(NEW." + c + ")) BEGIN DELETE FROM " + r +
          " WHERE id IN (OLD.fid, NEW.fid); END",
      prefix + "delete AFTER DELETE ON " + t + " WHEN old." + c + " NOT NULL BEGIN DELETE FROM " +
          r + " WHERE id = OLD.fid; END",
  };
}

}  // namespace

std::vector<std::string> create_statements(int zone, bool northern, std::string_view last_change) {
  const int epsg = utm_epsg(zone, northern);
  const std::string srs = std::to_string(epsg);
  std::vector<std::string> statements = {
      "PRAGMA application_id = " + std::to_string(kGpkgApplicationId),
      "PRAGMA user_version = " + std::to_string(kGpkgUserVersion),
      // GeoPackage core tables (spec 1.3, clauses 1.1.2 and 1.1.3).
      "CREATE TABLE gpkg_spatial_ref_sys (srs_name TEXT NOT NULL, srs_id INTEGER PRIMARY KEY, "
      "organization TEXT NOT NULL, organization_coordsys_id INTEGER NOT NULL, definition TEXT NOT "
      "NULL, description TEXT)",
      "INSERT INTO gpkg_spatial_ref_sys VALUES ('Undefined cartesian SRS', -1, 'NONE', -1, "
      "'undefined', 'undefined cartesian coordinate reference system')",
      "INSERT INTO gpkg_spatial_ref_sys VALUES ('Undefined geographic SRS', 0, 'NONE', 0, "
      "'undefined', 'undefined geographic coordinate reference system')",
      "INSERT INTO gpkg_spatial_ref_sys VALUES ('WGS 84 geodetic', 4326, 'EPSG', 4326, "
      "'GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563,"
      "AUTHORITY[\"EPSG\",\"7030\"]],AUTHORITY[\"EPSG\",\"6326\"]],PRIMEM[\"Greenwich\",0,"
      "AUTHORITY[\"EPSG\",\"8901\"]],UNIT[\"degree\",0.0174532925199433,AUTHORITY[\"EPSG\","
      "\"9122\"]],AXIS[\"Latitude\",NORTH],AXIS[\"Longitude\",EAST],AUTHORITY[\"EPSG\","
      "\"4326\"]]', 'longitude/latitude coordinates in decimal degrees on the WGS 84 spheroid')",
      "INSERT INTO gpkg_spatial_ref_sys VALUES (" +
          quote("WGS 84 / UTM zone " + std::to_string(zone) + (northern ? "N" : "S")) + ", " + srs +
          ", 'EPSG', " + srs + ", " + quote(utm_wkt(zone, northern)) + ", NULL)",
      "CREATE TABLE gpkg_contents (table_name TEXT NOT NULL PRIMARY KEY, data_type TEXT NOT NULL, "
      "identifier TEXT UNIQUE, description TEXT DEFAULT '', last_change DATETIME NOT NULL "
      "DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ','now')), "
      "min_x DOUBLE, min_y DOUBLE, max_x DOUBLE, max_y DOUBLE, srs_id INTEGER, CONSTRAINT "
      "fk_gc_r_srs_id FOREIGN KEY (srs_id) REFERENCES gpkg_spatial_ref_sys(srs_id))",
      "CREATE TABLE gpkg_geometry_columns (table_name TEXT NOT NULL, column_name TEXT NOT NULL, "
      "geometry_type_name TEXT NOT NULL, srs_id INTEGER NOT NULL, z TINYINT NOT NULL, m TINYINT "
      "NOT NULL, CONSTRAINT pk_geom_cols PRIMARY KEY (table_name, column_name), CONSTRAINT "
      "uk_gc_table_name UNIQUE (table_name), CONSTRAINT fk_gc_tn FOREIGN KEY (table_name) "
      "REFERENCES gpkg_contents(table_name), CONSTRAINT fk_gc_srs FOREIGN KEY (srs_id) REFERENCES "
      "gpkg_spatial_ref_sys (srs_id))",
      "CREATE TABLE gpkg_extensions (table_name TEXT, column_name TEXT, extension_name TEXT NOT "
      "NULL, definition TEXT NOT NULL, scope TEXT NOT NULL, CONSTRAINT ge_tce UNIQUE "
      "(table_name, column_name, extension_name))",
      // roadcross tables: the metadata here, the feature tables appended below.
      // GeoPackage wants an INTEGER primary key on every attributes table (Req 119); readers
      // look rows up by key, which stays unique.
      "CREATE TABLE " + std::string(kMetadataTable) +
          " (id INTEGER PRIMARY KEY NOT NULL, key TEXT NOT NULL UNIQUE, value TEXT "
          "NOT NULL)",
      "INSERT INTO gpkg_contents (table_name, data_type, identifier, description, last_change) "
      "VALUES (" +
          quote(kMetadataTable) +
          ", 'attributes', 'roadcross_metadata', 'roadcross schema version, CRS, parameters and "
          "inputs', " +
          quote(last_change) + ")",
  };
  // The GeoPackage schema extension: what every column means, with its unit (spec 1.3, F.9).
  statements.push_back(
      "CREATE TABLE gpkg_data_columns (table_name TEXT NOT NULL, column_name TEXT NOT NULL, name "
      "TEXT, title TEXT, description TEXT, mime_type TEXT, constraint_name TEXT, CONSTRAINT "
      "pk_gdc PRIMARY KEY (table_name, column_name), CONSTRAINT gdc_tn UNIQUE (table_name, "
      "name))");
  statements.push_back(
      "CREATE TABLE gpkg_data_column_constraints (constraint_name TEXT NOT NULL, constraint_type "
      "TEXT NOT NULL, value TEXT, min NUMERIC, min_is_inclusive BOOLEAN, max NUMERIC, "
      "max_is_inclusive BOOLEAN, description TEXT, CONSTRAINT gdcc_ntv UNIQUE (constraint_name, "
      "constraint_type, value))");
  for (std::string_view table : {"gpkg_data_columns", "gpkg_data_column_constraints"}) {
    statements.push_back(
        "INSERT INTO gpkg_extensions VALUES (" + quote(table) +
        ", NULL, 'gpkg_schema', 'http://www.geopackage.org/spec/#extension_schema', "
        "'read-write')");
  }
  static const std::vector<Column> metadata_columns = {
      {"key", "", "what the value is: schema_version, utm_zone, param.<section>.<name>, ..."},
      {"value", "", "the value, as text"},
  };
  for (auto rows : {data_column_statements(kMetadataTable, metadata_columns),
                    data_column_statements(kSegmentsTable, segment_columns()),
                    data_column_statements(kCrossingsTable, crossing_columns())}) {
    for (std::string& statement : rows) statements.push_back(std::move(statement));
  }
  for (auto feature_table :
       {feature_table_statements(kSegmentsTable, kSegmentsRtree, "LINESTRING", segment_columns(),
                                 "road segments with crossing cost terms", srs, last_change),
        feature_table_statements(kCrossingsTable, kCrossingsRtree, "POINT", crossing_columns(),
                                 "designated road crossings", srs, last_change)}) {
    for (std::string& statement : feature_table) statements.push_back(std::move(statement));
  }
  return statements;
}

std::vector<std::string> rtree_trigger_statements() {
  std::vector<std::string> out =
      rtree_triggers(std::string(kSegmentsTable), std::string(kSegmentsRtree));
  for (std::string& statement :
       rtree_triggers(std::string(kCrossingsTable), std::string(kCrossingsRtree))) {
    out.push_back(std::move(statement));
  }
  return out;
}

}  // namespace roadcross::schema
