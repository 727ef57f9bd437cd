// Fusion across statements: a variable an effect owns that one statement
// of the step sets and one later statement reads, at its own particle
// only, is computed inside its reader instead of stored.
//
// Runs after sema and before the analyses, which then see the fused
// statement as if written so: its sums, searches and symmetry are the
// writer's, its pass over the set is the reader's. This is what makes a
// symplectic Euler scene cost what one hand-written statement does: the
// force channel f, set at slot force and read at slot kick, is not stored
// and needs no pass of its own. Legal only when nothing between the two
// statements writes anything the writer reads (the value would differ), the
// reader reads the variable at i outside every sum (a sum would evaluate the
// writer's sums once per pair) and once (twice would compute it twice), and no
// output, initial value or other statement reads it.
#pragma once

#include <string>
#include <vector>

#include "ir/ir.hpp"

namespace partc::ir {

struct InlinedVariable {
  std::string set, var;  // no longer stored
  Location writer, reader;
};
struct InlineRefusal {
  std::string set, var;
  std::string reason;  // why it stays stored
};
struct SingleUseReport {
  std::vector<InlinedVariable> inlined;
  std::vector<InlineRefusal> refused;
};

// Rewrites `model`: each eligible variable's writer is removed, its value
// put where the reader reads it, and the variable removed from its set.
SingleUseReport inline_single_use(Model& model);

}  // namespace partc::ir
