// partc/io/output_file.cpp: write_file_atomically (output_file.hpp says how it behaves).
#include "partc/io/output_file.hpp"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <system_error>

namespace partc {

namespace detail {

namespace {

// The temporary being written, for the signal handler.
std::atomic<const char*> pending_temporary{nullptr};

extern "C" void remove_pending_temporary(int signal) {
  if (const char* path = pending_temporary.load()) ::unlink(path);  // async-signal-safe
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

// Installs remove_pending_temporary where the default action would end the
// program (two system calls per file written: nothing beside the writing).
void guard_temporaries_against_signals() {
  for (int s : {SIGINT, SIGTERM}) {
    struct sigaction old {};
    if (sigaction(s, nullptr, &old) == 0 && old.sa_handler == SIG_DFL)
      std::signal(s, remove_pending_temporary);
  }
}

}  // namespace

void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write) {
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
    explicit Pending(const std::string& p) { pending_temporary.store(p.c_str()); }
    ~Pending() { pending_temporary.store(nullptr); }
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
