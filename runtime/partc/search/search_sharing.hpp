// partc/search/search_sharing.hpp: which search a group of neighbourhood sums walks
// when the ratio of its radius to the other groups' is known only at run
// time (two params, rc and rf). The compiler decides this itself when the
// ratio is known (compiler/analysis/search_plan.cpp); this is the same rule,
// applied to the radii the run has:
//
//   const std::size_t walked = partc::search_to_walk({rc, rf}, 1, 2, 1.2);
//   // 0: group 1 walks group 0's search (built at the larger radius, rc);
//   // 1: group 1 walks a search of its own, built at rf.
//
// With M the largest radius, a group at radius r walks the search at M
// while its candidates there grow at most `growth` times, (M / r)^dim <=
// growth; otherwise a second build costs less than the longer walks, and it
// walks its own. The group at M always walks its own (the first of equal
// largest radii, so that ties share one search).
//
// Surprises:
// - Each group that does not share has a search of its own, even when two
//   such groups' radii are close to each other: the choice is one test per
//   group against M, so each sum's search is fixed by the radii alone.
// - A NaN radius walks its own search, whose build refuses it, as a search
//   built at the largest radius would have.
#pragma once

#include <cmath>
#include <cstddef>

namespace partc {

template <std::size_t N>
std::size_t search_to_walk(const double (&radii)[N], std::size_t group, int dim, double growth) {
  static_assert(N >= 2, "a choice needs two radii at least");
  if (std::isnan(radii[group])) return group;
  std::size_t largest = 0;
  for (std::size_t k = 1; k < N; ++k)
    if (radii[k] > radii[largest]) largest = k;
  return std::pow(radii[largest] / radii[group], dim) <= growth ? largest : group;
}

}  // namespace partc
