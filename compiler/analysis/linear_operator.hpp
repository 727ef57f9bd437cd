// Linear operators: the left side of each `solve w[i]: operator = rhs`, as
// the rows of a matrix.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "analysis/neighbourhood.hpp"
#include "ir/ir.hpp"

namespace partc {

// One part of row i: scale * coefficient(i, j) * w[j] summed over the j of
// `sum` that satisfy its condition, or scale * w[i] when `sum` is null; it
// applies to the rows where every guard (condition, wanted value) holds.
struct OperatorTerm {
  std::vector<std::pair<ir::Expr, bool>> guards;
  ir::Expr scale;                       // reads i only (params, consts, x[i]); null: 1
  const ir::Accumulate* sum = nullptr;  // null: the diagonal term
  ir::Expr coefficient;                 // the sum's body with w[j] taken as 1; null: 1
};

struct LinearOperatorFact {
  std::vector<OperatorTerm> terms;
  bool sparse = false;  // every sum is a neighbourhood sum: rows hold only neighbours
  std::string reason;   // for --explain
};

// Keyed by (stage, statement), for each solve statement.
using LinearOperatorReport = std::map<std::pair<int, int>, LinearOperatorFact>;

// Throws CompileError when an operator is not linear in its unknown, or is
// linear in a form partc cannot assemble (a constant term, w[j] of another set).
LinearOperatorReport find_linear_operators(const ir::Model& model,
                                           const NeighbourhoodReport& neighbourhoods);

}  // namespace partc
