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
#pragma once

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace partc {

namespace detail {

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
