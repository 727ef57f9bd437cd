// Lays out generated C++ with clang's own formatter, linked from LLVM 14,
// so the emitter can concentrate on content and users read tidy code.
#include <clang/Format/Format.h>
#include <clang/Tooling/Core/Replacement.h>

#include "codegen/codegen.hpp"
#include "support/diagnostics.hpp"

namespace partc {

std::string format_cpp(const std::string& code, const std::string& file_name) {
  clang::format::FormatStyle style = clang::format::getLLVMStyle();
  style.ColumnLimit = 100;
  style.AllowShortFunctionsOnASingleLine = clang::format::FormatStyle::SFS_Inline;
  style.FixNamespaceComments = true;
  style.DerivePointerAlignment = false;
  style.ReflowComments = false;  // the emitter wraps its comments; reflowing would merge them
  style.PointerAlignment = clang::format::FormatStyle::PAS_Left;
  const std::vector<clang::tooling::Range> whole{
      clang::tooling::Range(0, static_cast<unsigned>(code.size()))};
  const clang::tooling::Replacements edits =
      clang::format::reformat(style, code, whole, file_name);
  auto formatted = clang::tooling::applyAllReplacements(code, edits);
  if (!formatted) {
    const std::string why = llvm::toString(formatted.takeError());
    internal_error("clang-format could not lay out the generated code: " + why);
  }
  return *formatted;
}

}  // namespace partc
