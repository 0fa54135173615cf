// roadcross-build: OSM extract + elevation (XYZ points, rasters) -> roadcross GeoPackage.
#include <CLI/CLI.hpp>

#include <sqlite3.h>
#include <unistd.h>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "cli_conventions.hpp"
#include "roadcross/preprocess/build.hpp"
#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/common/interrupt.hpp"
#include "roadcross/preprocess/common/progress.hpp"
#include "roadcross/preprocess/parameter_file.hpp"
#include "roadcross/preprocess/terrain/elevation_input.hpp"
#include "roadcross/version.hpp"

namespace rp = roadcross::preprocess;

namespace {

/// True when this process's malloc was started with glibc.malloc.hugetlb 1 or 2 (the last
/// setting in GLIBC_TUNABLES counts, as for glibc).
bool malloc_on_huge_pages() {
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (!tunables) return false;
  const std::string_view all(tunables), key = "glibc.malloc.hugetlb=";
  bool on = false;
  for (std::size_t at = all.find(key); at != std::string_view::npos; at = all.find(key, at + 1)) {
    if (at > 0 && all[at - 1] != ':') continue;
    const std::string_view value = all.substr(at + key.size(), all.find(':', at) - at - key.size());
    on = value == "1" || value == "2";
  }
  return on;
}

/// glibc's malloc puts its heaps on transparent huge pages only when told so before the process
/// starts (the tunable glibc.malloc.hugetlb=1, read by the dynamic loader). A build's tables
/// take hundreds of MiB to GiB, on 4 KiB pages a page fault (~10 us on a VM) and a TLB entry
/// each: so the build runs itself again, once, with the tunable added (docs/performance.md,
/// "Huge pages for malloc"). Not when GLIBC_TUNABLES already names it (the user's choice, either
/// way) or ROADCROSS_NO_RELAUNCH is set to anything but 0 (a profiler that follows one image);
/// if the exec fails the build goes on as it is. First thing in main: no file is open yet.
void relaunch_with_huge_page_malloc(char** argv) {
#if defined(__linux__) && defined(__GLIBC__)
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (tunables && std::strstr(tunables, "glibc.malloc.hugetlb")) return;
  const char* no_relaunch = std::getenv("ROADCROSS_NO_RELAUNCH");
  if (no_relaunch && *no_relaunch && std::strcmp(no_relaunch, "0") != 0) return;
  const std::string previous = tunables ? tunables : "";
  const std::string value =
      previous.empty() ? "glibc.malloc.hugetlb=1" : previous + ":glibc.malloc.hugetlb=1";
  if (::setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0) return;
  ::execv("/proc/self/exe", argv);
  if (tunables) {
    ::setenv("GLIBC_TUNABLES", previous.c_str(), 1);
  } else {
    ::unsetenv("GLIBC_TUNABLES");
  }
#else
  (void)argv;
#endif
}

void print_json_summary(const rp::BuildOptions& options, const rp::BuildSummary& s) {
  nlohmann::ordered_json out;
  out["output"] = options.output_path;
  out["utm_zone"] = s.zone.zone;
  out["utm_northern"] = s.zone.northern;
  out["road_ways"] = s.road_ways;
  out["pieces"] = s.pieces;
  out["segments"] = s.segments;
  out["junctions"] = s.junctions;
  out["total_length_m"] = s.total_length_m;
  out["missing_node_refs"] = s.missing_node_refs;
  out["crossings"] = s.crossings;
  if (s.has_elevation) {
    const rp::TerrainReport& t = s.terrain;
    out["terrain"] = {{"grid_cols", t.grid.cols},
                      {"grid_rows", t.grid.rows},
                      {"cell_m", t.grid.cell_m},
                      {"cell_size_source", t.cell_size_source},
                      {"cells_with_elevation", t.cells_with_elevation},
                      {"voids_filled", t.voids_filled},
                      {"xyz_points", t.xyz_points},
                      {"xyz_spilled_points", t.xyz_spilled_points},
                      {"xyz_crs", t.xyz_crs},
                      {"segments_without_elevation", t.segments_without_elevation},
                      {"structure_segments", t.structure_segments}};
  }
  out["notes"] = s.notes;
  nlohmann::ordered_json stages = nlohmann::ordered_json::array();
  for (const rp::StageRecord& stage : s.stages) {
    stages.push_back({{"stage", stage.name},
                      {"seconds", stage.seconds},
                      {"summary", stage.summary},
                      {"peak_rss_mib", static_cast<double>(stage.peak_rss_kib) / 1024.0}});
  }
  out["stages"] = stages;
  out["seconds"] = s.seconds;
  out["peak_rss_mib"] = static_cast<double>(s.peak_rss_kib) / 1024.0;
  out["malloc_huge_pages"] = malloc_on_huge_pages();
  // Paths may be any bytes: replaced in the JSON (which must be UTF-8), never fatal.
  std::cout << out.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) << "\n";
}

/// Parameters from --config FILE, with every --section.name flag given on the command line
/// taking precedence over the file.
void apply_config_file(CLI::App& app, const std::string& path, rp::Parameters& parameters) {
  rp::Parameters merged;
  rp::read_parameter_file(path, merged);
  const std::vector<rp::ParameterSpec> from_flags = parameters.specs();
  const std::vector<rp::ParameterSpec> into = merged.specs();
  for (std::size_t i = 0; i < into.size(); ++i) {
    if (app.get_option("--" + into[i].key())->count() > 0) *into[i].value = *from_flags[i].value;
  }
  parameters = merged;
}

}  // namespace

int main(int argc, char** argv) {
  relaunch_with_huge_page_malloc(argv);
  // SQLite counts every allocation under one process-wide mutex unless told not to; the build
  // never reads the counts, and the GeoPackage writers allocate per row on two threads.
  // (Only possible before SQLite initialises, i.e. first thing.)
  sqlite3_config(SQLITE_CONFIG_MEMSTATUS, 0);
  CLI::App app{
      "roadcross-build: turn an OpenStreetMap extract into a roadcross GeoPackage of short road\n"
      "segments with crossing cost terms, for the roadcross runtime.\n\n"
      "Example:\n  roadcross-build --osm maps/prague/prague_nove_mesto_roads_2017.osm -o "
      "prague.gpkg \\\n      --elevation maps/prague/N50E014.hgt\n",
      "roadcross-build"};
  app.set_version_flag("--version", std::string("roadcross-build ") + roadcross::kVersion);
  rp::BuildOptions options;
  bool quiet = false;
  // --print-config needs no input or output.
  const bool printing_config = std::any_of(argv + 1, argv + argc, [](const char* arg) {
    return std::string_view(arg) == "--print-config";
  });
  std::vector<std::string> osm_paths;
  app.add_option("--osm", osm_paths,
                 "OSM input: .osm, .osm.gz, .osm.bz2 or .osm.pbf; repeatable: several extracts "
                 "make one map, merged by object id as `osmium merge` does (each file sorted "
                 "by type and id, as extracts are)")
      ->required(!printing_config);
  app.add_option("-o,--output", options.output_path,
                 "output GeoPackage (.gpkg); replaced atomically")
      ->required(!printing_config);
  std::vector<std::string> elevation_paths;
  app.add_option("--elevation", elevation_paths,
                 "elevation input, repeatable, kinds may be mixed: XYZ points (.xyz/.txt/.csv: "
                 "'easting northing altitude' per line) or any raster GDAL reads (GeoTIFF, SRTM "
                 ".hgt, ...); where inputs overlap the first given wins")
      ->check(CLI::ExistingFile);
  app.add_option("--elevation-crs", options.elevation.xyz_crs,
                 "coordinate system of the XYZ files (EPSG:5514 S-JTSK, EPSG:32633, a PROJ "
                 "string); default: S-JTSK when the values fit it, else an error");
  std::string config_path;
  bool print_config = false;
  app.add_option(
      "--config", config_path,
      "parameter file (INI/TOML, as --print-config writes); --section.name flags override it");
  app.add_flag(
      "--print-config", print_config,
      "print every parameter (with --config and flags applied) as a parameter file and exit");
  app.add_option(
      "--overrides", options.overrides_path,
      "operator overrides: GeoJSON polygons or osm_way_id with context_delta, no_crossing, "
      "force_suitable, note");
  app.add_option("--country", options.country,
                 "country of implicit speed limits for untagged ways (CZ, SK, DE, AT, PL, FR, MC, "
                 "default); default: from the tags, else the extract's location");
  // Every model parameter is also a flag: --segments.max_segment_length_m 8
  for (const rp::ParameterSpec& spec : options.parameters.specs()) {
    app.add_option("--" + spec.key(), *spec.value, spec.description)
        ->capture_default_str()
        ->group("Model parameters");
  }
  app.add_flag("-q,--quiet", quiet, "no progress output and no summary");
  bool json = false;
  app.add_flag("--json", json, "print the final summary as JSON on stdout");
  if (const std::optional<int> status =
          roadcross::cli::parse_command_line(app, argc, argv, "roadcross-build")) {
    return *status;
  }
  using roadcross::cli::print_error;
  try {
    if (!config_path.empty()) apply_config_file(app, config_path, options.parameters);
    if (print_config) {
      options.parameters.validate();
      std::cout << rp::format_parameter_file(options.parameters);
      return 0;
    }
  } catch (const rp::ParameterError& e) {
    print_error("roadcross-build", std::string("invalid parameter: ") + e.what(),
                "invalid_parameter");
    return roadcross::cli::kUsageExitStatus;
  } catch (const std::exception& e) {
    print_error("roadcross-build", std::string("error: ") + e.what(), "error");
    return 1;
  }
  if (options.output_path.empty()) {
    print_error("roadcross-build", "-o/--output: an empty name is not a file", "usage");
    return roadcross::cli::kUsageExitStatus;
  }

  if (!osm_paths.empty()) {
    options.osm_path = osm_paths.front();
    options.extra_osm_paths.assign(osm_paths.begin() + 1, osm_paths.end());
  }
  for (const std::string& path : elevation_paths) {
    options.elevation.sources.push_back({path, rp::elevation_kind_of(path)});
  }
  // XYZ points past terrain.xyz_memory_mib spill next to the output (where there is room for it).
  options.elevation.spill_dir =
      std::filesystem::absolute(options.output_path).parent_path().string();
  rp::install_interrupt_cleanup();
  options.show_progress = !quiet && rp::Progress::stderr_is_terminal();
  options.tool_version = roadcross::kVersion;
  try {
    const rp::BuildSummary s = rp::run_build(options);
    if (json) {
      print_json_summary(options, s);
    } else if (!quiet) {
      std::printf(
          "%s: %llu segments (%.1f km) from %llu road ways, %llu junctions, UTM zone %d%s, %.2f "
          "s\n",
          options.output_path.c_str(), static_cast<unsigned long long>(s.segments),
          s.total_length_m / 1000.0, static_cast<unsigned long long>(s.road_ways),
          static_cast<unsigned long long>(s.junctions), s.zone.zone, s.zone.northern ? "N" : "S",
          s.seconds);
      if (s.missing_node_refs > 0) {
        std::printf(
            "note: %llu node references of road ways were not in the file (cut by the extract)\n",
            static_cast<unsigned long long>(s.missing_node_refs));
      }
      for (const std::string& note : s.notes) std::printf("  %s\n", note.c_str());
    }
    return 0;
  } catch (const rp::ParameterError& e) {
    print_error("roadcross-build", std::string("invalid parameter: ") + e.what(),
                "invalid_parameter");
    return roadcross::cli::kUsageExitStatus;
  } catch (const std::exception& e) {
    print_error("roadcross-build", std::string("error: ") + e.what(), "error");
    return 1;
  }
}
