#include "roadcross/preprocess/common/interrupt.hpp"

#include <unistd.h>

#include <csignal>
#include <cstring>
#include <initializer_list>

namespace roadcross::preprocess {
namespace {

// Signal handlers may only touch lock-free atomics and call async-signal-safe functions, so the
// path is kept in a fixed buffer and published through an atomic flag.
char g_cleanup_path[4096];
char g_cleanup_journal_path[4096 + 8];  // the path + "-journal" (SQLite's rollback journal)
char g_cleanup_side_path[4096 + 8];     // the path + "-rows" (the writer's side database)
volatile std::sig_atomic_t g_has_cleanup_path = 0;

void write_stderr(const char* text) noexcept {
  const ssize_t ignored = ::write(STDERR_FILENO, text, std::strlen(text));
  (void)ignored;
}

extern "C" void on_interrupt(int signal_number) {
  if (g_has_cleanup_path) {
    ::unlink(g_cleanup_path);
    ::unlink(g_cleanup_journal_path);
    ::unlink(g_cleanup_side_path);
    write_stderr("\nroadcross-build: interrupted; removed the partial output ");
    write_stderr(g_cleanup_path);
    write_stderr("\n");
  } else {
    write_stderr("\nroadcross-build: interrupted\n");
  }
  ::_exit(128 + signal_number);
}

}  // namespace

void install_interrupt_cleanup() noexcept {
  struct sigaction action {};
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  for (int signal_number : {SIGINT, SIGTERM, SIGHUP}) sigaction(signal_number, &action, nullptr);
  // Past a file size limit (ulimit -f) the kernel would kill the process with SIGXFSZ before it
  // could clean up; ignored, the write fails with EFBIG instead and the build reports it and
  // removes its temporary file like any other full disk.
  std::signal(SIGXFSZ, SIG_IGN);
}

void set_interrupt_cleanup_path(const char* path) noexcept {
  g_has_cleanup_path = 0;
  if (path == nullptr || std::strlen(path) >= sizeof g_cleanup_path) return;
  std::strcpy(g_cleanup_path, path);
  std::strcpy(g_cleanup_journal_path, path);
  std::strcat(g_cleanup_journal_path, "-journal");
  std::strcpy(g_cleanup_side_path, path);
  std::strcat(g_cleanup_side_path, kSideRowsSuffix);
  g_has_cleanup_path = 1;
}

}  // namespace roadcross::preprocess
