// partc/searches.cpp: the search structures for D = 1..4, compiled once
// (search_instances.hpp says what that covers).
#include "partc/brute_force.hpp"
#include "partc/kd_tree.hpp"
#include "partc/ordered_cell_list.hpp"

namespace partc {

PARTC_SEARCH_INSTANCES(template, BruteForce);
PARTC_SEARCH_INSTANCES(template, KdTree);
PARTC_SEARCH_INSTANCES(template, OrderedCellList);

}  // namespace partc
