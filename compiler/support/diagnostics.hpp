// User-facing errors and compiler bugs, kept on separate paths.
//
// A mistake in a .part file is a Diagnostic: file:line:column, the message,
// the source line and a caret under the offending range, as C compilers
// print them. A broken invariant inside partc is an InternalError, printed
// as "internal error: partc bug", so users never mistake one for the other.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "support/source.hpp"

namespace partc {

struct Diagnostic {
  Location loc;
  std::string message;
  std::string note = {};  // optional extra line ("note: ...") printed after the caret
  bool warning = false;   // a likely mistake that still compiles
  // Where the text came from, when it is a module's: "in effect lj, used at
  // scene.part:18", a last "note:" line.
  std::string context = {};
};

// Thrown to abandon compilation after one or more errors (the diagnostics
// may hold warnings too, in the order they were found).
class CompileError : public std::exception {
 public:
  explicit CompileError(std::vector<Diagnostic> diagnostics)
      : diagnostics_(std::move(diagnostics)) {}
  explicit CompileError(Diagnostic d) : diagnostics_{std::move(d)} {}
  const std::vector<Diagnostic>& diagnostics() const { return diagnostics_; }
  const char* what() const noexcept override { return "partc compile error"; }

 private:
  std::vector<Diagnostic> diagnostics_;
};

class InternalError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

[[noreturn]] void internal_error(const std::string& what);
#define PARTC_ASSERT(cond)                                              \
  do {                                                                  \
    if (!(cond)) ::partc::internal_error(__FILE__ ":" + std::to_string(__LINE__) + ": " #cond); \
  } while (0)

// "file:line:col: error: message" (or "warning:"), the source line, and a caret line.
std::string format_diagnostic(const SourceFile& file, const Diagnostic& d);

}  // namespace partc
