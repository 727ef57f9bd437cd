// partc/search/searches.cpp: the search structures for D = 1..4, compiled once
// (search_instances.hpp says what that covers), and NeighbourSearch's
// builds and packed pair walks (neighbour_search.hpp).
#include "partc/search/brute_force.hpp"
#include "partc/search/kd_tree.hpp"
#include "partc/search/neighbour_search.hpp"
#include "partc/search/ordered_cell_list.hpp"

namespace partc {

PARTC_SEARCH_INSTANCES(template, BruteForce);
PARTC_SEARCH_INSTANCES(template, KdTree);
PARTC_SEARCH_INSTANCES(template, OrderedCellList);
PARTC_NEIGHBOUR_SEARCH_INSTANCE(template, 1);
PARTC_NEIGHBOUR_SEARCH_INSTANCE(template, 2);
PARTC_NEIGHBOUR_SEARCH_INSTANCE(template, 3);
PARTC_NEIGHBOUR_SEARCH_INSTANCE(template, 4);

}  // namespace partc
