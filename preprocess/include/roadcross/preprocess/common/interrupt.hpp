// Ctrl-C (SIGINT), SIGTERM and SIGHUP during a build: remove the temporary output and exit with
// a message, so an interrupted build never leaves a partial file behind. The target file, if
// it existed before, is untouched (it is only ever replaced by rename on success).
#pragma once

namespace roadcross::preprocess {

/// Suffix of the side database the GeoPackage writer fills on its second thread in a build
/// without the sight stage (`<temporary output>-rows`; with it, the rows are written beside that
/// stage instead), removed when its rows are copied in; AtomicOutput and the handlers remove it
/// too.
inline constexpr const char* kSideRowsSuffix = "-rows";

/// Installs the handlers. Call once from main() of a tool that writes via AtomicOutput.
void install_interrupt_cleanup() noexcept;

/// The temporary file the handlers remove, with its SQLite "-journal" and the writer's "-rows"
/// side database (nullptr for none). Used by AtomicOutput, which registers a name before it
/// creates the file and removes the file before it unregisters the name: a signal at any moment
/// finds no unknown file.
void set_interrupt_cleanup_path(const char* path) noexcept;

}  // namespace roadcross::preprocess
