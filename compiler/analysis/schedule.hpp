// Schedule checks: what a model's schedule block asks must exist.
#pragma once

#include "analysis/neighbourhood.hpp"
#include "ir/ir.hpp"

namespace partc {

// Throws CompileError for a schedule entry that names a statement with no
// neighbourhood sum (nothing there to search or to keep Verlet lists for).
void check_schedule(const ir::Model& model, const NeighbourhoodReport& neighbourhoods);

}  // namespace partc
