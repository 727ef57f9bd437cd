// partc/io/output_file.hpp: the one way the runtime's writers (csv.hpp, vtk.hpp,
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
// - Compiled once, in the runtime library (output_file.cpp): the writer is
//   called through std::function, once per file.
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace partc {

namespace detail {

void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write);

}  // namespace detail

}  // namespace partc
