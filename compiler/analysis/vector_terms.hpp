// Vector terms: which pair sums the generated code evaluates on vectors of
// pairs (runtime/partc/simd/pair_batches.hpp) rather than pair by pair.
#pragma once

#include <map>
#include <string>

#include "analysis/coincident_pairs.hpp"
#include "analysis/neighbourhood.hpp"
#include "analysis/symmetry.hpp"
#include "ir/ir.hpp"

namespace partc {

struct VectorTermFact {
  // True when the sum's condition and term have a vector form: every
  // operation one that codegen/simd_term.cpp emits with Highway.
  bool vector = false;
  std::string reason;  // why or why not, in the model's terms (for --explain)
  // Whether the walk must give i's pair with itself (dx = 0): not when the
  // condition excludes |dx| = 0, where that term would be masked to 0.
  bool self_pair = true;
  // The lanes the term is computed on (the statement's schedule: arithmetic);
  // either way its values are added into double sums.
  ir::Precision arithmetic = ir::Precision::Double;
  // Whether the sum's per-particle queries can be packed the same way
  // (NeighbourSearch::for_each_near_batch): its statement's own set, a
  // search (not Verlet lists), not compensated. A Newton sum takes them
  // where its search walks pairs serially; any other sum has a fact only then.
  bool packed_queries = false;
};

using VectorTermReport = std::map<int, VectorTermFact>;  // keyed by Accumulate::id

// For each sum over neighbours taken each pair once (symmetry's newton), and
// each taken both ways whose per-particle queries can be packed (see
// vector_terms.cpp); `enabled` false (--no-simd) keeps every one scalar.
VectorTermReport find_vector_terms(const ir::Model& model,
                                   const NeighbourhoodReport& neighbourhoods,
                                   const PairSymmetryReport& symmetry,
                                   const CoincidenceReport& coincident, bool enabled);

}  // namespace partc
