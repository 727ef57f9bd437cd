// partc/io/csv.cpp: reading CSV files, and the messages that point into them
// (csv.hpp says what is accepted and what each complaint looks like).
#include "partc/io/csv.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <ios>
#include <limits>
#include <streambuf>
#include <system_error>
#include <unordered_map>

namespace partc {

namespace detail {

namespace {

// Text from a file as an error message shows it: printable ASCII, tabs and
// valid UTF-8 as they are, any other byte as '?', so that a binary file
// sends no control sequences to the terminal and a NUL cannot cut the message.
std::size_t utf8_length(std::string_view text, std::size_t at) {  // 0: not valid UTF-8
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char lead = byte(at);
  const std::size_t n = lead >= 0xC2 && lead <= 0xDF   ? 2
                        : lead >= 0xE0 && lead <= 0xEF ? 3
                        : lead >= 0xF0 && lead <= 0xF4 ? 4
                                                       : 0;
  if (n == 0 || at + n > text.size()) return 0;
  for (std::size_t k = at + 1; k < at + n; ++k)
    if ((byte(k) & 0xC0) != 0x80) return 0;
  const unsigned char second = byte(at + 1);  // no overlong forms, surrogates or > U+10FFFF
  if ((lead == 0xE0 && second < 0xA0) || (lead == 0xED && second > 0x9F) ||
      (lead == 0xF0 && second < 0x90) || (lead == 0xF4 && second > 0x8F))
    return 0;
  return n;
}

// `text` shown; `caret` (if given) receives the spaces and tabs that put a
// caret under byte `column_offset` of it, one per character shown.
std::string shown_text(std::string_view text, std::size_t column_offset = 0,
                       std::string* caret = nullptr) {
  std::string shown;
  for (std::size_t k = 0; k < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[k]);
    std::size_t n = (c >= 0x20 && c < 0x7F) || c == '\t' ? 1 : utf8_length(text, k);
    if (n == 0) {
      shown += '?';
      n = 1;
    } else {
      shown.append(text.substr(k, n));
    }
    if (caret && k < column_offset) *caret += c == '\t' ? '\t' : ' ';
    k += n;
  }
  return shown;
}

// The InputError "path:line:column: error: message", the line and a caret
// under the column (1-based, in bytes). A line longer than 160 bytes is shown
// as the 100 bytes around the column, with "..." where it is cut.
InputError csv_error(const std::string& path, std::size_t line, std::size_t column,
                     std::string_view text, const std::string& message) {
  std::size_t first = 0, last = text.size();
  const std::size_t at = std::min(column - 1, text.size());
  if (text.size() > 160) {
    first = at > 60 ? at - 60 : 0;
    last = std::min(text.size(), first + 100);
  }
  std::string caret = first > 0 ? "   " : "";
  std::string shown = (first > 0 ? "..." : "") +
                      shown_text(text.substr(first, last - first), at - first, &caret) +
                      (last < text.size() ? "..." : "");
  return InputError(path + ":" + std::to_string(line) + ":" + std::to_string(column) +
                    ": error: " + message + "\n" + shown + "\n" + caret + "^");
}

// The first byte of `line` that has no place in a text file (a control
// character other than a tab), or npos.
std::size_t find_control_character(std::string_view line) {
  for (std::size_t k = 0; k < line.size(); ++k) {
    const unsigned char c = static_cast<unsigned char>(line[k]);
    if ((c < 0x20 && c != '\t') || c == 0x7F) return k;
  }
  return std::string_view::npos;
}

std::string describe_control_character(char c) {
  if (c == '\r') return "a carriage return inside a line (lines end with \"\\n\" or \"\\r\\n\")";
  if (c == '\0') return "a NUL byte in the text; is this a CSV file?";
  const char* hex = "0123456789ABCDEF";
  const auto byte = static_cast<unsigned char>(c);
  return std::string("control character 0x") + hex[byte >> 4] + hex[byte & 15] +
         " in the text; is this a CSV file?";
}

// Lines of a text file without their "\r\n" or "\n", and without the byte
// order mark that spreadsheet programs put in front of the first line.
// A line is read up to max_line_length bytes: a file without line breaks
// (binary data, /dev/zero) cannot fill the memory.
class CsvLineReader {
 public:
  static constexpr std::size_t max_line_length = std::size_t{16} << 20;  // 16 MiB

  explicit CsvLineReader(const std::string& path) : path_(path) {
    if (std::filesystem::is_directory(path))
      throw InputError(path + ": error: this is a directory, not a CSV file");
    in_.open(path, std::ios::binary);
    if (!in_) throw InputError(path + ": error: cannot open: " + std::strerror(errno));
  }

  bool next(std::string& line) {
    line.clear();
    ended_ = false;
    using Traits = std::char_traits<char>;
    std::streambuf& in = *in_.rdbuf();
    try {  // libstdc++'s filebuf throws where the system's read fails
      for (Traits::int_type c = in.sbumpc(); c != Traits::eof(); c = in.sbumpc()) {
        if (c == '\n') {
          ended_ = true;
          break;
        }
        if (line.size() == max_line_length)
          throw csv_error(path_, number_ + 1, 1, line,
                          "a line longer than 16 MiB; is this a CSV file?");
        line.push_back(Traits::to_char_type(c));
      }
    } catch (const std::ios_base::failure&) {
      throw InputError(path_ + ": error: read failed: " + std::strerror(errno));
    }
    if (line.empty() && !ended_) return false;
    ++number_;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (number_ == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
    return true;
  }

  std::size_t number() const { return number_; }  // 1-based number of the last line read
  bool ended() const { return ended_; }  // whether that line ended with "\n" (else: the file did)

 private:
  std::string path_;
  std::ifstream in_;
  std::size_t number_ = 0;
  bool ended_ = false;
};

struct CsvField {
  std::size_t offset;     // 0-based byte offset in the line of the trimmed text
  std::string_view text;  // without the spaces and tabs around it
};

bool is_csv_space(char c) { return c == ' ' || c == '\t'; }

std::vector<CsvField> split_csv_line(std::string_view line) {
  std::vector<CsvField> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = std::min(line.find(',', start), line.size());
    std::size_t first = start, last = comma;
    while (first < last && is_csv_space(line[first])) ++first;
    while (last > first && is_csv_space(line[last - 1])) --last;
    fields.push_back({first, line.substr(first, last - first)});
    if (comma == line.size()) return fields;
    start = comma + 1;
  }
}

bool is_blank(std::string_view line) { return std::all_of(line.begin(), line.end(), is_csv_space); }

// Parses the whole field; on failure returns what is wrong with it.
std::string parse_csv_number(std::string_view text, double& value) {
  if (text.empty()) return "expected a number, got an empty field";
  std::string_view digits = text;
  // from_chars rejects a leading '+', which some writers emit.
  if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-') digits.remove_prefix(1);
  const char* end = digits.data() + digits.size();
  const auto [stop, error] = std::from_chars(digits.data(), end, value);
  if (error == std::errc() && stop == end && std::isfinite(value)) return "";
  if (error == std::errc::result_out_of_range && stop == end) {
    // Too small a magnitude would read as 0, changing what the number is
    // (a divisor, a mass): refused like one too large. Subnormals are read.
    if (std::abs(std::strtod(std::string(digits).c_str(), nullptr)) < 1)
      return quoted(text) +
             " is too small for a double: it would read as 0 (write 0 if that is meant)";
    return quoted(text) + " is out of the range of a double";
  }
  if (error != std::errc() || stop != end) return "expected a number, got " + detail::quoted(text);
  return "expected a finite number, got " + detail::quoted(text);
}

}  // namespace

// A field or name quoted in a message: shown, and cut after 40 bytes.
std::string quoted(std::string_view text) {
  constexpr std::size_t longest = 40;
  if (text.size() <= longest) return "'" + shown_text(text) + "'";
  return "'" + shown_text(text.substr(0, longest)) + "...' (" + std::to_string(text.size()) +
         " bytes)";
}

std::string join(const std::vector<std::string>& words) {
  std::string joined;
  for (const auto& word : words) joined += (joined.empty() ? "" : ", ") + word;
  return joined;
}

}  // namespace detail

int CsvTable::column(const std::string& name) const {
  if (index_.size() != header.size()) {
    index_.clear();
    for (std::size_t c = 0; c < header.size(); ++c) index_.emplace(header[c], static_cast<int>(c));
  }
  const auto found = index_.find(name);
  return found == index_.end() ? -1 : found->second;
}

InputError CsvTable::error_at(std::size_t line, std::size_t field,
                              const std::string& message) const {
  const std::string text = line_text(line);
  const auto fields = detail::split_csv_line(text);
  const std::size_t column = field < fields.size() ? fields[field].offset + 1 : text.size() + 1;
  return detail::csv_error(path, line, column, text, message);
}

std::string CsvTable::field_text(std::size_t line, std::size_t field) const {
  const std::string text = line_text(line);
  const auto fields = detail::split_csv_line(text);
  return field < fields.size() ? std::string(fields[field].text) : std::string();
}

std::string CsvTable::line_text(std::size_t line) const {
  std::string text;
  if (!texts.empty()) {
    if (line >= 1 && line <= texts.size()) text = texts[line - 1];
  } else {
    detail::CsvLineReader reader(path);
    while (reader.number() < line && reader.next(text)) continue;
  }
  return text;
}

CsvTable read_csv(const std::string& path) {
  CsvTable table;
  table.path = path;
  detail::CsvLineReader reader(path);
  std::string line;

  // What no line may hold: a control character (a binary file, or old Mac
  // line ends "\r"), and what ends a file before its last line break.
  const auto check_text = [&](const std::string& text) {
    const std::size_t bad = detail::find_control_character(text);
    if (bad != std::string::npos)
      throw detail::csv_error(path, reader.number(), bad + 1, text,
                              detail::describe_control_character(text[bad]));
    if (!reader.ended() && !detail::is_blank(text))
      throw detail::csv_error(path, reader.number(), text.size() + 1, text,
                              "the file ends inside this line, without its line break: is it "
                              "truncated? (a complete file ends with a line break)");
  };

  if (!reader.next(line) || detail::is_blank(line))
    throw detail::csv_error(path, 1, 1, line,
                            "expected a header line naming the columns, such as 'id,p_0,p_1'");
  check_text(line);
  const bool rereadable = std::filesystem::is_regular_file(path);
  if (!rereadable) table.texts.push_back(line);
  const auto names = detail::split_csv_line(line);
  // A first line of numbers is data without its header, whatever else is wrong with it.
  const bool all_numbers = std::all_of(names.begin(), names.end(), [](const detail::CsvField& f) {
    double ignored;
    return detail::parse_csv_number(f.text, ignored).empty();
  });
  if (all_numbers)
    throw detail::csv_error(path, 1, 1, line,
                            "the first line must name the columns, but it holds numbers; is the "
                            "header line missing?");
  std::unordered_map<std::string_view, std::size_t> seen;  // a linear check: 100000 columns
  for (const auto& name : names) {
    if (name.text.empty())
      throw detail::csv_error(path, 1, name.offset + 1, line, "empty column name");
    const auto [previous, fresh] = seen.emplace(name.text, seen.size());
    if (!fresh)
      throw detail::csv_error(path, 1, name.offset + 1, line,
                              "duplicate column name " + detail::quoted(name.text) +
                                  " (also column " + std::to_string(previous->second + 1) + ")");
    table.header.emplace_back(name.text);
  }

  std::size_t first_blank = 0;  // blank lines are fine only at the end
  while (reader.next(line)) {
    if (!rereadable) table.texts.push_back(line);
    check_text(line);
    if (detail::is_blank(line)) {
      if (first_blank == 0) first_blank = reader.number();
      continue;
    }
    if (first_blank != 0)
      throw detail::csv_error(path, first_blank, 1, "",
                              "blank line inside the data (only trailing blank lines are allowed)");
    const auto fields = detail::split_csv_line(line);
    if (fields.size() != names.size()) {
      const std::size_t column =
          fields.size() > names.size() ? fields[names.size()].offset + 1 : line.size() + 1;
      throw detail::csv_error(path, reader.number(), column, line,
                              "expected " + std::to_string(names.size()) +
                                  " fields as in the header, got " + std::to_string(fields.size()));
    }
    std::vector<double> row(fields.size());
    for (std::size_t c = 0; c < fields.size(); ++c) {
      const std::string problem = detail::parse_csv_number(fields[c].text, row[c]);
      if (!problem.empty())
        throw detail::csv_error(path, reader.number(), fields[c].offset + 1, line,
                                problem + " in column '" + table.header[c] + "'");
    }
    table.rows.push_back(std::move(row));
    table.lines.push_back(reader.number());
  }
  return table;
}

namespace detail {

namespace {

constexpr double largest_exact_integer = 9007199254740992.0;  // 2^53

void check_integers(const CsvTable& table, std::size_t c, double low, double high,
                    const char* what) {
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const double x = table.rows[r][c];
    if (x != std::floor(x) || x < low || x > high) {
      std::string message = "column '" + table.header[c] + "' holds " + what + ", got ";
      append_number(message, x);
      if (std::abs(x) >= largest_exact_integer) {  // it may not be what was written
        const std::string written = table.field_text(table.lines[r], c);
        if (message.compare(message.size() - written.size(), written.size(), written) != 0)
          message += " (the double nearest to " + detail::quoted(written) + ")";
      }
      throw table.error_at(table.lines[r], c, message);
    }
  }
}

// How a variable is stored, which says what its columns may hold.
enum class StoredAs { real, single, boolean, integer };

StoredAs stored_as(const ColumnView& column) {
  switch (column.element) {
    case Element::f32: return StoredAs::single;
    case Element::u8: return StoredAs::boolean;
    case Element::i64: return StoredAs::integer;
    case Element::f64: break;
  }
  return StoredAs::real;
}

// Every column of the table is one of `known`.
void check_known_columns(const CsvTable& table, const std::vector<std::string>& known) {
  for (std::size_t c = 0; c < table.header.size(); ++c)
    if (std::find(known.begin(), known.end(), table.header[c]) == known.end())
      throw table.error_at(
          1, c,
          "unknown column " + detail::quoted(table.header[c]) + "; the columns are " + join(known));
}

// The CSV columns of one variable (all present or none, the positions
// always), each value one the variable can hold.
void check_variable_columns(const CsvTable& table, const ColumnView& variable) {
  const char* name = variable.name;
  const StoredAs stored = stored_as(variable);
  const std::vector<std::string> columns =
      csv_column_names(name, variable.is_vec, variable.components);
  for (const auto& column : columns) {
    const int found = table.column(column);
    if (found < 0) {
      const bool required = std::strcmp(name, "p") == 0;
      const bool partial =
          std::any_of(columns.begin(), columns.end(),
                      [&](const std::string& other) { return table.column(other) >= 0; });
      if (required || partial)
        throw table.error_at(
            1, table.header.size(),
            "missing column '" + column + "' (" +
                (required ? "positions are required" : "a vec needs all its components") + ")");
      continue;
    }
    const auto c = static_cast<std::size_t>(found);
    switch (stored) {
      case StoredAs::single:
        // A finite double beyond a float's range would become inf.
        for (std::size_t r = 0; r < table.rows.size(); ++r)
          if (std::abs(table.rows[r][c]) > std::numeric_limits<float>::max()) {
            std::string message = "column '" + column + "' is stored as float, which cannot hold ";
            append_number(message, table.rows[r][c]);
            throw table.error_at(table.lines[r], c, message);
          }
        break;
      case StoredAs::boolean: check_integers(table, c, 0, 1, "0 or 1 (a bool)"); break;
      case StoredAs::integer:
        check_integers(table, c, -largest_exact_integer, largest_exact_integer, "integers");
        break;
      case StoredAs::real: break;
    }
  }
}

// Column c holds distinct non-negative integer ids below 2^53.
void check_ids(const CsvTable& table, std::size_t c) {
  // Below 2^53: a larger id may already have been rounded to a neighbour on reading.
  check_integers(table, c, 0, largest_exact_integer - 1, "non-negative integer ids below 2^53");
  std::unordered_map<std::int64_t, std::size_t> row_of_id;
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const auto id = static_cast<std::int64_t>(table.rows[r][c]);
    if (const auto [previous, inserted] = row_of_id.emplace(id, r); !inserted)
      throw table.error_at(table.lines[r], c,
                           "duplicate id " + std::to_string(id) + " (also on line " +
                               std::to_string(table.lines[previous->second]) + ")");
  }
}

}  // namespace

void check_loadable(const CsvTable& table, const SetView& set) {
  check_known_columns(table, csv_columns_of(set));
  for (const ColumnView& column : set.columns) check_variable_columns(table, column);
  const int id_column = table.column("id");
  if (id_column >= 0) check_ids(table, static_cast<std::size_t>(id_column));
}

}  // namespace detail

}  // namespace partc
