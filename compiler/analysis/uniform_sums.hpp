// Uniform sums: which accumulations are the same for every particle i.
#pragma once

#include <map>
#include <string>

#include "ir/ir.hpp"

namespace partc {

struct UniformSumFact {
  bool once = false;   // one value for all i: computed once per statement, not per particle
  std::string reason;  // why, in the model's terms (for --explain)
};

// Keyed by Accumulate::id.
using UniformSumReport = std::map<int, UniformSumFact>;

UniformSumReport find_uniform_sums(const ir::Model& model);

}  // namespace partc
