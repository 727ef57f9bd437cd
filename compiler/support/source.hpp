// The .part source text of one compilation held in memory, and positions
// inside it.
//
// Every AST and IR node carries a Location: byte offsets into one buffer
// that holds the model's file first and then each module it opens, one
// after another (as a compiler's source manager does), so a location says
// which file it is in without carrying a file name. Line and column are
// counted within that file, and only when a diagnostic is printed.
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

  // The model's own file: the first one.
  const std::string& path() const { return segments_.front().path; }
  // All the text: the model's file, then each module appended.
  const std::string& text() const { return text_; }

  // Appends a module's text (after a newline if the last file lacked one)
  // and returns its index; `path` is how messages name it.
  int append(std::string path, std::string text);
  int files() const { return static_cast<int>(segments_.size()); }
  // The file an offset is in (0: the model's), its name, and its bytes.
  int file_of(std::uint32_t offset) const;
  const std::string& path_of(std::uint32_t offset) const { return segments_[file_of(offset)].path; }
  Location extent(int file) const { return {segments_[file].begin, segments_[file].end}; }

  // Line and column within the offset's own file.
  LineColumn line_column(std::uint32_t offset) const;
  // The text of a 1-based line of the file an offset is in, without its newline.
  std::string_view line_text(std::uint32_t offset, int line) const;
  // The source text a location covers.
  std::string_view slice(Location loc) const;
  // "line 12" in the model's file, "stdlib/pair/lj.part:12" in another:
  // for notes that point from one place to another.
  std::string line_reference(std::uint32_t offset) const;

  // Lines of the model's file the output numbers as if deleted (--drop's use
  // lines): the generated code cites the line a statement would have in the
  // model without them, while messages keep citing the file as it is.
  void omit_lines(int first, int last);
  int output_line(std::uint32_t offset) const;

 private:
  struct Segment {
    std::string path;
    std::uint32_t begin, end;  // byte range in text_
    int first_line;            // index into line_starts_ of the file's first line
  };
  std::string text_;
  std::vector<std::uint32_t> line_starts_;
  std::vector<Segment> segments_;
  std::vector<std::pair<int, int>> omitted_;  // [first, last] lines of file 0
};

// Reads a whole file; throws std::runtime_error when it cannot.
SourceFile read_source_file(const std::string& path);

}  // namespace partc
