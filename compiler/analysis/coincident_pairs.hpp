// Coincident pairs: whether a sum's term is singular where two particles
// share a position (|dx| = 0), and whether its condition keeps such pairs out.
#pragma once

#include <map>
#include <optional>
#include <string>

#include "ir/ir.hpp"
#include "support/diagnostics.hpp"

namespace partc {

struct CoincidenceFact {
  bool singular = false;  // the term divides by (or takes log of, ...) something 0 at |dx| = 0
  bool excluded = false;  // the condition excludes |dx| = 0 (so i's pair with itself)
  std::string reason;     // for --explain; empty when the term is not singular
  std::optional<Diagnostic> warning;  // singular and not excluded
};

// Keyed by Accumulate::id.
using CoincidenceReport = std::map<int, CoincidenceFact>;

CoincidenceReport find_coincident_pairs(const ir::Model& model, const std::string& source);

}  // namespace partc
