// Text form of the IR, for --emit=ir and for debugging passes.
#pragma once

#include <string>

#include "ir/ir.hpp"

namespace partc::ir {

// An expression in .part-like syntax, fully parenthesised, with labels by
// name; accumulations and random draws show their ids.
std::string to_string(const Expr& e, const Model& model, const std::vector<Label>& labels);

// The whole model: header, params, consts, sets and stages with types.
std::string to_string(const Model& model);

}  // namespace partc::ir
