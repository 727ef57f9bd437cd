// Fast sums: which dense sums the schedule runs by a fast method
// (`dense = fmm`), and the kernel and charge each one factors into.
#pragma once

#include <map>
#include <string>

#include "analysis/linear_operator.hpp"
#include "analysis/neighbourhood.hpp"
#include "ir/ir.hpp"

namespace partc {

// sum(j, k(|dx|) * q[j]) (a potential), or sum(j, k(|dx|) * dx * q[j]) (a
// field: a vec), from the particles of `sources` to those of `targets`.
struct FastSumFact {
  ir::Expr kernel;  // reads |dx| (and params, consts, observables), nothing else
  ir::Expr charge;  // reads j's variables (and params, consts, observables), no dx
  bool field = false;
  bool skips_coincident = false;  // the condition is |dx| > 0: k(0) counts as 0
  bool in_solve = false;          // a term of a solve's operator: the charge multiplies w[j]
  int sources = 0, targets = 0;   // sets
  ir::Expr tolerance;             // requested relative L2 error; null with an order or in a solve
  ir::Expr order;                 // Chebyshev nodes per axis; null: from the tolerance
  // The float-stored variables it reads (the sets' p, the charge's), "S.p, S.q":
  // a tolerance finer than their rounding is met for the rounded values only.
  std::string float_inputs;
  int line = 0;        // of the sum, for reports
  std::string reason;  // for --explain
};

// Keyed by Accumulate::id; only sums that run fast are in it.
using FastSumReport = std::map<int, FastSumFact>;

// Throws CompileError where `dense = fmm` is asked of a statement with a
// dense sum it cannot take (saying which factor stops it), of a statement
// without a dense sum, or in a periodic domain. A solve's dense operator
// terms are factored from their coefficients (the linear operators' facts).
FastSumReport find_fast_sums(const ir::Model& model, const NeighbourhoodReport& neighbourhoods,
                             const LinearOperatorReport& operators, const std::string& source);

}  // namespace partc
