// partc/io/csv.hpp: particle sets to and from CSV files, one row per particle.
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
//   would reject them at step 0 anyway, with a worse location). So are a
//   magnitude too small for a double ("1e-400" would read as 0; subnormals
//   are read), hexadecimal floats, quoted fields, control characters (NUL, a
//   lone "\r") and a last line without its line break, which is how a
//   truncated file ends ("0.1" may be the start of "0.15"). CRLF, a leading
//   '+' and spaces around fields are fine; a header without rows is 0 particles.
// - Messages show the file's text safely: bytes that are neither printable
//   ASCII nor valid UTF-8 as '?', a line over 160 bytes as the 100 around the
//   column, a quoted field cut after 40 bytes. A line over 16 MiB is an error
//   (/dev/zero or a binary file cannot fill the memory).
// - Numbers are written in the shortest form that reads back to the same
//   double ("0.1", not "0.10000000000000001"): a round trip is exact. Data
//   stored as float (a schedule's precision = float) is written as the double
//   it widens to, so it reads back as that double, which rounds to the same
//   float: exact too. Loading a float variable rounds each value to the
//   nearest float; one beyond a float's range is an error at its field.
// - Writers go through path + ".tmp" and a rename, so a failure or a crash
//   never leaves a half-written file under the real name (output_file.hpp;
//   a link, a pipe or a device such as /dev/stdout is written in place).
//   vtk.hpp shares these helpers (partc::detail) rather than keep a twin copy.
// - What does not depend on the set's type (reading, the checks, the
//   messages, writing a SetView) is compiled once, in the runtime library
//   (csv.cpp): link partc_runtime.
#pragma once

#include <algorithm>
#include <charconv>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

#include "partc/errors.hpp"
#include "partc/finite.hpp"
#include "partc/io/output_file.hpp"
#include "partc/io/set_view.hpp"
#include "partc/vec.hpp"

namespace partc {

namespace detail {

// A field or name quoted in a message, as messages show a file's text
// (printable ASCII, tabs and valid UTF-8 as they are, any other byte as '?'),
// and cut after 40 bytes.
std::string quoted(std::string_view text);

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

// "a, b, c".
std::string join(const std::vector<std::string>& words);

// The CSV column names of one variable: v, or v_0 .. v_{D-1} for a Vec<D>.
std::vector<std::string> csv_column_names(const std::string& name, bool is_vec, int components);

// Every CSV column of a set, in file order: id, p_0 .. p_{D-1}, then the variables.
std::vector<std::string> csv_columns_of(const SetView& set);

// The set's indices in increasing id order: files are keyed by id whatever
// order the set keeps its particles in, and a loaded set is stored so.
std::vector<std::size_t> id_order(const std::int64_t* ids, std::size_t n);

}  // namespace detail

struct CsvTable;

namespace detail {

// load_set's checks, before it touches the set, throwing the InputError of
// the first field at fault: every column of the table is one of the set's;
// each variable has all its columns or none (the positions all); each value
// is one its variable can hold (stored as float: within a float's range;
// bool: 0 or 1; int: an integer); ids are distinct non-negative integers
// below 2^53.
void check_loadable(const CsvTable& table, const SetView& set);

}  // namespace detail

struct CsvTable {
  std::string path;
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  std::vector<std::size_t> lines;  // 1-based file line of each row; the header is line 1
  // The text of every line, kept only when the file cannot be read again (a
  // pipe, /dev/stdin), for error_at.
  std::vector<std::string> texts;

  // The index of the column named `name`, or -1.
  int column(const std::string& name) const;

  // An error pointing at field `field` of file line `line` (a field index past
  // the last points just after the line's end, for "missing ..."). The line is
  // read again from a regular file: a table does not keep its text, errors
  // are rare.
  InputError error_at(std::size_t line, std::size_t field, const std::string& message) const;

  // The text of field `field` of file line `line`, as written (read again as error_at does).
  std::string field_text(std::size_t line, std::size_t field) const;

  // File line `line` (1-based): kept, or read again.
  std::string line_text(std::size_t line) const;

 private:
  mutable std::unordered_map<std::string, int> index_;  // header name -> column, built on use
};

CsvTable read_csv(const std::string& path);

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
  detail::check_loadable(table, view_of("", std::as_const(set)));
  const int id_column = table.column("id");
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
    const auto columns =
        detail::csv_column_names(name, StorageTraits<S>::is_vec, StorageTraits<S>::components);
    for (std::size_t k = 0; k < columns.size(); ++k) {
      const int found = table.column(columns[k]);
      if (found < 0) continue;
      for (std::size_t r = 0; r < table.rows.size(); ++r) {
        const double x = table.rows[r][static_cast<std::size_t>(found)];
        // Integral where S is, checked above; rounded to the nearest float where S holds floats.
        if constexpr (StorageTraits<S>::is_vec)
          values[r][static_cast<int>(k)] = static_cast<typename S::value_type>(x);
        else
          values[r] = static_cast<S>(x);
      }
    }
  });
  // Kept in id order, as init creates them: the order of the rows must not
  // change a result (sums within a cell run in storage order).
  set.permute(detail::id_order(set.ids().data(), set.size()));
}

template <class Set>
void load_set(const CsvTable& table, Set& set) {
  load_set(table, set, [](std::size_t) {});
}

void write_csv(const std::string& path, const SetView& set);

template <class Set>
void write_csv(const std::string& path, const Set& set) {
  write_csv(path, view_of("", set));
}

}  // namespace partc
