// Aliasing: which statements must compute into a buffer.
#pragma once

#include <string>
#include <vector>

#include "analysis/uniform_sums.hpp"
#include "ir/ir.hpp"

namespace partc {

struct AliasFact {
  bool buffered = false;  // compute every new value first, then store them all
  std::string reason;     // why, in the model's terms (for --explain)
};

// One fact per statement: facts[stage][statement].
using AliasReport = std::vector<std::vector<AliasFact>>;

// Reads inside sums computed once (uniform_sums) do not count: they see old values.
AliasReport detect_aliasing(const ir::Model& model, const UniformSumReport& uniform_sums);

}  // namespace partc
