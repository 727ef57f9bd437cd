// partc/csv.hpp: particle sets to and from CSV files, one row per particle.
//
//   read_csv(path)          -> CsvTable: a header of names and rows of doubles
//   load_set(table, set[, initialise])  fills a ParticleSet from a CsvTable
//   write_csv(path, set)    writes a ParticleSet, rows in id order
//
// Column names: id, then each variable of for_each_variable ("p" first);
// a Vec<D> variable v is the D columns v_0 .. v_{D-1}; bools are 0/1.
// Surprises:
// - Reading is strict, and every complaint is "file:line:col: error: ..." with
//   the line and a caret: "1.5x", "nan" and "inf" are errors (check_finite
//   would reject them at step 0 anyway, with a worse location).
// - Numbers are written in the shortest form that reads back to the same
//   double ("0.1", not "0.10000000000000001"): a round trip is exact.
// - Writers go through path + ".tmp" and a rename, so a failure or a crash
//   never leaves a half-written file under the real name (output_file.hpp;
//   a link, a pipe or a device such as /dev/stdout is written in place).
//   vtk.hpp shares these helpers (partc::detail) rather than keep a twin copy.
#pragma once

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

#include "partc/errors.hpp"
#include "partc/finite.hpp"
#include "partc/output_file.hpp"
#include "partc/vec.hpp"

namespace partc {

namespace detail {

// Lines of a text file without their "\r\n" or "\n", and without the byte
// order mark that spreadsheet programs put in front of the first line.
class CsvLineReader {
 public:
  explicit CsvLineReader(const std::string& path) : path_(path) {
    if (std::filesystem::is_directory(path))
      throw InputError(path + ": error: this is a directory, not a CSV file");
    in_.open(path, std::ios::binary);
    if (!in_) throw InputError(path + ": error: cannot open: " + std::strerror(errno));
  }

  bool next(std::string& line) {
    if (!std::getline(in_, line)) {
      if (in_.bad()) throw InputError(path_ + ": error: read failed: " + std::strerror(errno));
      return false;
    }
    ++number_;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (number_ == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
    return true;
  }

  std::size_t number() const { return number_; }  // 1-based number of the last line read

 private:
  std::string path_;
  std::ifstream in_;
  std::size_t number_ = 0;
};

struct CsvField {
  std::size_t offset;     // 0-based byte offset in the line of the trimmed text
  std::string_view text;  // without the spaces and tabs around it
};

inline bool is_csv_space(char c) { return c == ' ' || c == '\t'; }

inline std::vector<CsvField> split_csv_line(std::string_view line) {
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

inline bool is_blank(std::string_view line) {
  return std::all_of(line.begin(), line.end(), is_csv_space);
}

// Parses the whole field; on failure returns what is wrong with it.
inline std::string parse_csv_number(std::string_view text, double& value) {
  if (text.empty()) return "expected a number, got an empty field";
  std::string_view digits = text;
  // from_chars rejects a leading '+', which some writers emit.
  if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-') digits.remove_prefix(1);
  const char* end = digits.data() + digits.size();
  const auto [stop, error] = std::from_chars(digits.data(), end, value);
  if (error == std::errc() && stop == end && std::isfinite(value)) return "";
  const std::string quoted = "'" + std::string(text) + "'";
  if (error == std::errc::result_out_of_range) return quoted + " is out of the range of a double";
  if (error != std::errc() || stop != end) return "expected a number, got " + quoted;
  return "expected a finite number, got " + quoted;
}

// The shortest text that reads back as the same value.
inline void append_number(std::string& out, double x) {
  char buffer[32];
  out.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, x).ptr);
}

inline void append_number(std::string& out, std::int64_t x) {
  char buffer[24];
  out.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, x).ptr);
}

// A bool is a number in files, not a character.
inline void append_number(std::string& out, std::uint8_t x) { append_number(out, std::int64_t{x}); }

inline std::string join(const std::vector<std::string>& words) {
  std::string joined;
  for (const auto& word : words) joined += (joined.empty() ? "" : ", ") + word;
  return joined;
}

// The CSV column names of one variable: v, or v_0 .. v_{D-1} for a Vec<D>.
template <class S>
std::vector<std::string> csv_column_names(const std::string& name) {
  std::vector<std::string> names;
  if constexpr (StorageTraits<S>::is_vec) {
    for (int k = 0; k < StorageTraits<S>::components; ++k)
      names.push_back(name + "_" + std::to_string(k));
  } else {
    names.push_back(name);
  }
  return names;
}

// Every CSV column of a set, in file order: id, p_0 .. p_{D-1}, then the variables.
template <class Set>
std::vector<std::string> csv_columns_of(const Set& set) {
  std::vector<std::string> columns = {"id"};
  set.for_each_variable([&](const char* name, const auto& values) {
    using S = typename std::decay_t<decltype(values)>::value_type;
    for (auto& column : csv_column_names<S>(name)) columns.push_back(std::move(column));
  });
  return columns;
}

// The set's indices in increasing id order: files are keyed by id whatever
// order the set keeps its particles in, and a loaded set is stored so.
template <class Set>
std::vector<std::size_t> id_order(const Set& set) {
  std::vector<std::size_t> order(set.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  const auto& ids = set.ids();
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return ids[a] < ids[b]; });
  return order;
}

}  // namespace detail

struct CsvTable {
  std::string path;
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  std::vector<std::size_t> lines;  // 1-based file line of each row; the header is line 1
  // The text of every line, kept only when the file cannot be read again (a
  // pipe, /dev/stdin), for error_at.
  std::vector<std::string> texts;

  int column(const std::string& name) const {
    if (index_.size() != header.size()) {
      index_.clear();
      for (std::size_t c = 0; c < header.size(); ++c) index_.emplace(header[c], static_cast<int>(c));
    }
    const auto found = index_.find(name);
    return found == index_.end() ? -1 : found->second;
  }

  // An error pointing at field `field` of file line `line` (a field index past
  // the last points just after the line's end, for "missing ..."). The line is
  // read again from a regular file: a table does not keep its text, errors
  // are rare.
  InputError error_at(std::size_t line, std::size_t field, const std::string& message) const {
    std::string text;
    if (!texts.empty()) {
      if (line >= 1 && line <= texts.size()) text = texts[line - 1];
    } else {
      detail::CsvLineReader reader(path);
      while (reader.number() < line && reader.next(text)) continue;
    }
    const auto fields = detail::split_csv_line(text);
    const std::size_t column = field < fields.size() ? fields[field].offset + 1 : text.size() + 1;
    return InputError(path, line, column, text, message);
  }

 private:
  mutable std::unordered_map<std::string, int> index_;  // header name -> column, built on use
};

inline CsvTable read_csv(const std::string& path) {
  CsvTable table;
  table.path = path;
  detail::CsvLineReader reader(path);
  std::string line;

  if (!reader.next(line) || detail::is_blank(line))
    throw InputError(path, 1, 1, line,
                     "expected a header line naming the columns, such as 'id,p_0,p_1'");
  const bool rereadable = std::filesystem::is_regular_file(path);
  if (!rereadable) table.texts.push_back(line);
  const auto names = detail::split_csv_line(line);
  // A first line of numbers is data without its header, whatever else is wrong with it.
  const bool all_numbers = std::all_of(names.begin(), names.end(), [](const detail::CsvField& f) {
    double ignored;
    return detail::parse_csv_number(f.text, ignored).empty();
  });
  if (all_numbers)
    throw InputError(path, 1, 1, line,
                     "the first line must name the columns, but it holds numbers; is the "
                     "header line missing?");
  std::unordered_map<std::string_view, std::size_t> seen;  // a linear check: 100000 columns
  for (const auto& name : names) {
    if (name.text.empty()) throw InputError(path, 1, name.offset + 1, line, "empty column name");
    const auto [previous, fresh] = seen.emplace(name.text, seen.size());
    if (!fresh)
      throw InputError(path, 1, name.offset + 1, line,
                       "duplicate column name '" + std::string(name.text) + "' (also column " +
                           std::to_string(previous->second + 1) + ")");
    table.header.emplace_back(name.text);
  }

  std::size_t first_blank = 0;  // blank lines are fine only at the end
  while (reader.next(line)) {
    if (!rereadable) table.texts.push_back(line);
    if (detail::is_blank(line)) {
      if (first_blank == 0) first_blank = reader.number();
      continue;
    }
    if (first_blank != 0)
      throw InputError(path, first_blank, 1, "",
                       "blank line inside the data (only trailing blank lines are allowed)");
    const auto fields = detail::split_csv_line(line);
    if (fields.size() != names.size()) {
      const std::size_t column =
          fields.size() > names.size() ? fields[names.size()].offset + 1 : line.size() + 1;
      throw InputError(path, reader.number(), column, line,
                       "expected " + std::to_string(names.size()) +
                           " fields as in the header, got " + std::to_string(fields.size()));
    }
    std::vector<double> row(fields.size());
    for (std::size_t c = 0; c < fields.size(); ++c) {
      const std::string problem = detail::parse_csv_number(fields[c].text, row[c]);
      if (!problem.empty())
        throw InputError(path, reader.number(), fields[c].offset + 1, line,
                         problem + " in column '" + table.header[c] + "'");
    }
    table.rows.push_back(std::move(row));
    table.lines.push_back(reader.number());
  }
  return table;
}

// Replaces the particles of `set` with the rows of `table`, stored in id order
// whatever the order of the rows.
// Columns: p_0 .. p_{D-1} are required; id is optional (absent: ids 0, 1, ...
// in row order); any other variable is optional, a Vec all or none of its
// columns. `initialise(i)` runs for each new particle i before the table's
// values are copied in, so that a variable the table lacks gets its declared
// initial value (0 without it). A column the set does not have is an error, so
// that a misspelt name cannot silently leave a variable at its default.
// Everything is checked before `set` is touched: on error it is unchanged.
template <class Set, class Initialise>
void load_set(const CsvTable& table, Set& set, Initialise&& initialise) {
  const std::vector<std::string> known = detail::csv_columns_of(set);
  for (std::size_t c = 0; c < table.header.size(); ++c)
    if (std::find(known.begin(), known.end(), table.header[c]) == known.end())
      throw table.error_at(
          1, c, "unknown column '" + table.header[c] + "'; the columns are " + detail::join(known));

  constexpr double largest_exact_integer = 9007199254740992.0;  // 2^53
  const auto check_integers = [&](std::size_t c, double low, double high, const char* what) {
    for (std::size_t r = 0; r < table.rows.size(); ++r) {
      const double x = table.rows[r][c];
      if (x != std::floor(x) || x < low || x > high) {
        std::string message = "column '" + table.header[c] + "' holds " + what + ", got ";
        detail::append_number(message, x);
        throw table.error_at(table.lines[r], c, message);
      }
    }
  };
  std::as_const(set).for_each_variable([&](const char* name, const auto& values) {
    using S = typename std::decay_t<decltype(values)>::value_type;
    const auto columns = detail::csv_column_names<S>(name);
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
      } else if constexpr (std::is_same_v<S, std::uint8_t>) {
        check_integers(static_cast<std::size_t>(found), 0, 1, "0 or 1 (a bool)");
      } else if constexpr (std::is_integral_v<S>) {
        check_integers(static_cast<std::size_t>(found), -largest_exact_integer,
                       largest_exact_integer, "integers");
      }
    }
  });
  const int id_column = table.column("id");
  if (id_column >= 0) {
    const auto c = static_cast<std::size_t>(id_column);
    // Below 2^53: a larger id may already have been rounded to a neighbour on reading.
    check_integers(c, 0, largest_exact_integer - 1, "non-negative integer ids below 2^53");
    std::unordered_map<std::int64_t, std::size_t> row_of_id;
    for (std::size_t r = 0; r < table.rows.size(); ++r) {
      const auto id = static_cast<std::int64_t>(table.rows[r][c]);
      if (const auto [previous, inserted] = row_of_id.emplace(id, r); !inserted)
        throw table.error_at(table.lines[r], c,
                             "duplicate id " + std::to_string(id) + " (also on line " +
                                 std::to_string(table.lines[previous->second]) + ")");
    }
  }

  set.clear();
  set.reserve(table.rows.size());
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const double id =
        id_column < 0 ? static_cast<double>(r) : table.rows[r][static_cast<std::size_t>(id_column)];
    set.push_back_with_id(Vec<Set::dim>::zero(), static_cast<std::int64_t>(id));
    initialise(set.size() - 1);
  }
  set.for_each_variable([&](const char* name, auto& values) {
    using S = typename std::decay_t<decltype(values)>::value_type;
    const auto columns = detail::csv_column_names<S>(name);
    for (std::size_t k = 0; k < columns.size(); ++k) {
      const int found = table.column(columns[k]);
      if (found < 0) continue;
      for (std::size_t r = 0; r < table.rows.size(); ++r) {
        const double x = table.rows[r][static_cast<std::size_t>(found)];
        if constexpr (StorageTraits<S>::is_vec)
          values[r][static_cast<int>(k)] = x;
        else
          values[r] = static_cast<S>(x);  // integral where S is, checked above
      }
    }
  });
  // Kept in id order, as init creates them: the order of the rows must not
  // change a result (sums within a cell run in storage order).
  set.permute(detail::id_order(set));
}

template <class Set>
void load_set(const CsvTable& table, Set& set) {
  load_set(table, set, [](std::size_t) {});
}

template <class Set>
void write_csv(const std::string& path, const Set& set) {
  const auto order = detail::id_order(set);
  detail::write_file_atomically(path, [&](std::ostream& out) {
    std::string line;
    for (const auto& column : detail::csv_columns_of(set))
      line += (line.empty() ? "" : ",") + column;
    out << line << '\n';
    for (const std::size_t i : order) {
      line.clear();
      detail::append_number(line, set.ids()[i]);
      set.for_each_variable([&](const char*, const auto& values) {
        using S = typename std::decay_t<decltype(values)>::value_type;
        for (int k = 0; k < StorageTraits<S>::components; ++k) {
          line += ',';
          detail::append_number(line, StorageTraits<S>::component(values[i], k));
        }
      });
      line += '\n';
      out << line;
    }
  });
}

}  // namespace partc
