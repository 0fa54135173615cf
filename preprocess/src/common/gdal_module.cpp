#include "roadcross/preprocess/common/gdal_module.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <system_error>

#include "roadcross/version.hpp"

namespace roadcross::preprocess {
namespace {

/// The places to look for the module, in order.
std::vector<std::string> module_candidates() {
  if (const char* path = std::getenv("ROADCROSS_GDAL_MODULE"); path && *path) return {path};
  std::vector<std::string> candidates;
  std::error_code error;
  const std::filesystem::path executable = std::filesystem::read_symlink("/proc/self/exe", error);
  if (!error) {
    const std::filesystem::path folder = executable.parent_path();
    candidates.push_back((folder / kGdalModuleFile).string());
#ifdef ROADCROSS_GDAL_MODULE_FROM_BINDIR
    candidates.push_back(
        (folder / ROADCROSS_GDAL_MODULE_FROM_BINDIR / kGdalModuleFile).lexically_normal().string());
#endif
  }
#ifdef ROADCROSS_GDAL_MODULE_BUILD_PATH
  if (candidates.empty() || candidates.front() != ROADCROSS_GDAL_MODULE_BUILD_PATH) {
    candidates.emplace_back(ROADCROSS_GDAL_MODULE_BUILD_PATH);  // the tests' executables
  }
#endif
  return candidates;
}

/// The module at `path`, or null with the reason in `why`.
const GdalModule* open_module(const std::string& path, std::string& why) {
  // RTLD_LOCAL: GDAL's symbols stay out of the global scope of the process.
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* message = dlerror();
    why = message ? message : "cannot be opened";
    // dlerror's text starts with the path, which the caller prints already.
    if (why.rfind(path + ": ", 0) == 0) why.erase(0, path.size() + 2);
    return nullptr;
  }
  const auto entry = reinterpret_cast<GdalModuleEntry>(dlsym(handle, kGdalModuleEntrySymbol));
  if (!entry) {
    why = std::string("not a roadcross GDAL module (no ") + kGdalModuleEntrySymbol + ")";
    dlclose(handle);
    return nullptr;
  }
  const GdalModule* module = entry(kGdalModuleInterface, roadcross::kVersion);
  if (!module) {
    why = std::string("built from another roadcross than this ") + roadcross::kVersion +
          " (keep the module of the same build beside the executable)";
    dlclose(handle);
    return nullptr;
  }
  return module;  // never closed: the objects it made live until the process ends
}

const GdalModule* load_module() {
  std::string tried;
  for (const std::string& path : module_candidates()) {
    std::string why;
    if (const GdalModule* module = open_module(path, why)) return module;
    tried += "\n  " + path + ": " + why;
  }
  throw std::runtime_error(
      "elevation input needs roadcross's GDAL module (" + std::string(kGdalModuleFile) +
      "), which could not be loaded:" + tried +
      "\nInstall it beside roadcross-build, or set ROADCROSS_GDAL_MODULE to its path.");
}

}  // namespace

const GdalModule& gdal_module() {
  static std::mutex mutex;
  static const GdalModule* module = nullptr;
  const std::lock_guard lock(mutex);
  if (!module) module = load_module();
  return *module;
}

}  // namespace roadcross::preprocess
