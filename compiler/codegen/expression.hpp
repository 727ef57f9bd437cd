// Prints IR expressions as C++ expressions.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "ir/ir.hpp"

namespace partc::codegen {

// What the names in an expression are called in the kernel being emitted.
struct ExpressionNames {
  int home_set = 0;                 // the set the statement's label (i) runs over
  std::vector<std::string> labels;  // loop index per statement label
  std::function<std::string(int set, int var)> array;  // local array of a variable
  std::vector<std::string> params;                     // each param's name (default params_.NAME)
  std::vector<std::string> consts;                     // member (or local) holding each const
  std::vector<std::string> observables;                // member (or local) holding each observable
  std::vector<std::string> functions;                  // member function of each user fn
  std::map<int, std::string> accumulators;             // Accumulate::id -> its variable
  std::string dx_norm;                                 // set when |dx| is computed once per pair
};

// C++ for `e`; the runtime's partc::Vec<dim> is spelled `Vec`. With
// `operand_of`, parenthesised as needed to be the right operand of that
// operator (for `p[i] + (a - b)` style updates).
std::string emit_expression(const ir::Expr& e, const ir::Model& model,
                            const ExpressionNames& names);
std::string emit_operand(const ir::Expr& e, ir::BinaryOp operand_of, const ir::Model& model,
                         const ExpressionNames& names);

// `element` (an array element such as "v[i]") of variable `var` of set `set`
// as kernels compute with it: as it is, or partc::widen(v[i]) when the
// variable is stored as float, so that every expression computes in double.
std::string emit_load(const ir::Model& model, int set, int var, const std::string& element);

// A literal of the given type, e.g. "0.0", "3", "true".
std::string emit_literal(ir::Type type, double value);
// As `type`; an int exactly, in all 64 bits.
std::string emit_literal(ir::Type type, const ir::Literal& literal);

// The C++ type holding a value of `type` in a model of dimension `dim`.
std::string cpp_type(ir::Type type);

}  // namespace partc::codegen
