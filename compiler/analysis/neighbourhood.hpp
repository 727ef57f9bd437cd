// Neighbourhood structure: how each accumulation finds its particles.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "ir/ir.hpp"

namespace partc {

struct SearchFact {
  enum class Kind {
    Dense,      // every particle of the set
    Neighbours  // only particles within `radius`: a spatial search
  };
  Kind kind = Kind::Dense;
  ir::Expr radius;  // Neighbours: the upper bound on |dx| the condition states
  // The search radius is the sum of these terms' largest values over the
  // particles each reads (a uniform term is its own largest value): r[i] +
  // r[j] gives max r + max r. One uniform term when the bound is uniform.
  std::vector<ir::Expr> radius_terms;
  std::string reason;
};

// Keyed by Accumulate::id.
using NeighbourhoodReport = std::map<int, SearchFact>;

NeighbourhoodReport find_neighbourhoods(const ir::Model& model, const std::string& source);

}  // namespace partc
