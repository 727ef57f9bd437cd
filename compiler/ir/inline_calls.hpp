// User-function calls replaced by the functions' bodies, for analyses that
// must see what a call computes (is amix(a[i], a[j]) symmetric in i and j?)
// rather than trust only its arguments.
#pragma once

#include <cstddef>

#include "ir/ir.hpp"

namespace partc::ir {

// e with every FnCall replaced by its function's body, each argument put
// where the body reads it (functions are pure, so this is the value the
// call computes). Null when that would take more than `max_calls` calls
// inlined: a function that calls another twice, and so on, grows as 2^depth.
Expr inline_calls(const Expr& e, const Model& model, std::size_t max_calls = 1000);

}  // namespace partc::ir
