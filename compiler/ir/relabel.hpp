// One statement's expressions inside another's: its labels appended to the
// other's, so one label table names both. Label 0, the particle the
// statement updates, stays 0: both statements update the same one. Fusion
// needs it twice: inline_single_use puts a writer's value in its reader,
// and a fused pass (analysis/statement_fusion) names every member's sums
// with its first member's table.
#pragma once

#include "ir/ir.hpp"

namespace partc::ir {

// e with its labels l >= 1 renumbered base + l - 1 (base: the other
// statement's label count).
Expr append_labels(const Expr& e, int base);

}  // namespace partc::ir
