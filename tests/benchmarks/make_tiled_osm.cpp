// make_tiled_osm: makes large realistic inputs for scale benchmarks from a real extract by
// tiling copies of it side by side with fresh ids, and (optionally) a matching DEM mosaic.
//
//   make_tiled_osm INPUT.osm.pbf COPIES OUTPUT.osm.pbf [DEM_IN DEM_OUT.tif]
//
// Copy k (0-based) sits in column k % cols, row k / cols of a near-square grid. Ids are fresh and
// dense, as in a real planet file: an object's id is k * count + its rank among the input's
// objects of its type + 1 (sparse ids would make id-set based tools such as osmium tags-filter
// allocate for the whole id range), and stay sorted;
// its locations are shifted by whole DEM pixels (1/1200 degree for SRTM3) so that the DEM
// mosaic made from the same source window matches every copy exactly.
#include <gdal_priv.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <osmium/io/any_input.hpp>
#include <osmium/io/any_output.hpp>
#include <osmium/osm/box.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

constexpr double kPixelsPerDegree = 1200.0;  // SRTM 3 arc-second

struct Layout {
  int copies = 1;
  int columns = 1;
  osmium::Box source_box;       // of the input's nodes
  double tile_width_deg = 0.0;  // whole DEM pixels, with a small gap
  double tile_height_deg = 0.0;
  std::vector<std::int64_t> node_ids, way_ids, relation_ids;  // sorted input ids, for ranks

  double dlon(int k) const { return (k % columns) * tile_width_deg; }
  double dlat(int k) const { return (k / columns) * tile_height_deg; }
};

Layout plan(const osmium::memory::Buffer& input, int copies) {
  Layout layout;
  layout.copies = copies;
  layout.columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(copies))));
  for (const auto& object : input.select<osmium::OSMObject>()) {
    if (object.type() == osmium::item_type::node) {
      layout.source_box.extend(static_cast<const osmium::Node&>(object).location());
      layout.node_ids.push_back(object.id());
    } else if (object.type() == osmium::item_type::way) {
      layout.way_ids.push_back(object.id());
    } else {
      layout.relation_ids.push_back(object.id());
    }
  }
  for (auto* ids : {&layout.node_ids, &layout.way_ids, &layout.relation_ids})
    std::sort(ids->begin(), ids->end());
  const auto whole_pixels = [](double degrees) {
    return std::ceil(degrees * kPixelsPerDegree + 12) / kPixelsPerDegree;
  };
  layout.tile_width_deg =
      whole_pixels(layout.source_box.top_right().lon() - layout.source_box.bottom_left().lon());
  layout.tile_height_deg =
      whole_pixels(layout.source_box.top_right().lat() - layout.source_box.bottom_left().lat());
  return layout;
}

/// The fresh id of input object `id` of `type` in copy k. References to objects missing from
/// the input (members outside the extract) get ids past every copy's range.
std::int64_t shifted_id(osmium::item_type type, std::int64_t id, int k, const Layout& layout) {
  const std::vector<std::int64_t>& ids = type == osmium::item_type::node  ? layout.node_ids
                                         : type == osmium::item_type::way ? layout.way_ids
                                                                          : layout.relation_ids;
  const auto count = static_cast<std::int64_t>(ids.size());
  const auto it = std::lower_bound(ids.begin(), ids.end(), id);
  if (it == ids.end() || *it != id) return count * layout.copies + 1 + (id % 1000000007);
  return k * count + (it - ids.begin()) + 1;
}

/// Appends copy k of every object of `type` in `input` to `out`.
void append_copy(const osmium::memory::Buffer& input, osmium::item_type type, int k,
                 const Layout& layout, osmium::memory::Buffer& out) {
  for (const auto& object : input.select<osmium::OSMObject>()) {
    if (object.type() != type) continue;
    out.add_item(object);
    out.commit();
    auto& copy = out.get<osmium::OSMObject>(out.committed() - object.padded_size());
    copy.set_id(shifted_id(type, object.id(), k, layout));
    if (type == osmium::item_type::node) {
      auto& node = static_cast<osmium::Node&>(copy);
      const osmium::Location l = node.location();
      node.set_location(osmium::Location{l.lon() + layout.dlon(k), l.lat() + layout.dlat(k)});
    } else if (type == osmium::item_type::way) {
      for (auto& ref : static_cast<osmium::Way&>(copy).nodes()) {
        ref.set_ref(shifted_id(osmium::item_type::node, ref.ref(), k, layout));
      }
    } else {
      for (auto& member : static_cast<osmium::Relation&>(copy).members()) {
        member.set_ref(shifted_id(member.type(), member.ref(), k, layout));
      }
    }
  }
}

void write_osm(const osmium::memory::Buffer& input, const Layout& layout, const std::string& path) {
  osmium::io::Header header;
  header.set("generator", "roadcross make_tiled_osm");
  osmium::io::Writer writer{path, header, osmium::io::overwrite::allow};
  for (osmium::item_type type :
       {osmium::item_type::node, osmium::item_type::way, osmium::item_type::relation}) {
    for (int k = 0; k < layout.copies; ++k) {
      osmium::memory::Buffer out{input.committed() + 1024, osmium::memory::Buffer::auto_grow::yes};
      append_copy(input, type, k, layout, out);
      writer(std::move(out));
    }
  }
  writer.close();
}

/// A GeoTIFF (EPSG:4326) holding the source DEM's window around the extract once per copy.
void write_dem(const std::string& dem_in, const std::string& dem_out, const Layout& layout) {
  GDALAllRegister();
  auto* source = static_cast<GDALDataset*>(GDALOpen(dem_in.c_str(), GA_ReadOnly));
  if (!source) throw std::runtime_error(dem_in + ": cannot open DEM");
  double gt[6];
  source->GetGeoTransform(gt);
  GDALRasterBand* band = source->GetRasterBand(1);
  int has_nodata = 0;
  const double nodata = band->GetNoDataValue(&has_nodata);
  const int tile_cols = static_cast<int>(std::lround(layout.tile_width_deg / gt[1]));
  const int tile_rows = static_cast<int>(std::lround(layout.tile_height_deg / -gt[5]));
  // Window origin: the pixel containing the box's west/north edge, minus a 6-pixel margin.
  const int x0 = std::max(
      0, static_cast<int>(std::floor((layout.source_box.bottom_left().lon() - gt[0]) / gt[1])) - 6);
  const int y0 = std::max(
      0, static_cast<int>(std::floor((layout.source_box.top_right().lat() - gt[3]) / gt[5])) - 6);
  const int cols = std::min(tile_cols, band->GetXSize() - x0),
            rows = std::min(tile_rows, band->GetYSize() - y0);
  std::vector<float> window(static_cast<std::size_t>(cols) * rows);
  if (band->RasterIO(GF_Read, x0, y0, cols, rows, window.data(), cols, rows, GDT_Float32, 0, 0) !=
      CE_None) {
    throw std::runtime_error(dem_in + ": read failed");
  }
  const int grid_rows = (layout.copies + layout.columns - 1) / layout.columns;
  const int out_cols = layout.columns * tile_cols, out_rows = grid_rows * tile_rows;
  GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
  char** options = nullptr;
  options = CSLSetNameValue(options, "COMPRESS", "DEFLATE");
  options = CSLSetNameValue(options, "TILED", "YES");
  options = CSLSetNameValue(options, "BIGTIFF", "IF_SAFER");
  GDALDataset* out = gtiff->Create(dem_out.c_str(), out_cols, out_rows, 1, GDT_Float32, options);
  CSLDestroy(options);
  if (!out) throw std::runtime_error(dem_out + ": cannot create");
  // Row 0 of the copies is the southernmost: the mosaic's top-left is the last row's window.
  const double west = gt[0] + x0 * gt[1];
  const double north_of_source = gt[3] + y0 * gt[5];
  double out_gt[6] = {west, gt[1], 0.0, north_of_source + (grid_rows - 1) * layout.tile_height_deg,
                      0.0,  gt[5]};
  out->SetGeoTransform(out_gt);
  out->SetProjection(source->GetProjectionRef());
  GDALRasterBand* out_band = out->GetRasterBand(1);
  out_band->SetNoDataValue(has_nodata ? nodata : -32768.0);
  std::vector<float> fill(static_cast<std::size_t>(out_cols),
                          has_nodata ? static_cast<float>(nodata) : -32768.0f);
  for (int r = 0; r < out_rows; ++r) {
    if (out_band->RasterIO(GF_Write, 0, r, out_cols, 1, fill.data(), out_cols, 1, GDT_Float32, 0,
                           0) != CE_None) {
      throw std::runtime_error(dem_out + ": write failed");
    }
  }
  for (int k = 0; k < layout.copies; ++k) {
    const int xo = (k % layout.columns) * tile_cols;
    const int yo = (grid_rows - 1 - k / layout.columns) * tile_rows;
    if (out_band->RasterIO(GF_Write, xo, yo, cols, rows, window.data(), cols, rows, GDT_Float32, 0,
                           0) != CE_None) {
      throw std::runtime_error(dem_out + ": write failed");
    }
  }
  GDALClose(out);
  GDALClose(source);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4 && argc != 6) {
    std::fprintf(stderr,
                 "usage: make_tiled_osm INPUT COPIES OUTPUT.osm.pbf [DEM_IN DEM_OUT.tif]\n");
    return 2;
  }
  try {
    const int copies = std::atoi(argv[2]);
    if (copies < 1 || copies > 10000) throw std::invalid_argument("COPIES must be in 1..10000");
    osmium::io::Reader reader{argv[1]};
    osmium::memory::Buffer input{1024 * 1024, osmium::memory::Buffer::auto_grow::yes};
    while (osmium::memory::Buffer buffer = reader.read()) {
      for (const auto& item : buffer) {
        input.add_item(item);
        input.commit();
      }
    }
    reader.close();
    const Layout layout = plan(input, copies);
    write_osm(input, layout, argv[3]);
    if (argc == 6) write_dem(argv[4], argv[5], layout);
    std::printf("%s: %d copies in %d columns, tile %.4f x %.4f deg\n", argv[3], copies,
                layout.columns, layout.tile_width_deg, layout.tile_height_deg);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_tiled_osm: %s\n", e.what());
    return 1;
  }
}
