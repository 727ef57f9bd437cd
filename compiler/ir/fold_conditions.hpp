// Conditionals decided when partc runs: if(c, a, b) whose condition is a
// constant -- an effect's const parameter choosing its kernel,
// `use sph.pressure(const kernel = 1)`, or a scene's const -- becomes the
// branch c chooses, so the other is neither computed nor emitted (with
// drop_unread_declarations, nor the functions only it called).
//
// Runs after sema, where consts have values, and before fold_zero_terms (a
// chosen branch can be a constant 0 factor) and the analyses, which see only
// the branch kept: its variables, its searches. Folds the statements, not
// the functions' bodies: a const a body can read is the model's (dim, a
// module's own const), not a choice a scene makes per effect, and a body is
// emitted once, where the C++ compiler folds `2 == 1 ? a : b` itself. A
// branch of another type than the conditional's (an int in a real if) is
// left as it was: the conditional converts it.
#pragma once

#include <string>
#include <vector>

#include "ir/ir.hpp"

namespace partc::ir {

struct FoldedCondition {
  std::string effect;  // empty: in a statement of the model's own
  Location loc;        // the if(...)
  bool condition;      // its value: true keeps the first branch
};

// Rewrites `model`; returns the conditionals folded, in statement order.
std::vector<FoldedCondition> fold_conditions(Model& model);

}  // namespace partc::ir
