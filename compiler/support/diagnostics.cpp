#include "support/diagnostics.hpp"

#include <algorithm>

namespace partc {

void internal_error(const std::string& what) { throw InternalError(what); }

std::string format_diagnostic(const SourceFile& file, const Diagnostic& d) {
  const LineColumn at = file.line_column(d.loc.begin);
  std::string out = file.path_of(d.loc.begin) + ":" + std::to_string(at.line) + ":" +
                    std::to_string(at.column) + (d.warning ? ": warning: " : ": error: ") + d.message + "\n";
  const std::string_view line = file.line_text(d.loc.begin, at.line);
  out += "  ";
  out += line;
  out += "\n  ";
  // Tabs in the prefix stay tabs so the caret lines up in any terminal.
  for (int k = 0; k < at.column - 1 && k < static_cast<int>(line.size()); ++k)
    out += line[k] == '\t' ? '\t' : ' ';
  const int first = at.column - 1;
  const int last_on_line = static_cast<int>(line.size());
  const int width = std::max(1, std::min<int>(static_cast<int>(d.loc.end - d.loc.begin),
                                              last_on_line - first));
  out += '^';
  out += std::string(width - 1, '~');
  out += "\n";
  if (!d.note.empty()) out += "note: " + d.note + "\n";
  if (!d.context.empty()) out += "note: " + d.context + "\n";
  return out;
}

}  // namespace partc
