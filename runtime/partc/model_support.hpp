// partc/model_support.hpp: small pieces every generated model uses.
//
// - ParamInfo / parse_param: parameters as text, for --set and --help.
// - load_set: a particle set from a CSV table, with the model's declared
//   initial values for the variables the table lacks, and positions wrapped
//   into the periodic domain.
//
// Surprises: parse_param accepts the whole text or throws (no "10abc");
// bools are true/false/1/0.
#pragma once

#include <charconv>
#include <cstdint>
#include <string>
#include <system_error>

#include "partc/csv.hpp"
#include "partc/domain.hpp"
#include "partc/errors.hpp"

namespace partc {

// One model parameter as --help shows it: name, type ("int", "real", ...), default.
struct ParamInfo {
  const char* name;
  const char* type;
  std::string default_value;
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

// Replaces the particles of `set` with the table's (see partc::load_set in
// csv.hpp for the columns); `initialise(i)` first gives particle i the
// model's declared initial values, which the table's columns then override.
template <class Set, class Initialise>
void load_set(Set& set, const CsvTable& table, const Domain<Set::dim>& domain,
              Initialise&& initialise) {
  load_set(table, set, initialise);
  for (auto& x : set.positions()) x = domain.wrap(x);
}

}  // namespace partc
