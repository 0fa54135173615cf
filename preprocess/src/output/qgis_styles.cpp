#include "roadcross/preprocess/output/qgis_styles.hpp"

#include <cstdio>

#include "roadcross/preprocess/output/terrain_coverage.hpp"
#include "roadcross/schema/schema.hpp"

namespace roadcross::preprocess {

namespace {

std::string sql_quote(const std::string& text) {
  std::string out = "'";
  for (char c : text) {
    if (c == '\'') out += '\'';
    out += c;
  }
  return out + "'";
}

std::string xml_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

/// A rule of a rule-based renderer: its label, QGIS filter expression ("ELSE" for the rest) and
/// the colour it draws in ("R,G,B,A"). QGIS draws every rule that matches, so the filters must
/// exclude each other.
struct Rule {
  std::string label;
  std::string filter;
  std::string color;
};

std::string line_symbol(std::size_t index, const std::string& color) {
  return "<symbol type=\"line\" name=\"" + std::to_string(index) +
         "\" alpha=\"1\" clip_to_extent=\"1\" force_rhr=\"0\"><layer class=\"SimpleLine\" "
         "enabled=\"1\" locked=\"0\" pass=\"0\"><Option type=\"Map\">"
         "<Option type=\"QString\" name=\"line_color\" value=\"" +
         color +
         "\"/><Option type=\"QString\" name=\"line_width\" value=\"1.2\"/>"
         "<Option type=\"QString\" name=\"line_width_unit\" value=\"MM\"/>"
         "<Option type=\"QString\" name=\"capstyle\" value=\"round\"/>"
         "<Option type=\"QString\" name=\"joinstyle\" value=\"round\"/>"
         "</Option></layer></symbol>";
}

std::string marker_symbol(std::size_t index, const std::string& color) {
  return "<symbol type=\"marker\" name=\"" + std::to_string(index) +
         "\" alpha=\"1\" clip_to_extent=\"1\" force_rhr=\"0\"><layer class=\"SimpleMarker\" "
         "enabled=\"1\" locked=\"0\" pass=\"0\"><Option type=\"Map\">"
         "<Option type=\"QString\" name=\"name\" value=\"circle\"/>"
         "<Option type=\"QString\" name=\"color\" value=\"" +
         color +
         "\"/><Option type=\"QString\" name=\"outline_color\" value=\"35,35,35,255\"/>"
         "<Option type=\"QString\" name=\"outline_width\" value=\"0.3\"/>"
         "<Option type=\"QString\" name=\"size\" value=\"2.6\"/>"
         "<Option type=\"QString\" name=\"size_unit\" value=\"MM\"/>"
         "</Option></layer></symbol>";
}

std::string rule_based_qml(const std::vector<Rule>& rules, bool lines) {
  std::string qml =
      "<!DOCTYPE qgis PUBLIC 'http://mrcc.com/qgis.dtd' 'SYSTEM'>\n<qgis version=\"3.22.16\" "
      "styleCategories=\"Symbology\"><renderer-v2 type=\"RuleRenderer\" symbollevels=\"0\" "
      "enableorderby=\"0\" forceraster=\"0\"><rules key=\"root\">";
  for (std::size_t i = 0; i < rules.size(); ++i) {
    qml += "<rule key=\"r" + std::to_string(i) + "\" label=\"" + xml_escape(rules[i].label) +
           "\" symbol=\"" + std::to_string(i) + "\" filter=\"" + xml_escape(rules[i].filter) +
           "\"/>";
  }
  qml += "</rules><symbols>";
  for (std::size_t i = 0; i < rules.size(); ++i) {
    qml += lines ? line_symbol(i, rules[i].color) : marker_symbol(i, rules[i].color);
  }
  return qml + "</symbols></renderer-v2></qgis>\n";
}

// Colours of the suitable/unsuitable pair and the rank classes: ColorBrewer RdYlGn, as the
// PNG renderer (viz/src/colors.cpp) draws them.
constexpr const char* kSuitableColor = "26,150,65,255";
constexpr const char* kUnsuitableColor = "215,25,28,255";

/// By the stored verdict (the `suitable` column: the runtime's judge under the map's defaults).
std::string segments_by_suitability() {
  return rule_based_qml({{"suitable to cross", "\"suitable\"", kSuitableColor},
                         {"not suitable", "ELSE", kUnsuitableColor}},
                        true);
}

std::string segments_by_rank() {
  return rule_based_qml({{"rank 0-2 (best)", "\"rank\" <= 2", "26,150,65,255"},
                         {"rank 3-5", "\"rank\" >= 3 AND \"rank\" <= 5", "166,217,106,255"},
                         {"rank 6-8", "\"rank\" >= 6 AND \"rank\" <= 8", "255,255,191,255"},
                         {"rank 9-11", "\"rank\" >= 9 AND \"rank\" <= 11", "253,174,97,255"},
                         {"rank 12-14 (worst)", "\"rank\" >= 12", "215,25,28,255"},
                         {"no rank", "ELSE", "150,150,150,255"}},
                        true);
}

std::string crossings_by_kind() {
  return rule_based_qml(
      {{"traffic signals", "\"signals\"", "43,131,186,255"},
       {"designated (zebra, marked)", "\"designated\" AND NOT \"signals\"", "255,255,255,255"},
       {"informal or none", "ELSE", "150,150,150,255"}},
      false);
}

/// The terrain as a hillshade (light from the north-west, 45 degrees up): a renderer that needs
/// no elevation range.
std::string terrain_hillshade() {
  return "<!DOCTYPE qgis PUBLIC 'http://mrcc.com/qgis.dtd' 'SYSTEM'>\n<qgis version=\"3.22.16\" "
         "styleCategories=\"Symbology\"><pipe><rasterrenderer type=\"hillshade\" band=\"1\" "
         "zfactor=\"1\" azimuth=\"315\" angle=\"45\" multidirection=\"0\" opacity=\"1\" "
         "alphaBand=\"-1\"/></pipe></qgis>\n";
}

}  // namespace

std::vector<std::string> qgis_style_statements(const std::string& last_change) {
  std::vector<std::string> statements = {
      // QGIS's own layout of the table (no AUTOINCREMENT: rows are numbered 1.. either way).
      "CREATE TABLE layer_styles (id INTEGER PRIMARY KEY NOT NULL, f_table_catalog TEXT(256), "
      "f_table_schema TEXT(256), f_table_name TEXT(256), f_geometry_column TEXT(256), styleName "
      "TEXT(30), styleQML TEXT, styleSLD TEXT, useAsDefault BOOLEAN, description TEXT, owner "
      "TEXT(30), ui TEXT(30), update_time DATETIME)",
      "INSERT INTO gpkg_contents (table_name, data_type, identifier, description, last_change) "
      "VALUES ('layer_styles', 'attributes', 'layer_styles', 'default styles for QGIS (QML)', " +
          sql_quote(last_change) + ")",
  };
  struct Style {
    std::string table, geometry_column, name, qml, description;
    bool is_default;
  };
  const std::string geom(schema::kGeometryColumn);
  const std::vector<Style> styles = {
      {std::string(schema::kSegmentsTable), geom, "suitable", segments_by_suitability(),
       "green where the runtime judges the place suitable under the map's default thresholds, "
       "red where not",
       true},
      {std::string(schema::kSegmentsTable), geom, "rank", segments_by_rank(),
       "rank 0 (best) .. 14 (worst) in five classes", false},
      {std::string(schema::kCrossingsTable), geom, "crossings", crossings_by_kind(),
       "crossings: blue with traffic signals, white designated, grey informal", true},
      {kTerrainTable, "", "hillshade", terrain_hillshade(), "terrain as a hillshade", true},
  };
  for (const Style& s : styles) {
    statements.push_back(
        "INSERT INTO layer_styles (f_table_catalog, f_table_schema, f_table_name, "
        "f_geometry_column, styleName, styleQML, styleSLD, useAsDefault, description, owner, ui, "
        "update_time) VALUES ('', '', " +
        sql_quote(s.table) + ", " + sql_quote(s.geometry_column) + ", " + sql_quote(s.name) + ", " +
        sql_quote(s.qml) + ", '', " + (s.is_default ? "1" : "0") + ", " + sql_quote(s.description) +
        ", '', '', " + sql_quote(last_change) + ")");
  }
  return statements;
}

}  // namespace roadcross::preprocess
