// Every neighbour-search structure against an O(N^2) reference written here:
// for each query, the set of (j, dx) reported must be exactly the points within
// the radius under minimum-image periodicity, each j once. Dimensions 1-4;
// periodic, non-periodic and mixed boxes; random and adversarial point sets.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "partc/brute_force.hpp"
#include "partc/linked_cell_list.hpp"
#include "partc/neighbour_search.hpp"
#include "partc/ordered_cell_list.hpp"
#include "partc/particle_set.hpp"

using partc::Domain;
using partc::Vec;

struct P_origin {  // the index a particle had before the facade reordered the set
  using type = std::int64_t;
  static constexpr const char* name = "origin";
};

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

template <int D>
struct Case {
  std::string name;
  Domain<D> domain;
  double radius;
  std::vector<Vec<D>> points;
  std::vector<Vec<D>> queries;
};

template <int D>
std::string show(const Vec<D>& v) {
  std::ostringstream s;
  s.precision(17);
  s << "(";
  for (int k = 0; k < D; ++k) s << (k ? ", " : "") << v[k];
  return s.str() + ")";
}

// Independent reference: subtract the nearest whole number of boxes.
template <int D>
Vec<D> reference_image(const Domain<D>& domain, Vec<D> d) {
  for (int k = 0; k < D; ++k) {
    const double L = domain.hi[k] - domain.lo[k];
    if (domain.periodic[k]) d[k] -= L * std::nearbyint(d[k] / L);
  }
  return d;
}

// Largest finite magnitude of a component (at least 1): rounding errors of positions scale with it.
template <int D>
double magnitude(const Vec<D>& v) {
  double m = 1.0;
  for (int k = 0; k < D; ++k)
    if (std::isfinite(v[k])) m = std::max(m, std::abs(v[k]));
  return m;
}

// Runs every query of c through `search` (indices refer to pts) and returns a
// description of each disagreement with the reference.
template <int D, class Search>
std::vector<std::string> disagreements(const Case<D>& c, const std::vector<Vec<D>>& pts,
                                       const Search& search) {
  const double r = c.radius;
  double case_magnitude = std::max(magnitude(c.domain.lo), magnitude(c.domain.hi));
  for (const auto& p : pts) case_magnitude = std::max(case_magnitude, magnitude(p));
  std::vector<std::string> errors;
  std::vector<int> hits(pts.size());
  std::vector<Vec<D>> found(pts.size());
  for (std::size_t iq = 0; iq < c.queries.size(); ++iq) {
    const Vec<D>& q = c.queries[iq];
    // Per component: rounding of positions, shifts and wrapping.
    const double tol = 64 * eps * std::max(case_magnitude, magnitude(q));
    const double too_far = r * (1 + 1e-12) + D * tol;
    // The contract's inflated radius, less what rounding may move a distance: points a
    // hair beyond r (lattice neighbours at r(1 + 1e-16)) must still be found.
    const double must_find_squared = std::max(r * r, r * r * (1 + 1e-12) - 2 * r * D * tol);
    const auto where = [&](std::size_t j) {
      return "query " + std::to_string(iq) + " " + show(q) + ", j " + std::to_string(j) + " " +
             (j < pts.size() ? show(pts[j]) : std::string("?")) + ": ";
    };
    std::fill(hits.begin(), hits.end(), 0);
    search.for_each_near(q, [&](std::size_t j, const Vec<D>& dx) {
      if (j >= pts.size()) {
        errors.push_back(where(j) + "index out of range");
        return;
      }
      ++hits[j];
      found[j] = dx;
    });
    for (std::size_t j = 0; j < pts.size(); ++j) {
      const Vec<D> ref = reference_image(c.domain, pts[j] - q);
      if (hits[j] == 0) {
        if (squared_norm(ref) <= must_find_squared)
          errors.push_back(where(j) + "missed, dx " + show(ref));
        continue;
      }
      if (hits[j] > 1) errors.push_back(where(j) + "reported " + std::to_string(hits[j]) + " times");
      if (!(norm(ref) <= too_far)) errors.push_back(where(j) + "too far, dx " + show(ref));
      for (int k = 0; k < D; ++k) {
        const double got = found[j][k];
        if (std::abs(got - ref[k]) <= tol) continue;
        // A point exactly half a box away has two shortest images; either will do.
        const double half = 0.5 * (c.domain.hi[k] - c.domain.lo[k]);
        const bool tie = c.domain.periodic[k] && std::abs(std::abs(ref[k]) - half) <= tol &&
                         std::abs(got + ref[k]) <= tol;
        if (!tie) {
          errors.push_back(where(j) + "dx " + show(found[j]) + ", expected " + show(ref));
          break;
        }
      }
    }
  }
  return errors;
}

template <class Errors>
void check_no_errors(const std::string& what, const Errors& errors) {
  std::string first;
  for (std::size_t i = 0; i < std::min<std::size_t>(errors.size(), 5); ++i)
    first += "\n  " + errors[i];
  INFO(what << ": " << errors.size() << " disagreements" << first);
  CHECK(errors.empty());
}

bool is_permutation_of_indices(const std::vector<std::size_t>& order, std::size_t n) {
  std::vector<std::size_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < sorted.size(); ++i)
    if (sorted[i] != i) return false;
  return sorted.size() == n;
}

// Checks every structure (and the facade on both of its paths) against the reference.
template <int D>
void check_all_structures(const Case<D>& c) {
  INFO("case " << c.name << ", D = " << D << ", radius " << c.radius << ", N = "
               << c.points.size());
  {
    partc::BruteForce<D> s;
    s.build(c.domain, c.radius, c.points);
    check_no_errors("BruteForce", disagreements(c, c.points, s));
  }
  {
    partc::LinkedCellList<D> s;
    s.build(c.domain, c.radius, c.points);
    check_no_errors("LinkedCellList", disagreements(c, c.points, s));
  }
  {
    partc::OrderedCellList<D> s;
    s.build(c.domain, c.radius, c.points);
    const std::vector<std::size_t>& order = s.order();
    REQUIRE(is_permutation_of_indices(order, c.points.size()));
    std::vector<Vec<D>> sorted;
    for (std::size_t i : order) sorted.push_back(c.points[i]);
    // Stable: copies of one point share a cell and keep their relative order.
    for (std::size_t a = 0; a < order.size(); ++a)
      for (std::size_t b = a + 1; b < order.size(); ++b)
        if (sorted[a] == sorted[b]) REQUIRE(order[a] < order[b]);
    check_no_errors("OrderedCellList", disagreements(c, sorted, s));
  }
  using Search = partc::NeighbourSearch<D>;
  const std::vector<std::pair<std::string, Search>> searches = {
      {"NeighbourSearch(margin 0)", Search(0.0)},
      {"NeighbourSearch(default margin)", Search()},
      {"NeighbourSearch(forced brute force)", Search(Search::Kind::brute_force)},
      {"NeighbourSearch(forced cell list)", Search(Search::Kind::cell_list)},
      {"NeighbourSearch(forced k-d tree)", Search(Search::Kind::kd_tree)}};
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
      const Vec<D>& original = c.points[static_cast<std::size_t>(set.ids()[k])];
      REQUIRE(std::memcmp(&set.positions()[k], &original, sizeof original) == 0);  // NaN too
    }
    check_no_errors(name, disagreements(c, set.positions(), s));
  }
}

// ---------------------------------------------------------------------------
// Case generators

enum class Periodicity { none, all, mixed };

template <int D>
Domain<D> make_domain(Periodicity periodicity, bool uniform) {
  Domain<D> d{};
  for (int k = 0; k < D; ++k) {
    d.lo[k] = uniform ? -1.0 : -1.0 - 0.25 * k;
    d.hi[k] = uniform ? 1.0 : d.lo[k] + 2.0 + 0.75 * k;
    d.periodic[k] = periodicity == Periodicity::all || (periodicity == Periodicity::mixed && k % 2 == 0);
  }
  return d;
}

const char* periodicity_name(Periodicity p) {
  return p == Periodicity::none ? "non-periodic" : p == Periodicity::all ? "periodic" : "mixed";
}

// Queries: every point, random points in and around the box, far-away points.
template <int D>
void add_queries(Case<D>& c, std::mt19937_64& rng) {
  c.queries = c.points;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 25; ++i) {
    Vec<D> q;
    for (int k = 0; k < D; ++k) {
      const double L = c.domain.hi[k] - c.domain.lo[k];
      q[k] = c.domain.lo[k] - L + 3 * L * unit(rng);
    }
    c.queries.push_back(q);
  }
  Vec<D> far_low = c.domain.lo, far_high = c.domain.hi;
  for (int k = 0; k < D; ++k) {
    const double L = c.domain.hi[k] - c.domain.lo[k];
    far_low[k] -= 1000.3 * L;
    far_high[k] += 12345.0625 * L;
  }
  c.queries.push_back(far_low);
  c.queries.push_back(far_high);
  c.queries.push_back(c.domain.lo);
  c.queries.push_back(c.domain.hi);
}

// Mostly uniform points in the box; some outside it; some with coordinates on the
// boundaries or on the (nominal) cell edges lo + m * radius.
template <int D>
Case<D> random_case(Periodicity periodicity, std::size_t n, double radius_fraction,
                    std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Case<D> c;
  c.domain = make_domain<D>(periodicity, false);
  double shortest = std::numeric_limits<double>::infinity();
  for (int k = 0; k < D; ++k) shortest = std::min(shortest, c.domain.hi[k] - c.domain.lo[k]);
  c.radius = radius_fraction * shortest;
  c.name = std::string("random ") + periodicity_name(periodicity);
  for (std::size_t i = 0; i < n; ++i) {
    Vec<D> p;
    const double kind = unit(rng);
    for (int k = 0; k < D; ++k) {
      const double lo = c.domain.lo[k], hi = c.domain.hi[k], L = hi - lo;
      if (kind < 0.75) {
        p[k] = lo + L * unit(rng);
      } else if (kind < 0.85) {
        p[k] = lo - 0.5 * L + 2 * L * unit(rng);  // possibly outside
      } else {
        const double special[] = {lo, hi, std::nextafter(hi, lo), std::nextafter(lo, hi),
                                  std::nextafter(lo, lo - 1), lo + 0.5 * L,
                                  lo + std::floor(unit(rng) * L / c.radius) * c.radius};
        p[k] = special[rng() % 7];
      }
    }
    c.points.push_back(p);
  }
  add_queries(c, rng);
  return c;
}

// Points on the lattice lo + m * spacing, m = 0..count-1, i.e. on cell edges and on
// lo and hi themselves when spacing divides the box: distances of exactly radius.
template <int D>
Case<D> lattice_case(Periodicity periodicity, double spacing, int count, double radius) {
  Case<D> c;
  c.domain = make_domain<D>(periodicity, true);
  c.radius = radius;
  c.name = std::string("lattice ") + periodicity_name(periodicity) +
           ", spacing " + std::to_string(spacing);
  std::vector<int> m(D, 0);
  while (true) {
    Vec<D> p;
    for (int k = 0; k < D; ++k) p[k] = c.domain.lo[k] + m[k] * spacing;
    c.points.push_back(p);
    int k = 0;
    while (k < D && ++m[k] == count) m[k++] = 0;
    if (k == D) break;
  }
  std::mt19937_64 rng(17);
  add_queries(c, rng);
  for (std::size_t i = 0; i < c.points.size(); i += 3)  // lattice points shifted half a step
    c.queries.push_back(c.points[i] + Vec<D>::filled(0.5 * spacing));
  return c;
}

template <int D>
Case<D> clustered_case(Periodicity periodicity, const char* name, double radius,
                       std::vector<Vec<D>> points) {
  Case<D> c;
  c.domain = make_domain<D>(periodicity, true);
  c.radius = radius;
  c.name = std::string(name) + " " + periodicity_name(periodicity);
  c.points = std::move(points);
  std::mt19937_64 rng(5);
  add_queries(c, rng);
  return c;
}

}  // namespace

template <int D>
using Dim = std::integral_constant<int, D>;
#define PARTC_ALL_DIMS Dim<1>, Dim<2>, Dim<3>, Dim<4>

TEMPLATE_TEST_CASE("random sets match the reference", "[search]", PARTC_ALL_DIMS) {
  constexpr int D = TestType::value;
  std::uint64_t seed = 1000 * D;
  for (Periodicity periodicity : {Periodicity::none, Periodicity::all, Periodicity::mixed})
    for (std::size_t n : {0, 1, 2, 31, 150})
      // 0.003: capped cell count; 0.3-0.34: about 3 cells; 0.5+: radius beyond half the box.
      for (double radius_fraction : {0.003, 0.13, 0.3, 0.34, 0.5, 0.61, 1.7})
        check_all_structures(random_case<D>(periodicity, n, radius_fraction, ++seed));
}

TEMPLATE_TEST_CASE("points on cell edges and on lo/hi match the reference", "[search]",
                   PARTC_ALL_DIMS) {
  constexpr int D = TestType::value;
  for (Periodicity periodicity : {Periodicity::none, Periodicity::all, Periodicity::mixed}) {
    // Box [-1, 1]: 5 points per dimension, -1 and 1 included.
    for (double radius : {0.5, 0.25, 1.0 /* = L/2 */, 2.0 / 3.0, 0.5 + 1e-15, 0.5 - 1e-15, 3.0})
      check_all_structures(lattice_case<D>(periodicity, 0.5, 5, radius));
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
  for (Periodicity periodicity : {Periodicity::none, Periodicity::all, Periodicity::mixed}) {
    std::vector<Vec<D>> one_cell;
    for (int i = 0; i < 60; ++i) {
      Vec<D> p;
      for (int k = 0; k < D; ++k) p[k] = 0.1 + tiny(rng);
      one_cell.push_back(p);
    }
    check_all_structures(clustered_case<D>(periodicity, "all in one cell", 0.3, one_cell));

    std::vector<Vec<D>> duplicates;
    for (int i = 0; i < 20; ++i) {
      duplicates.push_back(Vec<D>::filled(0.25));
      duplicates.push_back(Vec<D>::filled(-1.0));  // lo corner
      duplicates.push_back(Vec<D>::filled(1.0));   // hi corner: the lo corner when periodic
    }
    for (double radius : {0.2, 1e-9, 1.5})
      check_all_structures(clustered_case<D>(periodicity, "duplicates", radius, duplicates));
  }
}

TEST_CASE("NaN points are never reported and do not disturb the others", "[search]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (Periodicity periodicity : {Periodicity::none, Periodicity::all}) {
    std::vector<Vec<2>> points = {Vec<2>{{0.0, 0.0}}, Vec<2>{{nan, 0.0}}, Vec<2>{{0.1, 0.0}},
                                  Vec<2>{{0.0, nan}}, Vec<2>{{-0.1, 0.05}}};
    for (int i = 0; i < 40; ++i) points.push_back(Vec<2>{{0.02 * i - 0.9, 0.5}});
    Case<2> c = clustered_case<2>(periodicity, "with NaN", 0.15, points);
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
    partc::ParticleSet<2> set;
    set.push_back(points[0]);
    CHECK_THROWS_WITH(partc::NeighbourSearch<2>().build(box, radius, set),
                      Catch::Contains("radius must be positive"));
  }
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

TEST_CASE("the facade picks brute force when queries would examine nearly every point",
          "[search]") {
  const Domain<2> box = make_domain<2>(Periodicity::all, true);  // L = 2
  partc::ParticleSet<2> set;
  for (int i = 0; i < 100; ++i) set.push_back(Vec<2>{{0.01 * i, -0.013 * i}});
  partc::NeighbourSearch<2> search;
  search.build(box, 0.2, set);  // 10 x 10 cells: a query examines 9% of the points
  CHECK(search.kind() == partc::NeighbourSearch<2>::Kind::cell_list);
  CHECK(search.cell_count() == 10 * 10);
  search.build(box, 0.66, set);  // 3 x 3 cells: a query examines 99%
  CHECK(search.kind() == partc::NeighbourSearch<2>::Kind::brute_force);
  CHECK(search.cell_count() == 0);
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
