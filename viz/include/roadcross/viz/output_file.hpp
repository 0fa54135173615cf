// Never a half-written output (docs/architecture.md): write beside the target, rename on success.
#pragma once

#include <string>
#include <string_view>

namespace roadcross::viz {

/// Throws std::runtime_error naming `path` unless its folder exists and is writable: checked
/// before the work so that a typo in -o fails at once.
void check_writable(const std::string& path);

/// A temporary name beside `path` (same folder, so the rename is atomic).
std::string temp_path_for(const std::string& path);

/// Renames `temp` onto `path`; throws naming both on failure (and removes `temp`).
void commit_file(const std::string& temp, const std::string& path);

/// Writes `content` to `path` atomically.
void write_file(const std::string& path, std::string_view content);

}  // namespace roadcross::viz
