// partc/errors.cpp: the messages of InputError and NumericalError (errors.hpp).
#include "partc/errors.hpp"

#include <sstream>

namespace partc {

std::string InputError::located(const std::string& path, std::size_t line, std::size_t column,
                                const std::string& line_text, const std::string& message) {
  std::string caret;
  for (std::size_t k = 0; k + 1 < column && k < line_text.size(); ++k)
    caret += line_text[k] == '\t' ? '\t' : ' ';
  caret += '^';
  return path + ":" + std::to_string(line) + ":" + std::to_string(column) + ": error: " + message +
         "\n" + line_text + "\n" + caret;
}

std::string NumericalError::describe(const std::string& set, const std::string& variable,
                                     std::int64_t id, std::int64_t step, double value) {
  std::ostringstream text;
  text << "numerical blow-up: variable '" << variable << "' of particle id " << id << " is ";
  // A NaN's sign bit is meaningless; libstdc++ would print "-nan".
  if (std::isnan(value))
    text << "nan";
  else
    text << value;
  text << " at step " << step << " (set " << set << ")";
  return text.str();
}

}  // namespace partc
