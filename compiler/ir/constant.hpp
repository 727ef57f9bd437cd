// Evaluation of expressions whose value is known at compile time.
#pragma once

#include <optional>

#include "ir/ir.hpp"

namespace partc {

// The value of an expression built only from literals, operators, builtin
// functions and consts that are themselves literal; nullopt otherwise (it
// reads a param, a particle, a random number, ...). Booleans are 0/1.
std::optional<double> evaluate_constant(const ir::Expr& e, const ir::Model& model);

// True when the expression depends on nothing that varies per particle or
// per step: only literals, params and consts.
bool is_uniform(const ir::Expr& e);

}  // namespace partc
