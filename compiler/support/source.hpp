// A .part source file held in memory, and positions inside it.
//
// Every AST and IR node carries a Location (byte offsets into one source
// file); line and column are computed only when a diagnostic is printed.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace partc {

struct Location {
  std::uint32_t begin = 0;  // byte offset of the first character
  std::uint32_t end = 0;    // one past the last character
};

struct LineColumn {
  int line = 1;    // 1-based
  int column = 1;  // 1-based, in bytes
};

class SourceFile {
 public:
  SourceFile(std::string path, std::string text);

  const std::string& path() const { return path_; }
  const std::string& text() const { return text_; }

  LineColumn line_column(std::uint32_t offset) const;
  // The text of a 1-based line, without its newline.
  std::string_view line_text(int line) const;
  // The source text a location covers.
  std::string_view slice(Location loc) const;

 private:
  std::string path_;
  std::string text_;
  std::vector<std::uint32_t> line_starts_;
};

// Reads a whole file; throws std::runtime_error when it cannot.
SourceFile read_source_file(const std::string& path);

}  // namespace partc
