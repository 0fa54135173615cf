// The GDAL module's contract (common/gdal_module.hpp): its entry point hands the module only to
// a caller of the same interface and version; it is loaded once; the build's errors thrown
// inside it are caught as themselves outside.
#include "roadcross/preprocess/common/gdal_module.hpp"

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <string>

#include "osm_fixture.hpp"
#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/terrain/elevation_input.hpp"
#include "roadcross/preprocess/terrain/terrain_grid.hpp"
#include "roadcross/version.hpp"

namespace rp = roadcross::preprocess;

namespace {
const std::string kModulePath = std::string(ROADCROSS_BINARY_DIR) + "/cli/" + rp::kGdalModuleFile;
}

TEST(GdalModule, EntryRefusesAnotherInterfaceOrVersion) {
  void* handle = dlopen(kModulePath.c_str(), RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(handle, nullptr) << dlerror();
  const auto entry =
      reinterpret_cast<rp::GdalModuleEntry>(dlsym(handle, rp::kGdalModuleEntrySymbol));
  ASSERT_NE(entry, nullptr);
  EXPECT_NE(entry(rp::kGdalModuleInterface, roadcross::kVersion), nullptr);
  EXPECT_EQ(entry(rp::kGdalModuleInterface + 1, roadcross::kVersion), nullptr);
  EXPECT_EQ(entry(rp::kGdalModuleInterface - 1, roadcross::kVersion), nullptr);
  EXPECT_EQ(entry(rp::kGdalModuleInterface, "0.0.0-another"), nullptr);
  EXPECT_EQ(entry(rp::kGdalModuleInterface, nullptr), nullptr);
  dlclose(handle);
}

TEST(GdalModule, LoadedOnce) {
  EXPECT_EQ(&rp::gdal_module(), &rp::gdal_module());
}

TEST(GdalModule, ItsInputErrorIsCaughtAsOneWithTheFile) {
  const roadcross::testing::TempDir dir;
  const std::string missing = dir.file("missing.tif");
  try {
    const rp::RasterElevation raster(missing, roadcross::geo::UtmZone{33, true});
    FAIL() << "no error for a missing raster";
  } catch (const rp::InputError& e) {
    EXPECT_EQ(e.file(), missing);
    EXPECT_NE(std::string(e.what()).find("GDAL cannot read this elevation raster"),
              std::string::npos)
        << e.what();
  }
}

TEST(GdalModule, ItsParameterErrorIsCaughtAsOne) {
  EXPECT_THROW(rp::CrsTransform("EPSG:999999", roadcross::geo::UtmZone{33, true}),
               rp::ParameterError);
}
