// partc/model_support.hpp: small pieces every generated model uses.
//
// - ParamInfo / parse_param: parameters as text, for --set and --help.
// - SearchReport: what a neighbour search is and how often it was built.
// - max_over: the largest value over a set's particles.
// - shown: a number for a message, in 6 significant digits.
// - load_set: a particle set from a CSV table, with the model's declared
//   initial values for the variables the table lacks, and positions wrapped
//   into the periodic domain (at their precision: Domain::wrap_into); with
//   reflecting or open faces, a position outside them is an error.
//
// Surprises: parse_param accepts the whole text or throws (no "10abc");
// bools are true/false/1/0.
#pragma once

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <iomanip>
#include <sstream>
#include <string>
#include <system_error>

#include "partc/domain.hpp"
#include "partc/errors.hpp"
#include "partc/faces.hpp"
#include "partc/io/csv.hpp"

namespace partc {

// One model parameter as --help shows it: name, type ("int", "real", ...), default.
struct ParamInfo {
  const char* name;
  const char* type;
  std::string default_value;
};

// One neighbour search or set of Verlet lists of a model, for the driver's summary:
// what it serves, its structure (describe()), and its builds so far.
struct SearchReport {
  std::string serves;
  std::string structure;
  std::size_t builds;
  std::size_t walks = 0;  // passes over the pairs (NeighbourSearch::note_walk)
};

template <class T>
T parse_param(const std::string& name, const std::string& text) {
  if constexpr (std::is_same_v<T, bool>) {
    if (text == "true" || text == "1") return true;
    if (text == "false" || text == "0") return false;
    throw UsageError("parameter " + name + " expects true or false, got '" + text + "'");
  } else {
    T value{};
    const char* end = text.data() + text.size();
    const auto [stop, error] = std::from_chars(text.data(), end, value);
    if (text.empty() || error != std::errc() || stop != end)
      throw UsageError("parameter " + name + " expects " +
                       (std::is_integral_v<T> ? "an int" : "a real number") + ", got '" + text +
                       "'");
    return value;
  }
}

template <class T>
std::string shown(T value) {
  std::ostringstream text;
  text << std::setprecision(6) << value;
  return text.str();
}

// The largest value(n) over k < n, or 0 with no particles: sizes a search
// whose bound varies per particle (|dx| < r[i] + r[j]).
template <class Value>
double max_over(std::size_t n, Value&& value) {
  if (n == 0) return 0.0;
  double largest = value(std::size_t{0});
  for (std::size_t k = 1; k < n; ++k) largest = std::max(largest, static_cast<double>(value(k)));
  return largest;
}

// Replaces the particles of `set` with the table's (see partc::load_set in
// csv.hpp for the columns); `initialise(i)` first gives particle i the
// model's declared initial values, which the table's columns then override.
template <class Set, class Initialise>
void load_set(Set& set, const CsvTable& table, const Domain<Set::dim>& domain,
              Initialise&& initialise) {
  load_set(table, set, initialise);
  for (auto& x : set.positions()) domain.wrap_into(x, widen(x));
}

// The same for a model with reflecting or open faces, refusing a row whose
// position is outside them: [lo, hi] along a reflecting axis, [lo, hi) along
// an open one. The first step would otherwise fold such a particle back in,
// or remove it, without a word.
template <class Set, class Initialise>
void load_set(Set& set, const CsvTable& table, const Domain<Set::dim>& domain,
              const Faces<Set::dim>& faces, Initialise&& initialise) {
  for (int k = 0; k < Set::dim; ++k) {
    const int column = table.column("p_" + std::to_string(k));
    if (column < 0 || !(faces.reflect[k] || faces.open[k])) continue;  // load_set says what is missing
    const double lo = faces.lo[k], hi = faces.hi[k];
    for (std::size_t r = 0; r < table.rows.size(); ++r) {
      const double x = table.rows[r][static_cast<std::size_t>(column)];
      if (x >= lo && (faces.open[k] ? x < hi : x <= hi)) continue;
      throw table.error_at(table.lines[r], static_cast<std::size_t>(column),
                           "p_" + std::to_string(k) + " = " + shown(x) + " is outside the " +
                               (faces.open[k] ? "open" : "reflecting") + " faces at " + shown(lo) +
                               " and " + shown(hi) + (faces.open[k] ? " (lo <= p < hi)" : ""));
    }
  }
  load_set(set, table, domain, initialise);
}

}  // namespace partc
