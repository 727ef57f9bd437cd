// Pair symmetry: which sums may use Newton's third law (each pair once).
#pragma once

#include <map>
#include <string>

#include "ir/ir.hpp"

namespace partc {

struct PairSymmetryFact {
  // True when term(i, j) = sign * term(j, i) and the condition is the same both ways,
  // so one evaluation per unordered pair serves both particles.
  bool newton = false;
  int sign = 1;        // +1: the term is even (j gets +term); -1: odd (j gets -term)
  std::string reason;  // why or why not, in the model's terms (for --explain)
};

using PairSymmetryReport = std::map<int, PairSymmetryFact>;  // keyed by Accumulate::id

PairSymmetryReport find_pair_symmetry(const ir::Model& model);

}  // namespace partc
