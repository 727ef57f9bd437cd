// partc/errors.hpp: the three ways a partc model run can fail on the user's side.
//
//   InputError      a bad data file; what() is a complete compiler-style message,
//                   "file:line:col: error: ...", then the offending line and a caret.
//   UsageError      a bad command-line argument or parameter value.
//   NumericalError  a NaN or Inf in a particle variable, with where and when;
//                   or a failed linear solve (solve/), with the solve's own text.
//
// The driver maps them to exit codes 1, 2 and 3. Surprise: a particle
// variable's NumericalError message ends with the set name in parentheses,
// because two sets may both have a variable 'v'. The messages are composed
// in the runtime library (errors.cpp).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

namespace partc {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;

  // `column` is 1-based and counts bytes; the caret line copies the tabs of
  // `line_text` so that the caret stays under the column in any terminal.
  InputError(const std::string& path, std::size_t line, std::size_t column,
             const std::string& line_text, const std::string& message)
      : std::runtime_error(located(path, line, column, line_text, message)) {}

 private:
  static std::string located(const std::string& path, std::size_t line, std::size_t column,
                             const std::string& line_text, const std::string& message);
};

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct NumericalError : std::runtime_error {
  NumericalError(std::string set_name, std::string variable_name, std::int64_t particle_id,
                 std::int64_t at_step, double bad_value)
      : std::runtime_error(describe(set_name, variable_name, particle_id, at_step, bad_value)),
        set(std::move(set_name)),
        variable(std::move(variable_name)),
        id(particle_id),
        step(at_step),
        value(bad_value) {}

  // A failure that is not one particle's value, such as a solve's NaN matrix
  // entry or its iterative method's non-convergence: the message says it all,
  // set and variable are empty, id and step -1, value NaN.
  explicit NumericalError(const std::string& message)
      : std::runtime_error(message), id(-1), step(-1), value(std::nan("")) {}

  std::string set;
  std::string variable;
  std::int64_t id;
  std::int64_t step;
  double value;

 private:
  static std::string describe(const std::string& set, const std::string& variable, std::int64_t id,
                              std::int64_t step, double value);
};

}  // namespace partc
