// Every neighbour-search structure against the O(N^2) reference of search_cases.hpp:
// for each query, the set of (j, dx) reported must be exactly the points within
// the radius under minimum-image periodicity, each j once (every image, for
// brute force beyond half a periodic box); box queries exactly the stored
// points in the box. Dimensions 1-4;
// periodic, non-periodic and mixed boxes; random and adversarial point sets.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <mutex>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <tuple>
#include <vector>

#include "search_cases.hpp"
#include "partc/particle_set.hpp"
#include "partc/search/brute_force.hpp"
#include "partc/search/linked_cell_list.hpp"
#include "partc/search/neighbour_search.hpp"
#include "partc/search/ordered_cell_list.hpp"
#include "partc/search/slab_schedule.hpp"

using partc::Domain;
using partc::Vec;
using namespace search_cases;  // Case, disagreements, check_no_errors, the generators

struct P_origin {  // the index a particle had before the facade reordered the set
  using type = std::int64_t;
  static constexpr const char* name = "origin";
};

namespace {

bool is_permutation_of_indices(const std::vector<std::size_t>& order, std::size_t n) {
  std::vector<std::size_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < sorted.size(); ++i)
    if (sorted[i] != i) return false;
  return sorted.size() == n;
}

// Queries by index, for_each_near(k, f), asked about each of the structure's own
// points (`points`, in its order): against the reference, and the same (j, dx),
// bit for bit and in the same order, as the query by position.
template <int D, class Search>
void check_member_queries(const std::string& name, const Case<D>& c,
                          const std::vector<Vec<D>>& points, const Search& search,
                          bool all_images = false) {
  const auto query = [&](std::size_t k, const auto& report) { search.for_each_near(k, report); };
  check_no_errors(name + " by index",
                  disagreements(c.domain, c.radius, points, points, query, all_images));
  using Found = std::vector<std::pair<std::size_t, Vec<D>>>;
  std::size_t differing = 0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    Found by_index, by_position;
    search.for_each_near(k, [&](std::size_t j, const Vec<D>& dx) { by_index.push_back({j, dx}); });
    search.for_each_near(points[k],
                         [&](std::size_t j, const Vec<D>& dx) { by_position.push_back({j, dx}); });
    const bool same = by_index.size() == by_position.size() &&
                      std::equal(by_index.begin(), by_index.end(), by_position.begin(),
                                 [](const auto& a, const auto& b) {
                                   return a.first == b.first &&
                                          std::memcmp(&a.second, &b.second, sizeof a.second) == 0;
                                 });
    differing += !same;
  }
  INFO(name << ": queries by index that differ from the query by position");
  CHECK(differing == 0);
}

// The pair walk, for_each_pair(f(i, pairs of i)), against the member queries (checked
// against the reference above): exactly the (i, j, dx) with j >= i they report,
// each once with the same dx bit for bit. With a slab schedule (the ordered
// cell list), every pair must obey its rule: what makes the parallel walk safe.
template <int D, class Search>
void check_pair_walk(const std::string& name, std::size_t n, const Search& search,
                     const partc::SlabSchedule* slabs = nullptr) {
  // (i, j, dx) with i <= j: a pair walk that sees a pair from j (a search
  // keeping the set's order walks in its own order) gives j, i and -dx.
  struct Entry {
    std::size_t i, j;
    std::array<double, D> dx;
    bool from_j;  // the walk saw it from j: dx computed the other way round
    bool operator<(const Entry& o) const { return std::tie(i, j, dx) < std::tie(o.i, o.j, o.dx); }
  };
  const auto entry = [](std::size_t i, std::size_t j, const Vec<D>& dx, double sign) {
    Entry e{std::min(i, j), std::max(i, j), {}, sign < 0};
    for (int k = 0; k < D; ++k) e.dx[k] = sign * dx[k] + 0.0;  // -0 as +0
    return e;
  };
  std::vector<Entry> walked, queried;
  std::size_t breaking_the_slab_rule = 0;
  std::mutex calls;  // the slabs' walks may run in parallel
  search.for_each_pair([&](std::size_t i, const auto& pairs) {
    pairs([&](std::size_t j, const Vec<D>& dx) {
      const std::lock_guard<std::mutex> lock(calls);
      if (slabs && !slabs->allows(slabs->slab_of(i), slabs->slab_of(j))) ++breaking_the_slab_rule;
      walked.push_back(entry(i, j, dx, i <= j ? 1.0 : -1.0));
    });
  });
  for (std::size_t i = 0; i < n; ++i)
    search.for_each_near(i, [&](std::size_t j, const Vec<D>& dx) {
      if (j >= i) queried.push_back(entry(i, j, dx, 1.0));
    });
  std::sort(walked.begin(), walked.end());
  std::sort(queried.begin(), queried.end());
  INFO(name << ": the pair walk against the member queries with j >= i");
  CHECK(breaking_the_slab_rule == 0);
  REQUIRE(walked.size() == queried.size());
  // The same pairs, and the same dx bit for bit when the walk sees the pair
  // from i; from j, dx is computed the other way round (p[i] - p[j] with the
  // image's shift), equal to rounding.
  std::size_t differ = 0;
  for (std::size_t k = 0; k < walked.size(); ++k) {
    bool same = walked[k].i == queried[k].i && walked[k].j == queried[k].j;
    for (int d = 0; d < D; ++d)
      same = same && (walked[k].from_j ? std::abs(walked[k].dx[d] - queried[k].dx[d]) <=
                                             1e-14 * (1 + std::abs(queried[k].dx[d]))
                                       : walked[k].dx[d] == queried[k].dx[d]);
    differ += !same;
  }
  CHECK(differ == 0);
}

// Checks every structure (and the facade on both of its paths) against the
// reference. Returns whether the ordered cell list walks its pairs in parallel
// slabs (so that callers can make sure some cases test that).
template <int D>
bool check_all_structures(const Case<D>& c) {
  bool parallel_slabs = false;
  INFO("case " << c.name << ", D = " << D << ", radius " << c.radius << ", N = "
               << c.points.size());
  // Brute force (and so the facade) reports every image when the radius passes
  // half a periodic length; the others the nearest one.
  const bool all_images = partc::BruteForce<D>::needs_all_images(c.domain, c.radius);
  {
    partc::BruteForce<D> s;
    s.build(c.domain, c.radius, c.points);
    CHECK(s.all_images() == all_images);
    check_no_errors("BruteForce", disagreements(c, c.points, s, all_images));
    check_no_errors("BruteForce boxes", box_disagreements(c, c.points, s));
    check_pair_walk<D>("BruteForce", c.points.size(), s);
  }
  {
    partc::LinkedCellList<D> s;
    s.build(c.domain, c.radius, c.points);
    check_no_errors("LinkedCellList", disagreements(c, c.points, s));
    check_no_errors("LinkedCellList boxes", box_disagreements(c, c.points, s));
  }
  {
    partc::OrderedCellList<D> s;
    s.build(c.domain, c.radius, c.points);
    const std::vector<std::size_t>& order = s.order();
    REQUIRE(is_permutation_of_indices(order, c.points.size()));
    const std::vector<Vec<D>> sorted = in_order(c.points, order);
    // Stable: copies of one point share a cell and keep their relative order.
    for (std::size_t a = 0; a < order.size(); ++a)
      for (std::size_t b = a + 1; b < order.size(); ++b)
        if (sorted[a] == sorted[b]) REQUIRE(order[a] < order[b]);
    check_no_errors("OrderedCellList", disagreements(c, sorted, s));
    check_member_queries("OrderedCellList", c, sorted, s);
    check_pair_walk<D>("OrderedCellList", sorted.size(), s, &s.pair_slabs());
    parallel_slabs = s.pair_slabs().count() > 1;
    check_no_errors("OrderedCellList boxes", box_disagreements(c, sorted, s));
  }
  using Search = partc::NeighbourSearch<D>;
  const std::vector<std::pair<std::string, Search>> searches = {
      {"NeighbourSearch(margin 0)", Search(0.0)},
      {"NeighbourSearch(default margin)", Search()},
      {"NeighbourSearch(forced brute force)", Search(Search::Kind::brute_force)},
      {"NeighbourSearch(forced cell list)", Search(Search::Kind::cell_list)},
      {"NeighbourSearch(forced k-d tree)", Search(Search::Kind::kd_tree)},
      // Keeping the set's order: the same answers, by the set's indices.
      {"NeighbourSearch(margin 0, order kept)", Search(0.0, Search::Order::keep)},
      {"NeighbourSearch(forced k-d tree, order kept)",
       Search(Search::Kind::kd_tree, Search::Order::keep)}};
  for (auto [name, s] : searches) {
    partc::ParticleSet<D, P_origin> set;
    for (const auto& p : c.points) {
      const std::size_t i = set.push_back(p);
      set.template get<P_origin>()[i] = set.ids()[i];
    }
    s.build(c.domain, c.radius, set);
    REQUIRE(set.size() == c.points.size());
    for (std::size_t k = 0; k < set.size(); ++k) {  // the set was permuted as a whole
      REQUIRE(set.template get<P_origin>()[k] == set.ids()[k]);
      if (s.keeps_order()) REQUIRE(set.ids()[k] == static_cast<std::int64_t>(k));
      const Vec<D>& original = c.points[static_cast<std::size_t>(set.ids()[k])];
      REQUIRE(std::memcmp(&set.positions()[k], &original, sizeof original) == 0);  // NaN too
    }
    check_no_errors(name, disagreements(c, set.positions(), s, all_images));
    check_member_queries(name, c, set.positions(), s, all_images);
    check_pair_walk<D>(name, set.size(), s);
    check_no_errors(name + " boxes", box_disagreements(c, set.positions(), s));
  }
  return parallel_slabs;
}

}  // namespace

TEMPLATE_TEST_CASE("random sets match the reference", "[search]", PARTC_ALL_DIMS) {
  constexpr int D = TestType::value;
  std::size_t parallel_slabs = 0;
  for_each_random_case<D>(1000 * D, [&](const Case<D>& c) { parallel_slabs += check_all_structures(c); });
  // In 4D the cell count, capped near N <= 150, leaves fewer than 4 planes.
  if (D < 4) CHECK(parallel_slabs > 0);
}

// A cell list keeps what depends on its grid alone from one build to the
// next (the runs of whole cells): rebuilt on case after case, and on the same
// grid with other points, it must answer exactly as one built afresh (which
// the tests above check against the reference).
TEMPLATE_TEST_CASE("a cell list rebuilt case after case answers as one built afresh", "[search]",
                   PARTC_ALL_DIMS) {
  constexpr int D = TestType::value;
  using Found = std::vector<std::pair<std::size_t, Vec<D>>>;
  const auto near_of_each = [](const partc::OrderedCellList<D>& s, std::size_t n) {
    std::vector<Found> found(n);
    for (std::size_t k = 0; k < n; ++k)
      s.for_each_near(k, [&](std::size_t j, const Vec<D>& dx) { found[k].push_back({j, dx}); });
    return found;
  };
  partc::OrderedCellList<D> reused;
  std::size_t differing = 0, compared = 0;
  for_each_random_case<D>(500 * D, [&](const Case<D>& c) {
    std::vector<Vec<D>> points = c.points;
    for (int round = 0; round < 2; ++round) {  // the second: the same grid, the points reversed
      reused.build(c.domain, c.radius, points);
      partc::OrderedCellList<D> fresh;
      fresh.build(c.domain, c.radius, points);
      const bool same =
          reused.order() == fresh.order() && reused.mean_examined() == fresh.mean_examined() &&
          reused.pair_slabs().count() == fresh.pair_slabs().count() &&
          near_of_each(reused, points.size()) == near_of_each(fresh, points.size());
      differing += !same;
      ++compared;
      std::reverse(points.begin(), points.end());
    }
  });
  INFO(compared << " builds compared");
  CHECK(differing == 0);
}

TEMPLATE_TEST_CASE("points on cell edges and on lo/hi match the reference", "[search]",
                   PARTC_ALL_DIMS) {
  constexpr int D = TestType::value;
  for (Periodicity periodicity : all_periodicities) {
    // Box [-1, 1]: 5 points per dimension, -1 and 1 included.
    for (double radius : {0.5, 0.25, 1.0 /* = L/2 */, 2.0 / 3.0, 0.5 + 1e-15, 0.5 - 1e-15, 3.0})
      // Radius 3 passes 4^D images of each point: in 4D, 3 points a side keep it quick.
      check_all_structures(lattice_case<D>(periodicity, 0.5, D == 4 && radius > 2 ? 3 : 5, radius));
    // Spacing not a power of two: lattice coordinates and cell edges round.
    check_all_structures(lattice_case<D>(periodicity, 0.2, D <= 2 ? 11 : 5, 0.2));
    check_all_structures(lattice_case<D>(periodicity, 0.1, D <= 2 ? 21 : 4, 0.3));
  }
}

TEMPLATE_TEST_CASE("clustered and duplicate points match the reference", "[search]",
                   PARTC_ALL_DIMS) {
  constexpr int D = TestType::value;
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> tiny(0.0, 1e-3);
  for (Periodicity periodicity : all_periodicities) {
    std::vector<Vec<D>> one_cell;
    for (int i = 0; i < 60; ++i) {
      Vec<D> p;
      for (int k = 0; k < D; ++k) p[k] = 0.1 + tiny(rng);
      one_cell.push_back(p);
    }
    check_all_structures(make_case<D>("all in one cell", periodicity, true, 0.3, one_cell));

    std::vector<Vec<D>> duplicates;
    for (int i = 0; i < 20; ++i) {
      duplicates.push_back(Vec<D>::filled(0.25));
      duplicates.push_back(Vec<D>::filled(-1.0));  // lo corner
      duplicates.push_back(Vec<D>::filled(1.0));   // hi corner: the lo corner when periodic
    }
    for (double radius : {0.2, 1e-9, 1.5})
      check_all_structures(make_case<D>("duplicates", periodicity, true, radius, duplicates));
  }
}

TEST_CASE("NaN points are never reported and do not disturb the others", "[search]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (Periodicity periodicity : {Periodicity::none, Periodicity::all}) {
    std::vector<Vec<2>> points = {Vec<2>{{0.0, 0.0}}, Vec<2>{{nan, 0.0}}, Vec<2>{{0.1, 0.0}},
                                  Vec<2>{{0.0, nan}}, Vec<2>{{-0.1, 0.05}}};
    for (int i = 0; i < 40; ++i) points.push_back(Vec<2>{{0.02 * i - 0.9, 0.5}});
    Case<2> c = make_case<2>("with NaN", periodicity, true, 0.15, points);
    c.queries.push_back(Vec<2>{{nan, nan}});
    check_all_structures(c);
  }
}

TEST_CASE("a bad radius or periodic length is rejected", "[search]") {
  const Domain<2> box = make_domain<2>(Periodicity::mixed, true);
  const std::vector<Vec<2>> points = {Vec<2>{{0.0, 0.0}}};
  Domain<2> flat = box;
  flat.hi[0] = flat.lo[0];
  for (double radius : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN()}) {
    INFO("radius " << radius);
    CHECK_THROWS_AS(partc::BruteForce<2>().build(box, radius, points), std::invalid_argument);
    CHECK_THROWS_AS(partc::LinkedCellList<2>().build(box, radius, points), std::invalid_argument);
    CHECK_THROWS_AS(partc::OrderedCellList<2>().build(box, radius, points), std::invalid_argument);
  }
  // The facade takes 0 and less (coincident particles only, tested below), not NaN.
  partc::ParticleSet<2> set;
  set.push_back(points[0]);
  CHECK_THROWS_WITH(
      partc::NeighbourSearch<2>().build(box, std::numeric_limits<double>::quiet_NaN(), set),
      Catch::Contains("radius must be positive"));
  CHECK_THROWS_AS(partc::BruteForce<2>().build(flat, 0.1, points), std::invalid_argument);
  CHECK_THROWS_AS(partc::OrderedCellList<2>().build(flat, 0.1, points), std::invalid_argument);
}

TEST_CASE("cell sizes follow L / floor(L / radius) and the count is capped", "[search]") {
  const Domain<3> box = make_domain<3>(Periodicity::all, true);  // L = 2
  std::vector<Vec<3>> points(500, Vec<3>::filled(0.0));
  partc::OrderedCellList<3> ordered;
  partc::LinkedCellList<3> linked;
  ordered.build(box, 0.5, points);
  CHECK(ordered.cell_count() == 4 * 4 * 4);
  ordered.build(box, 0.49, points);
  CHECK(ordered.cell_count() == 4 * 4 * 4);
  ordered.build(box, 0.4, points);
  CHECK(ordered.cell_count() == 5 * 5 * 5);
  // A tiny radius: at most about 2 * points + 64 cells, not (2 / 1e-6)^3.
  points.resize(10);
  ordered.build(box, 1e-6, points);
  linked.build(box, 1e-6, points);
  CHECK(ordered.cell_count() <= 84);
  CHECK(ordered.cell_count() >= 27);
  CHECK(linked.cell_count() == ordered.cell_count());
  // Non-periodic dimensions without a usable length get one cell.
  Domain<3> open = make_domain<3>(Periodicity::none, true);
  open.hi[1] = open.lo[1];
  open.lo[2] = -std::numeric_limits<double>::infinity();
  ordered.build(open, 0.5, points);
  CHECK(ordered.cell_count() == 4);
}

TEST_CASE("the ordered cell list sorts stably by cell on 1 and 2 threads", "[search]") {
  // Enough points for the counting sort to run in blocks, and a NaN point;
  // the reference: std::stable_sort of the indices by each point's cell.
  const Domain<2> box = make_domain<2>(Periodicity::all, true);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-3.0, 3.0);  // beyond the box too: wrapped
  std::vector<Vec<2>> points(40000);
  for (auto& p : points) p = Vec<2>{{u(rng), u(rng)}};
  points[123] = Vec<2>{{std::nan(""), 0.5}};
  const double radius = 0.02;
  const partc::CellGrid<2> grid(box, radius, points.size());
  std::vector<std::size_t> expected(points.size());
  for (std::size_t i = 0; i < expected.size(); ++i) expected[i] = i;
  std::stable_sort(expected.begin(), expected.end(), [&](std::size_t a, std::size_t b) {
    return grid.cell_of(box.wrap(points[a])) < grid.cell_of(box.wrap(points[b]));
  });
  for (int threads : {1, 2}) {
    INFO("threads " << threads);
    partc::OrderedCellList<2> cells;
    partc::with_threads(threads, [&] { cells.build(box, radius, points); });
    REQUIRE(cells.cell_count() < points.size());
    CHECK(cells.order() == expected);
  }
}

TEST_CASE("the facade picks brute force when queries would examine nearly every point",
          "[search]") {
  const Domain<2> box = make_domain<2>(Periodicity::all, true);  // L = 2
  partc::ParticleSet<2> set;
  for (int i = 0; i < 100; ++i) set.push_back(Vec<2>{{0.01 * i, -0.013 * i}});
  partc::NeighbourSearch<2> search;
  search.build(box, 0.2, set);  // 10 x 10 cells: a query examines 9% of the points
  CHECK(search.kind() == partc::NeighbourSearch<2>::Kind::cell_list);
  CHECK(search.cell_count() == 10 * 10);
  CHECK(search.describe() == "cell list, 100 cells, pair walks in 10 slabs");
  CHECK(search.pairs_once());  // the cell list walks its pairs in parallel
  search.build(box, 0.66, set);  // 3 x 3 cells: a query examines 99%
  CHECK(search.kind() == partc::NeighbourSearch<2>::Kind::brute_force);
  CHECK(search.cell_count() == 0);
  CHECK(search.pairs_once());  // 100 points: few enough for one thread
  search.build(box, 0.7, set);  // 2 cells per periodic dimension: shifts do not suffice
  CHECK(search.kind() == partc::NeighbourSearch<2>::Kind::brute_force);

  partc::NeighbourSearch<2> eager(0.0);  // a cell list whenever one can be used
  eager.build(box, 0.66, set);
  CHECK(eager.kind() == partc::NeighbourSearch<2>::Kind::cell_list);
  eager.build(box, 0.7, set);
  CHECK(eager.kind() == partc::NeighbourSearch<2>::Kind::brute_force);
  const Domain<2> open = make_domain<2>(Periodicity::none, true);
  eager.build(open, 0.7, set);  // few cells are fine without periodicity
  CHECK(eager.kind() == partc::NeighbourSearch<2>::Kind::cell_list);

  partc::NeighbourSearch<2> cells(partc::NeighbourSearch<2>::Kind::cell_list);
  cells.build(box, 0.7, set);  // forced: the cell list's exact mode serves 2 cells a side
  CHECK(cells.kind() == partc::NeighbourSearch<2>::Kind::cell_list);
  partc::NeighbourSearch<2> brute(partc::NeighbourSearch<2>::Kind::brute_force);
  brute.build(box, 0.01, set);
  CHECK(brute.kind() == partc::NeighbourSearch<2>::Kind::brute_force);

  partc::NeighbourSearch<2> tree(partc::NeighbourSearch<2>::Kind::kd_tree);
  tree.build(box, 0.7, set);
  CHECK(tree.kind() == partc::NeighbourSearch<2>::Kind::kd_tree);

  partc::NeighbourSearch<2> reluctant(101.0);  // more than there are points to save
  reluctant.build(box, 0.1, set);
  CHECK(reluctant.kind() == partc::NeighbourSearch<2>::Kind::brute_force);

  // Brute force over a large set: per-particle queries, which run in parallel.
  partc::ParticleSet<2> many;
  for (int i = 0; i < 1000; ++i) many.push_back(Vec<2>{{0.002 * i, -0.0013 * i}});
  brute.build(box, 0.1, many);
  CHECK_FALSE(brute.pairs_once());
}

TEST_CASE("the facade picks a k-d tree for tightly clustered points", "[search]") {
  const Domain<2> box = make_domain<2>(Periodicity::all, true);  // L = 2
  std::mt19937_64 random(4);
  std::normal_distribution<double> blob(0.0, 0.002);
  std::uniform_real_distribution<double> anywhere(-1.0, 1.0);
  partc::ParticleSet<2> clustered, uniform;
  for (int i = 0; i < 20000; ++i) {
    const double cx = (i % 4) * 0.5 - 0.75;  // four blobs
    clustered.push_back(Vec<2>{{cx + blob(random), 0.3 + blob(random)}});
    uniform.push_back(Vec<2>{{anywhere(random), anywhere(random)}});
  }
  // About 20 neighbours per query in the blobs; cells sized for that radius
  // hold thousands of points each.
  partc::NeighbourSearch<2> search;
  search.build(box, 0.0002, clustered);
  CHECK(search.kind() == partc::NeighbourSearch<2>::Kind::kd_tree);
  search.build(box, 0.02, uniform);
  CHECK(search.kind() == partc::NeighbourSearch<2>::Kind::cell_list);
}

TEST_CASE("facade: a radius of 0 or less finds coincident particles only", "[search][facade]") {
  const Domain<2> box{Vec<2>{{0.0, 0.0}}, Vec<2>{{1.0, 1.0}}, {{true, true}}};
  std::mt19937_64 random(4);
  std::uniform_real_distribution<double> anywhere(0.0, 1.0);
  partc::ParticleSet<2> set;
  for (int i = 0; i < 3000; ++i) {
    const Vec<2> x{{anywhere(random), anywhere(random)}};
    set.push_back(x);
    if (i % 10 == 0) set.push_back(x);  // a twin at the same place
  }
  for (const double radius : {0.0, -0.5}) {
    partc::NeighbourSearch<2> search;
    search.build(box, radius, set);
    std::size_t found = 0, coincident = 0;
    for (std::size_t i = 0; i < set.size(); ++i)
      search.for_each_near(i, [&](std::size_t j, const Vec<2>& dx) {
        ++found;
        coincident += dx[0] == 0 && dx[1] == 0;
        CHECK(set.positions()[j] == set.positions()[i]);
      });
    CHECK(found == set.size() + 2 * 300);  // each particle itself, and each twin both ways
    CHECK(coincident == found);
  }
  partc::NeighbourSearch<2> search;
  CHECK_THROWS_AS(search.build(box, std::nan(""), set), std::invalid_argument);
}
