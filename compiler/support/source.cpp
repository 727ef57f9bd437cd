#include "support/source.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace partc {

SourceFile::SourceFile(std::string path, std::string text) {
  append(std::move(path), std::move(text));
}

int SourceFile::append(std::string path, std::string text) {
  // A UTF-8 byte order mark (editors on Windows write one) is not text.
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
  if (!text_.empty() && text_.back() != '\n') {
    text_ += '\n';
    segments_.back().end = static_cast<std::uint32_t>(text_.size());
  }
  const auto begin = static_cast<std::uint32_t>(text_.size());
  if (line_starts_.empty() || line_starts_.back() != begin) line_starts_.push_back(begin);
  const int first_line = static_cast<int>(line_starts_.size()) - 1;
  text_ += text;
  for (std::uint32_t k = begin; k < text_.size(); ++k)
    if (text_[k] == '\n') line_starts_.push_back(k + 1);
  segments_.push_back({std::move(path), begin, static_cast<std::uint32_t>(text_.size()), first_line});
  return static_cast<int>(segments_.size()) - 1;
}

int SourceFile::file_of(std::uint32_t offset) const {
  int file = 0;
  while (file + 1 < files() && segments_[file + 1].begin <= offset) ++file;
  return file;
}

LineColumn SourceFile::line_column(std::uint32_t offset) const {
  auto next = std::upper_bound(line_starts_.begin(), line_starts_.end(), offset);
  const int line = static_cast<int>(next - line_starts_.begin());
  return {line - segments_[file_of(offset)].first_line,
          static_cast<int>(offset - line_starts_[line - 1]) + 1};
}

std::string_view SourceFile::line_text(std::uint32_t offset, int line) const {
  const Segment& file = segments_[file_of(offset)];
  const int index = file.first_line + line - 1;  // into line_starts_
  if (line < 1 || index >= static_cast<int>(line_starts_.size()) ||
      line_starts_[index] > file.end)
    return {};
  const std::uint32_t begin = line_starts_[index];
  std::uint32_t end =
      index + 1 < static_cast<int>(line_starts_.size()) ? line_starts_[index + 1] - 1 : file.end;
  end = std::min(end, file.end);
  if (end > begin && text_[end - 1] == '\n') --end;
  if (end > begin && text_[end - 1] == '\r') --end;
  return std::string_view(text_).substr(begin, end - begin);
}

std::string SourceFile::line_reference(std::uint32_t offset) const {
  const int line = line_column(offset).line;
  return file_of(offset) == 0 ? "line " + std::to_string(line)
                              : path_of(offset) + ":" + std::to_string(line);
}

void SourceFile::omit_lines(int first, int last) { omitted_.push_back({first, last}); }

int SourceFile::output_line(std::uint32_t offset) const {
  int line = line_column(offset).line;
  if (file_of(offset) != 0) return line;
  const int at = line;
  for (const auto& [first, last] : omitted_)
    if (last < at) line -= last - first + 1;
  return line;
}

std::string_view SourceFile::slice(Location loc) const {
  return std::string_view(text_).substr(loc.begin, loc.end - loc.begin);
}

SourceFile read_source_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open '" + path + "'");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return SourceFile(path, buffer.str());
}

}  // namespace partc
