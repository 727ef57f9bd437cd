// Search plan: which neighbourhood sums share one search, and at what radius.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "analysis/neighbourhood.hpp"
#include "ir/ir.hpp"

namespace partc {

// One search structure of a set, a member of the generated class.
struct PlannedSearch {
  int set;                     // the set it searches
  ir::SearchChoice structure;  // as the schedule forces, or Auto
  // Whether its build may reorder the set. One thing per set owns the order:
  // its Verlet lists if it has any, else its first search; the rest keep it.
  bool reorders = false;
  std::string order_reason;  // why it reorders or keeps the order, for people
};

// The sums one search serves between two position changes of its set (a
// stretch): it is built once there, at the largest of their radii, and each
// sum keeps its own cutoff test.
struct SearchGroup {
  int search;                                   // index into SearchPlan::searches
  int stretch;                                  // of its set, counted through the model
  std::vector<int> sums;                        // Accumulate ids, in statement order
  std::vector<std::pair<int, int>> statements;  // (stage, statement) of each sum
  // The group that reorders the set in the same stretch, built first so
  // that it does not scramble this one (-1: none, or this group reorders).
  int built_after = -1;
  std::vector<std::string> radii;  // the distinct radii asked, as written
  std::string reason;              // shared or apart, and why
  // The groups of its stretch whose radii's ratios are known only at run time
  // (indices into SearchPlan::groups, this one among them, in plan order;
  // empty when the plan is fixed here). The generated code applies the cost
  // model there: with M the largest of their radii, a group whose radius r
  // gives (M / r)^dim <= share_candidate_growth walks the search of the group
  // at M, and every other group walks its own search, built at its own radius.
  std::vector<int> chosen_at_run_time;
};

struct SearchPlan {
  std::vector<PlannedSearch> searches;
  std::vector<SearchGroup> groups;
  std::map<int, int> group_of;  // Accumulate id -> index into groups
};

// The cost model's threshold: two sums at radii R > r whose ratio is known
// (2 * h against h) share one search at R while (R / r)^dim, the factor by
// which the smaller sum's candidates grow, stays at most this. A second
// build costs little beside the walks it saves: tests/bench/bench_two_cutoffs
// (30 neighbours within r, N = 1e4, each evaluation with its builds) measured
// shared/separate at R / r = 1, 1.25: 2D 4.4/4.9 ms, 7.0/5.1 ms; 3D 8.5/10.9
// ms, 18.7/12.5 ms, so the break-even growth lies near 1.1 (2D) and 1.3 (3D).
// Radii whose ratio is known only at run time (two params) meet the same test
// there (partc::search_to_walk, runtime/partc/search/search_sharing.hpp).
inline constexpr double share_candidate_growth = 1.2;

SearchPlan plan_searches(const ir::Model& model, const NeighbourhoodReport& neighbourhoods,
                         const std::string& source);

}  // namespace partc
