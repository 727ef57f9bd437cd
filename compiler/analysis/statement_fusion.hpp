// Statement fusion: which consecutive statements of the step share one pass
// over their set, and so one walk of its pairs.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "analysis/neighbourhood.hpp"
#include "analysis/observed_steps.hpp"
#include "analysis/search_plan.hpp"
#include "analysis/symmetry.hpp"
#include "ir/ir.hpp"
#include "support/source.hpp"

namespace partc {

using StatementPosition = std::pair<int, int>;  // (stage, statement)

// Statements computed in one pass, in their order: every particle's sums
// of all of them from one walk, then each statement's update in turn. When
// some members run only on observed steps (a pair energy), the others run
// as a pass of their own on the steps not observed.
struct FusedPass {
  std::vector<StatementPosition> statements;
  std::string reason;  // its members and what they share, for people
};

// Two consecutive statements that would have shared a walk, and why not.
struct FusionRefusal {
  StatementPosition first, second;
  std::string reason;
};

struct StatementFusion {
  std::vector<FusedPass> passes;
  std::vector<FusionRefusal> refused;
  std::map<StatementPosition, int> pass_of;  // a member -> index into passes
};

// enabled = false (partc --no-fuse): no pass, each candidate refused as such.
StatementFusion fuse_statements(const ir::Model& model, const NeighbourhoodReport& neighbourhoods,
                                const PairSymmetryReport& symmetry, const SearchPlan& searches,
                                const ObservedStepReport& observed, const SourceFile& file,
                                bool enabled = true);

}  // namespace partc
