// GeoJSON export with OGR: the table's columns as they are in the DB, geometries transformed to
// WGS84 (lon, lat; RFC 7946), plus the runtime's judgement of each segment. Equivalent to
//   ogr2ogr -f GeoJSON -t_srs EPSG:4326 -lco RFC7946=YES OUT.geojson DB.gpkg segments
// with the properties fid, suitable and assess_reasons added.
#include "roadcross/viz/export.hpp"

#include <cpl_conv.h>
#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <memory>
#include <stdexcept>

#include "roadcross/files/atomic_file.hpp"
#include "roadcross/geo.hpp"

namespace roadcross::viz {

namespace {

using DatasetPtr = std::unique_ptr<GDALDataset, decltype(&GDALClose)>;

// Opens the DB with OGR; call after Map::open, which says what is wrong with a file that is not
// a roadcross map better than GDAL can.
DatasetPtr open_db(const std::string& path) {
  GDALAllRegister();
  GDALDataset* ds =
      GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr);
  if (!ds) throw std::runtime_error(path + ": GDAL cannot open it as a GeoPackage");
  return DatasetPtr(ds, GDALClose);
}

void create_field(OGRLayer& out, OGRFieldDefn& field) {
  if (out.CreateField(&field) != OGRERR_NONE)
    throw std::runtime_error("cannot create field " + std::string(field.GetNameRef()));
}

// Where the runtime's judgement goes in the output's fields.
struct JudgementFields {
  int suitable = -1;
  int reasons = -1;
};

// Adds the source's fields, then fid and (for segments) the runtime's judgement: suitable (the
// stored column of that name since schema version 4, filled with the runtime's answer) and
// assess_reasons.
JudgementFields define_fields(OGRLayer& out, OGRFeatureDefn& in, bool judged) {
  for (int i = 0; i < in.GetFieldCount(); ++i) create_field(out, *in.GetFieldDefn(i));
  OGRFieldDefn fid("fid", OFTInteger64);
  create_field(out, fid);
  JudgementFields fields;
  if (!judged) return fields;
  fields.suitable = in.GetFieldIndex("suitable");
  int next = in.GetFieldCount() + 1;
  if (fields.suitable < 0) {
    OGRFieldDefn suitable("suitable", OFTInteger);
    suitable.SetSubType(OFSTBoolean);
    create_field(out, suitable);
    fields.suitable = next++;
  }
  OGRFieldDefn reasons("assess_reasons", OFTString);
  create_field(out, reasons);
  fields.reasons = next;
  return fields;
}

std::string join(const std::vector<std::string>& codes) {
  std::string out;
  for (const std::string& c : codes) out += (out.empty() ? "" : ",") + c;
  return out;
}

std::size_t copy_features(OGRLayer& in, OGRLayer& out, OGRCoordinateTransformation& to_wgs84,
                          Map* judge, const JudgementFields& fields) {
  std::size_t count = 0;
  OGRFeatureDefn* out_defn = out.GetLayerDefn();
  const int n_in = in.GetLayerDefn()->GetFieldCount();
  in.ResetReading();
  for (std::unique_ptr<OGRFeature> f(in.GetNextFeature()); f; f.reset(in.GetNextFeature())) {
    OGRFeature g(out_defn);
    for (int i = 0; i < n_in; ++i) {
      if (f->IsFieldSetAndNotNull(i)) {
        g.SetField(i, f->GetRawFieldRef(i));
      } else {
        g.SetFieldNull(i);
      }
    }
    g.SetField(n_in, static_cast<GIntBig>(f->GetFID()));
    if (judge) {
      Result<Assessment> a = judge->assess_segment(f->GetFID());
      if (!a.ok()) throw std::runtime_error(a.status.message);
      g.SetField(fields.suitable, a->suitable ? 1 : 0);
      g.SetField(fields.reasons, join(a->reasons).c_str());
    }
    if (OGRGeometry* geom = f->GetGeometryRef()) {
      std::unique_ptr<OGRGeometry> copy(geom->clone());
      if (copy->transform(&to_wgs84) != OGRERR_NONE)
        throw std::runtime_error("cannot transform feature " + std::to_string(f->GetFID()));
      g.SetGeometryDirectly(copy.release());
    }
    g.SetFID(f->GetFID());
    if (out.CreateFeature(&g) != OGRERR_NONE)
      throw std::runtime_error("cannot write feature " + std::to_string(f->GetFID()));
    ++count;
  }
  return count;
}

// Writes the GeoJSON to `path` (a file or a /vsimem/ name).
ExportSummary write_geojson(const ExportOptions& options, const std::string& path) {
  if (options.format != "geojson")
    throw std::invalid_argument("--format '" + options.format + "': only geojson is supported");
  if (options.layer != "segments" && options.layer != "crossings")
    throw std::invalid_argument("--layer '" + options.layer + "': expected segments or crossings");
  Result<Map> map = Map::open(options.db_path);
  if (!map.ok()) throw std::runtime_error(map.status.message);
  DatasetPtr db = open_db(options.db_path);
  OGRLayer* in = db->GetLayerByName(options.layer.c_str());
  if (!in) throw std::runtime_error(options.db_path + ": no table '" + options.layer + "'");
  if (options.bbox) {
    const UtmBox box = bbox_in_map(*options.bbox, map->info());
    in->SetSpatialFilterRect(box.min_e_m, box.min_n_m, box.max_e_m, box.max_n_m);
  }
  OGRSpatialReference wgs84;
  wgs84.importFromEPSG(4326);
  wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> to_wgs84(
      OGRCreateCoordinateTransformation(in->GetSpatialRef(), &wgs84));
  if (!to_wgs84) throw std::runtime_error(options.db_path + ": cannot transform to WGS84");

  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GeoJSON");
  DatasetPtr out(driver->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr), GDALClose);
  if (!out) throw std::runtime_error("cannot write " + options.output_path);
  // RFC 7946: lon/lat WGS84 without a crs member; 7 decimals of a degree is about 1 cm.
  char** layer_options = CSLSetNameValue(nullptr, "RFC7946", "YES");
  layer_options = CSLSetNameValue(layer_options, "COORDINATE_PRECISION", "7");
  OGRLayer* layer =
      out->CreateLayer(options.layer.c_str(), &wgs84, in->GetGeomType(), layer_options);
  CSLDestroy(layer_options);
  if (!layer) throw std::runtime_error("cannot write " + options.output_path);
  const bool judged = options.layer == "segments";
  const JudgementFields fields = define_fields(*layer, *in->GetLayerDefn(), judged);
  ExportSummary summary;
  summary.features = copy_features(*in, *layer, *to_wgs84, judged ? &*map : nullptr, fields);
  out.reset();  // flushes and closes the file
  return summary;
}

}  // namespace

ExportSummary export_features(const ExportOptions& options) {
  files::AtomicFile output(options.output_path);
  // GDAL's GeoJSON writer does not report a failed write (a full disk), so the text is made in
  // memory and written here, where every write and the final flush are checked.
  ExportSummary summary;
  output.append(export_geojson_text(options, &summary));
  output.commit();
  return summary;
}

std::string export_geojson_text(const ExportOptions& options, ExportSummary* summary) {
  const std::string path = "/vsimem/roadcross_export_" + options.layer + ".geojson";
  ExportSummary s = write_geojson(options, path);
  vsi_l_offset length = 0;
  GByte* bytes = VSIGetMemFileBuffer(path.c_str(), &length, FALSE);
  std::string text(reinterpret_cast<const char*>(bytes), static_cast<std::size_t>(length));
  VSIUnlink(path.c_str());
  if (summary) *summary = s;
  return text;
}

}  // namespace roadcross::viz
