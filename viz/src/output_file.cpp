#include "roadcross/viz/output_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace roadcross::viz {

namespace {

std::string folder_of(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

}  // namespace

void check_writable(const std::string& path) {
  if (path.empty()) throw std::runtime_error("no output path given");
  const std::string folder = folder_of(path);
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw std::runtime_error("cannot write " + path + ": it is a directory");
  }
  if (!std::filesystem::is_directory(folder, ec)) {
    throw std::runtime_error("cannot write " + path + ": folder " + folder + " does not exist");
  }
  if (::access(folder.c_str(), W_OK) != 0) {
    throw std::runtime_error("cannot write " + path + ": folder " + folder + " is not writable (" +
                             std::strerror(errno) + ")");
  }
}

std::string temp_path_for(const std::string& path) {
  return path + ".tmp." + std::to_string(::getpid());
}

void commit_file(const std::string& temp, const std::string& path) {
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(temp.c_str());
    throw std::runtime_error("cannot write " + path + ": " + why);
  }
}

void write_file(const std::string& path, std::string_view content) {
  const std::string temp = temp_path_for(path);
  {
    std::ofstream out(temp, std::ios::binary);
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.close();
    if (!out) {
      std::remove(temp.c_str());
      throw std::runtime_error("cannot write " + path + ": " + std::strerror(errno));
    }
  }
  commit_file(temp, path);
}

}  // namespace roadcross::viz
