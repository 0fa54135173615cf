// A SQLite VFS for the build's own connections (the GeoPackage writer, the map identity's
// readers): the default VFS with fewer system calls. SQLite reads and writes one 4 KiB page a
// call; on a virtual machine each call costs an exit (docs/performance-log.md, "Build
// system calls and page faults (issue 27)"). This VFS
//  - keeps contiguous page writes in a buffer and writes them with one call: the buffer is written
//    out before anything that could see the file (a sync, a lock change, a truncation, a read of
//    those bytes, a file control but the size hint, the close) and before a write that does not
//    continue it; a failed write (a full disk) returns the base VFS's error to SQLite at that
//    point;
//  - reads ahead when reads are sequential (a window that doubles up to the buffer's size on each
//    sequential miss), dropping what it read ahead on any write over it, any lock change from or to
//    no lock, and for good once the file is opened in WAL mode (another connection's checkpoint
//    could change pages under it).
// Not for the runtime library: its connections keep SQLite's default VFS.
#pragma once

#include <cstddef>
#include <string>

namespace roadcross::mapcheck {

/// Registers (not as the default) a VFS named `name` over the registered VFS `base_name`
/// (empty: SQLite's default) with write and read-ahead buffers of `buffer_bytes` each per open
/// file (at most 128 KiB - 1: the unix VFS's limit for one call), allocated on first use.
/// Registering a name again replaces nothing and returns. Throws std::runtime_error if `base_name`
/// is not registered. Thread-safe.
void register_bulk_io_vfs(const std::string& name, const std::string& base_name,
                          std::size_t buffer_bytes);

/// The build's VFS: over the default VFS, 124 KiB buffers; registered on the first call.
const char* bulk_io_vfs();

}  // namespace roadcross::mapcheck
