// partc/output_file.hpp: the one way the runtime's writers (csv.hpp, vtk.hpp,
// solve/matrix_market.hpp) put a file on disk.
//
//   detail::write_file_atomically(path, [&](std::ostream& out) { out << ...; });
//
// A regular file (or a new one) is written as path + ".tmp" and renamed to
// path, so a failure or a crash never leaves a half-written file under the
// real name: either the old file or the complete new one is there.
// Surprises:
// - Any other path that exists is written directly, in place: a symbolic link
//   (/dev/stdout is one, to /proc/self/fd/1, even when it leads to a regular
//   file), a named pipe, a device, a terminal. Renaming a temporary over it
//   would replace the link or the device by a plain file, and its reader
//   would see nothing. Such a write is not atomic.
// - Errors are std::runtime_error naming the file and the system's reason; a
//   writer that throws half way removes the temporary, and its exception
//   propagates unchanged.
// - SIGINT or SIGTERM while a temporary is being written removes it, then
//   ends the program as the signal would have. This is the one piece of
//   global state here (a signal handler can reach nothing else); a handler
//   the program installed itself is left alone.
#pragma once

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace partc {

namespace detail {

// The temporary being written, for the signal handler.
inline std::atomic<const char*>& pending_temporary() {
  static std::atomic<const char*> pending{nullptr};
  return pending;
}

extern "C" inline void remove_pending_temporary(int signal) {
  if (const char* path = pending_temporary().load()) ::unlink(path);  // async-signal-safe
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

// Installs remove_pending_temporary where the default action would end the
// program (two system calls per file written: nothing beside the writing).
inline void guard_temporaries_against_signals() {
  for (int s : {SIGINT, SIGTERM}) {
    struct sigaction old {};
    if (sigaction(s, nullptr, &old) == 0 && old.sa_handler == SIG_DFL)
      std::signal(s, remove_pending_temporary);
  }
}

template <class Write>
void write_file_atomically(const std::string& path, Write&& write) {
  std::error_code ignored;  // a path that cannot be examined is treated as new
  const auto status = std::filesystem::symlink_status(path, ignored);  // the link, not its target
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
    std::ofstream out(path, std::ios::binary);
    if (!out) throw std::runtime_error("cannot open '" + path + "': " + std::strerror(errno));
    write(out);
    out.close();
    if (!out) throw std::runtime_error("cannot write '" + path + "': " + std::strerror(errno));
    return;
  }
  const std::string temporary = path + ".tmp";
  guard_temporaries_against_signals();
  struct Pending {  // cleared however the write ends
    explicit Pending(const std::string& p) { pending_temporary().store(p.c_str()); }
    ~Pending() { pending_temporary().store(nullptr); }
  } pending(temporary);
  try {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out)
      throw std::runtime_error("cannot create '" + temporary + "': " + std::strerror(errno));
    write(out);
    out.close();
    if (!out) throw std::runtime_error("cannot write '" + temporary + "': " + std::strerror(errno));
    if (std::rename(temporary.c_str(), path.c_str()) != 0)
      throw std::runtime_error("cannot rename '" + temporary + "' to '" + path +
                               "': " + std::strerror(errno));
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
}

}  // namespace detail

}  // namespace partc
