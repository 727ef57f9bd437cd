// Aliasing: which statements must compute into a buffer.
#pragma once

#include <string>
#include <vector>

#include "ir/ir.hpp"

namespace partc {

struct AliasFact {
  bool buffered = false;  // compute every new value first, then store them all
  std::string reason;     // why, in the model's terms (for --explain)
};

// One fact per statement: facts[stage][statement].
using AliasReport = std::vector<std::vector<AliasFact>>;

AliasReport detect_aliasing(const ir::Model& model);

}  // namespace partc
