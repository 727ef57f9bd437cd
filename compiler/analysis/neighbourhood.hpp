// Neighbourhood structure: how each accumulation finds its particles.
#pragma once

#include <map>
#include <string>

#include "ir/ir.hpp"

namespace partc {

struct SearchFact {
  enum class Kind {
    Dense,      // every particle of the set
    Neighbours  // only particles within `radius`: a spatial search
  };
  Kind kind = Kind::Dense;
  ir::Expr radius;  // Neighbours: an upper bound on |dx|, uniform over particles
  std::string reason;
};

// Keyed by Accumulate::id.
using NeighbourhoodReport = std::map<int, SearchFact>;

NeighbourhoodReport find_neighbourhoods(const ir::Model& model, const std::string& source);

}  // namespace partc
