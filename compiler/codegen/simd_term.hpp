// Highway code for the terms of pair sums, a vector of pairs at a time, over
// a PairBatch (runtime/partc/simd/pair_batches.hpp): the body of the vector
// loop of a packed pair walk. Only for sums analysis/vector_terms.cpp found
// a vector form for.
#pragma once

#include <string>
#include <vector>

#include "codegen/expression.hpp"
#include "codegen/names.hpp"
#include "ir/ir.hpp"

namespace partc::codegen {

struct SimdTermCode {
  std::vector<std::string> setup;  // statements before the loop (broadcasts)
  std::vector<std::string> lines;  // statements of the loop body, in order
  // Per sum: the vectors of its term's components (one for a real sum, one
  // per dimension for a vec), zero where its condition fails.
  std::vector<std::vector<std::string>> terms;
};

// The loop body for the sums `accs`, of one walk: `batch` names the PairBatch,
// `k` the first pair of the vector and `tag` the vector tag (partc::simd::Real,
// or partc::simd::Float when `arithmetic` is float) (lanes past the batch's
// end, its padding, are computed like the others); `names` names the
// kernel's params, consts, observables and arrays; the body's locals are
// drawn from `locals`.
SimdTermCode emit_simd_terms(const std::vector<const ir::Accumulate*>& accs, const ir::Model& model,
                             const ExpressionNames& names, NameTable& locals,
                             const std::string& batch, const std::string& k, const std::string& tag,
                             ir::Precision arithmetic);

}  // namespace partc::codegen
