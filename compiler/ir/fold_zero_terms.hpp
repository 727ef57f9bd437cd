// Terms that are zero whatever the data: a contribution with a factor that
// is a constant 0 -- a scene's `use force.gravity(const g = 0)`, or a
// module's const parameter left at 0 -- is removed from its statement, and a
// contribution that loses every term is removed with it.
//
// Runs after sema, where consts have values, and before fusion and the
// analyses, so that what only the folded term read is neither loaded nor
// searched for: a folded pair term costs no pair walk. A term holding a
// random draw is kept (its instance's noise stays as it is); so is anything
// not provably 0. The folded term's NaN, were its other factor NaN, is not
// computed: a const 0 says the effect is off.
#pragma once

#include <string>
#include <vector>

#include "ir/ir.hpp"

namespace partc::ir {

struct FoldedTerm {
  std::string effect;  // empty: a term of the model's own statement
  Location loc;        // the contribution's statement (the effect's line)
  std::string target;  // SET.var
};

// Rewrites `model`; returns the terms removed, in statement order.
std::vector<FoldedTerm> fold_zero_terms(Model& model);

}  // namespace partc::ir
