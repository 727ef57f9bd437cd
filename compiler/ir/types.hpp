// The value types of the .part language.
#pragma once

#include <string>

namespace partc::ir {

// vec is real^dim; dim is fixed per model.
enum class Type { Bool, Int, Real, Vec };

inline const char* type_name(Type t) {
  switch (t) {
    case Type::Bool: return "bool";
    case Type::Int: return "int";
    case Type::Real: return "real";
    case Type::Vec: return "vec";
  }
  return "?";
}

inline bool is_numeric_scalar(Type t) { return t == Type::Int || t == Type::Real; }

}  // namespace partc::ir
