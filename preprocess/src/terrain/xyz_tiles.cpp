#include "roadcross/preprocess/terrain/xyz_tiles.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "roadcross/preprocess/common/errors.hpp"

namespace roadcross::preprocess {

XyzTileBins::XyzTileBins(std::vector<UtmBox> boxes, std::size_t memory_budget_bytes,
                         std::string spill_dir)
    : boxes_(std::move(boxes)),
      budget_points_(std::max<std::size_t>(1, memory_budget_bytes / sizeof(ElevationPoint))),
      spill_dir_(std::move(spill_dir)),
      memory_(boxes_.size()),
      chunks_(boxes_.size()) {
  bool any = false;
  for (const UtmBox& b : boxes_) {
    if (!(b.max_e >= b.min_e && b.max_n >= b.min_n)) continue;  // an empty box
    if (!any) bounds_ = b, any = true;
    bounds_.min_e = std::min(bounds_.min_e, b.min_e),
    bounds_.max_e = std::max(bounds_.max_e, b.max_e);
    bounds_.min_n = std::min(bounds_.min_n, b.min_n),
    bounds_.max_n = std::max(bounds_.max_n, b.max_n);
    bucket_m_ = std::max({bucket_m_, b.max_e - b.min_e, b.max_n - b.min_n});
  }
  if (!any) return;
  bucket_cols_ = static_cast<std::size_t>((bounds_.max_e - bounds_.min_e) / bucket_m_) + 1;
  bucket_rows_ = static_cast<std::size_t>((bounds_.max_n - bounds_.min_n) / bucket_m_) + 1;
  buckets_.resize(bucket_cols_ * bucket_rows_);
  for (std::size_t t = 0; t < boxes_.size(); ++t) {
    const UtmBox& b = boxes_[t];
    if (!(b.max_e >= b.min_e && b.max_n >= b.min_n)) continue;
    const auto c0 = static_cast<std::size_t>((b.min_e - bounds_.min_e) / bucket_m_);
    const auto c1 = static_cast<std::size_t>((b.max_e - bounds_.min_e) / bucket_m_);
    const auto r0 = static_cast<std::size_t>((b.min_n - bounds_.min_n) / bucket_m_);
    const auto r1 = static_cast<std::size_t>((b.max_n - bounds_.min_n) / bucket_m_);
    for (std::size_t r = r0; r <= r1 && r < bucket_rows_; ++r) {
      for (std::size_t c = c0; c <= c1 && c < bucket_cols_; ++c) {
        buckets_[r * bucket_cols_ + c].push_back(t);
      }
    }
  }
}

XyzTileBins::~XyzTileBins() {
  if (fd_ >= 0) ::close(fd_);
}

void XyzTileBins::open_spill_file() {
  std::string dir = spill_dir_;
  if (dir.empty()) dir = std::filesystem::temp_directory_path().string();
#ifdef O_TMPFILE
  fd_ = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
#endif
  if (fd_ < 0) {
    // No O_TMPFILE on this file system: a named file, unlinked as soon as it is open.
    std::string name = dir + "/roadcross-xyz-XXXXXX";
    fd_ = ::mkstemp(name.data());
    if (fd_ >= 0) ::unlink(name.c_str());
  }
  if (fd_ < 0) {
    throw OutputError(dir + ": cannot create a temporary file for XYZ points (" +
                      std::strerror(errno) + "); give terrain.xyz_memory_mib more memory");
  }
}

void XyzTileBins::add(const std::vector<ElevationPoint>& points) {
  for (const ElevationPoint& p : points) {
    if (!bounds_.contains(p.x, p.y)) continue;  // also NaN
    const auto c = static_cast<std::size_t>((p.x - bounds_.min_e) / bucket_m_);
    const auto r = static_cast<std::size_t>((p.y - bounds_.min_n) / bucket_m_);
    for (const std::size_t t :
         buckets_[std::min(r, bucket_rows_ - 1) * bucket_cols_ + std::min(c, bucket_cols_ - 1)]) {
      if (!boxes_[t].contains(p.x, p.y)) continue;
      memory_[t].push_back(p);
      ++in_memory_;
    }
    if (in_memory_ > budget_points_) spill();
  }
}

void XyzTileBins::spill() {
  if (fd_ < 0) open_spill_file();
  for (std::size_t t = 0; t < memory_.size(); ++t) {
    std::vector<ElevationPoint>& bin = memory_[t];
    if (bin.empty()) continue;
    const auto* bytes = reinterpret_cast<const char*>(bin.data());
    std::size_t size = bin.size() * sizeof(ElevationPoint), done = 0;
    while (done < size) {
      const ssize_t n =
          ::pwrite(fd_, bytes + done, size - done, file_end_ + static_cast<long long>(done));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        throw OutputError(
            "cannot write the temporary file of XYZ points (" +
            std::string(n < 0 ? std::strerror(errno) : "disk full") + "): free space in " +
            (spill_dir_.empty() ? std::filesystem::temp_directory_path().string() : spill_dir_));
      }
      done += static_cast<std::size_t>(n);
    }
    chunks_[t].push_back({file_end_, bin.size()});
    file_end_ += static_cast<long long>(size);
    spilled_points_ += bin.size();
    std::vector<ElevationPoint>().swap(bin);  // give the memory back
  }
  in_memory_ = 0;
  ++spills_;
}

std::vector<ElevationPoint> XyzTileBins::take(std::size_t tile) {
  std::size_t total = memory_[tile].size();
  for (const Chunk& c : chunks_[tile]) total += c.count;
  std::vector<ElevationPoint> out;
  out.reserve(total);
  for (const Chunk& c : chunks_[tile]) {
    const std::size_t start = out.size();
    out.resize(start + c.count);
    auto* bytes = reinterpret_cast<char*>(out.data() + start);
    const std::size_t size = c.count * sizeof(ElevationPoint);
    std::size_t done = 0;
    while (done < size) {
      const ssize_t n =
          ::pread(fd_, bytes + done, size - done, c.offset + static_cast<long long>(done));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        throw OutputError("cannot read back the temporary file of XYZ points (" +
                          std::string(n < 0 ? std::strerror(errno) : "truncated") + ")");
      }
      done += static_cast<std::size_t>(n);
    }
  }
  chunks_[tile].clear();
  out.insert(out.end(), memory_[tile].begin(), memory_[tile].end());
  in_memory_ -= memory_[tile].size();
  std::vector<ElevationPoint>().swap(memory_[tile]);
  return out;
}

}  // namespace roadcross::preprocess
