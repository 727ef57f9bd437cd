// partc/search/search_instances.hpp: the search structures' code that does not
// depend on a model, compiled once in the runtime library (searches.cpp)
// for every dimension a model can have (1 to 4, x y z w).
//
//   PARTC_SEARCH_INSTANCES(extern template, BruteForce);  // at the end of its header
//   PARTC_SEARCH_INSTANCES(template, BruteForce);         // in searches.cpp
//
// For Search<D>, D = 1..4: the class (its members that are not templates:
// a k-d tree's split, a cell list's runs of cells, describing itself) and
// build on double and on float points (a schedule's precision = float).
// Their walks (for_each_near, for_each_pair, ...) take the model's kernel as
// a template argument: those are compiled with each model.
// Surprise: "extern template" keeps GCC from compiling these members in the
// model again, in-class (inline) definitions included, but it may still
// inline the small ones, as it would without it; results are the same
// either way (the library is compiled with the models' flags, and
// -ffp-contract=off rounds each operation as written).
#pragma once

#include <vector>

#include "partc/domain.hpp"
#include "partc/vec.hpp"

#define PARTC_SEARCH_INSTANCE(prefix, Search, D)                                              \
  prefix class Search<D>;                                                                     \
  prefix void Search<D>::build(const Domain<D>&, double, const std::vector<Vec<D, double>>&); \
  prefix void Search<D>::build(const Domain<D>&, double, const std::vector<Vec<D, float>>&)

#define PARTC_SEARCH_INSTANCES(prefix, Search) \
  PARTC_SEARCH_INSTANCE(prefix, Search, 1);    \
  PARTC_SEARCH_INSTANCE(prefix, Search, 2);    \
  PARTC_SEARCH_INSTANCE(prefix, Search, 3);    \
  PARTC_SEARCH_INSTANCE(prefix, Search, 4)
