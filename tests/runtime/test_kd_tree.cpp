// KdTree against O(N^2) references: for_each_near against search_cases.hpp's,
// which wants exactly the points within the radius under minimum-image
// periodicity, each once with its shortest vector; nearest must return the k
// nearest sorted by distance, then index; for_each_in_box exactly the stored
// points in the box.
// Dimensions 1-4; periodic, non-periodic and mixed boxes; uniform, clustered
// and adversarial point sets; radii up to beyond the periodic box.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "search_cases.hpp"
#include "partc/search/kd_tree.hpp"

using partc::Domain;
using partc::KdTree;
using partc::Vec;
using namespace search_cases;  // Case, disagreements, check_no_errors, the generators

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double quiet_nan = std::numeric_limits<double>::quiet_NaN();

// Every component a multiple of 2^-10 below 2^20: differences and squares of a few
// of these are exact, so the reference's distances are too.
template <int D>
bool is_dyadic(const Vec<D>& v) {
  for (int k = 0; k < D; ++k)
    if (!(std::abs(v[k]) < 0x1p20 && std::floor(v[k] * 0x1p10) == v[k] * 0x1p10)) return false;
  return true;
}

// nearest(q, k) against every finite point sorted by (reference distance, j). Distances
// that differ only by rounding may come in either order, except in exact cases.
template <int D>
std::vector<std::string> nearest_disagreements(const Case<D>& c, const KdTree<D>& tree) {
  const std::vector<Vec<D>> pts = in_order(c.points, tree.order());
  const double points_magnitude = magnitude(c.domain, c.points);
  std::vector<std::string> errors;
  // Each query costs a sort of all points: of the queries at the points, a sample.
  const std::size_t stride = 1 + c.points.size() / 200;
  for (std::size_t iq = 0; iq < c.queries.size(); ++iq) {
    if (iq < c.points.size() && iq % stride != 0) continue;
    const Vec<D>& q = c.queries[iq];
    const double tol = D * tolerance(points_magnitude, q);
    const bool exact = c.exact && is_dyadic(q);
    std::vector<std::pair<double, std::size_t>> ref;
    std::vector<double> ref_distance(pts.size(), quiet_nan);
    if (is_finite(q)) {
      for (std::size_t j = 0; j < pts.size(); ++j) {
        if (!is_finite(pts[j])) continue;
        ref_distance[j] = norm(reference_image(c.domain, pts[j] - q));
        ref.emplace_back(ref_distance[j], j);
      }
    }
    std::sort(ref.begin(), ref.end());
    // k = 30 spans several leaves; k > N (all points, sorted) only for every 4th query: it is slow.
    for (std::size_t k : {std::size_t{0}, std::size_t{1}, std::size_t{2}, std::size_t{7},
                          std::size_t{30}, iq % 4 == 0 ? pts.size() + 3 : 0}) {
      const auto got = tree.nearest(q, k);
      const auto where = [&] {
        return "query " + std::to_string(iq) + " " + show(q) + ", k " + std::to_string(k) + ": ";
      };
      if (got.size() != std::min(k, ref.size())) {
        errors.push_back(where() + std::to_string(got.size()) + " points, expected " +
                         std::to_string(std::min(k, ref.size())));
        continue;
      }
      for (std::size_t i = 0; i < got.size(); ++i) {
        const auto [j, distance] = got[i];
        std::string problem;
        if (j >= pts.size() || !(std::abs(distance - ref_distance[j]) <= tol))
          problem = "distance " + show(distance) + " is not j's";
        else if (!(std::abs(distance - ref[i].first) <= tol))
          problem = "distance " + show(distance) + ", expected " + show(ref[i].first);
        else if (exact && (j != ref[i].second || distance != ref[i].first))
          problem = "expected j " + std::to_string(ref[i].second);
        else if (i > 0 && !(std::make_pair(got[i - 1].second, got[i - 1].first) <
                            std::make_pair(distance, j)))
          problem = "not after the previous point by (distance, j)";
        if (!problem.empty())
          errors.push_back(where() + "rank " + std::to_string(i) + ", j " + std::to_string(j) +
                           ": " + problem);
      }
    }
  }
  return errors;
}

template <int D>
void check_tree(const Case<D>& c) {
  INFO("case " << c.name << ", D = " << D << ", radius " << c.radius << ", N = "
               << c.points.size());
  KdTree<D> tree;
  tree.build(c.domain, c.radius, c.points);
  std::vector<std::size_t> order = tree.order();
  std::sort(order.begin(), order.end());
  for (std::size_t i = 0; i < order.size(); ++i) REQUIRE(order[i] == i);
  REQUIRE(order.size() == c.points.size());
  check_no_errors("for_each_near", disagreements(c, in_order(c.points, tree.order()), tree));
  check_no_errors("nearest", nearest_disagreements(c, tree));
  check_no_errors("for_each_in_box", box_disagreements(c, in_order(c.points, tree.order()), tree));
}

// A few tight Gaussian blobs, one of them centred on the lo corner (split by
// every periodic face), plus a sparse uniform background.
template <int D>
Case<D> blobs_case(Periodicity periodicity, double sigma, double radius, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, sigma);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Vec<D>> centres = {Vec<D>::filled(-1.0), Vec<D>::filled(0.3)};
  for (int b = 0; b < 3; ++b) {
    Vec<D> centre;
    for (int k = 0; k < D; ++k) centre[k] = unit(rng);
    centres.push_back(centre);
  }
  std::vector<Vec<D>> points;
  for (int i = 0; i < 300; ++i) {
    Vec<D> p;
    for (int k = 0; k < D; ++k) p[k] = i % 10 == 0 ? unit(rng) : centres[i % 5][k] + normal(rng);
    points.push_back(p);
  }
  return make_case<D>("blobs sigma " + std::to_string(sigma), periodicity, true, radius,
                      std::move(points));
}

}  // namespace

TEMPLATE_TEST_CASE("kd tree: random sets match the references", "[kd_tree]", PARTC_ALL_DIMS) {
  constexpr int D = TestType::value;
  for_each_random_case<D>(2000 * D, [](const Case<D>& c) { check_tree(c); });
}

TEMPLATE_TEST_CASE("kd tree: clustered sets match the references", "[kd_tree]", PARTC_ALL_DIMS) {
  constexpr int D = TestType::value;
  std::uint64_t seed = 3000 * D;
  for (Periodicity periodicity : all_periodicities) {
    for (double sigma : {0.01, 1e-4}) {
      for (double radius : {sigma, 3 * sigma, 0.2, 1.2})
        check_tree(blobs_case<D>(periodicity, sigma, radius, ++seed));
    }
  }
}

TEMPLATE_TEST_CASE("kd tree: lattices with neighbours exactly at the radius", "[kd_tree]",
                   PARTC_ALL_DIMS) {
  constexpr int D = TestType::value;
  for (Periodicity periodicity : all_periodicities) {
    for (double radius : {0.5, 0.25, 1.0 /* = L/2 */, 2.0 / 3.0, 0.5 + 1e-15, 0.5 - 1e-15, 3.0}) {
      Case<D> c = lattice_case<D>(periodicity, 0.5, 5, radius);
      c.exact = true;
      check_tree(c);
    }
    // Spacing not a power of two: lattice coordinates round.
    check_tree(lattice_case<D>(periodicity, 0.2, D <= 2 ? 11 : 5, 0.2));
  }
}

TEMPLATE_TEST_CASE("kd tree: identical points, points on the faces, N = 0 and 1", "[kd_tree]",
                   PARTC_ALL_DIMS) {
  constexpr int D = TestType::value;
  for (Periodicity periodicity : all_periodicities) {
    for (double radius : {0.2, 1e-9, 1.5}) {
      Case<D> same = make_case<D>("identical", periodicity, true, radius,
                                  std::vector<Vec<D>>(200, Vec<D>::filled(0.25)));
      same.exact = true;
      check_tree(same);

      std::vector<Vec<D>> faces;  // lo and hi corners (the same point when periodic), face centres
      for (int i = 0; i < 20; ++i) {
        faces.push_back(Vec<D>::filled(-1.0));
        faces.push_back(Vec<D>::filled(1.0));
        for (int k = 0; k < D; ++k) {
          Vec<D> p = Vec<D>::filled(0.0);
          p[k] = i % 2 ? 1.0 : -1.0;
          faces.push_back(p);
        }
      }
      Case<D> c = make_case<D>("faces", periodicity, true, radius, faces);
      c.exact = true;
      check_tree(c);
      for (std::size_t n : {0, 1}) {
        Case<D> tiny = make_case<D>("N = " + std::to_string(n), periodicity, true, radius,
                                    std::vector<Vec<D>>(n, Vec<D>::filled(0.5)));
        tiny.exact = true;
        check_tree(tiny);
      }
    }
  }
}

TEST_CASE("kd tree: identical points make one leaf; nodes stay O(N / leaf_size)", "[kd_tree]") {
  const Domain<3> box = make_domain<3>(Periodicity::all, true);
  KdTree<3> tree;
  std::vector<Vec<3>> points(100000, Vec<3>::filled(0.125));
  tree.build(box, 0.1, points);
  CHECK(tree.node_count() == 1);
  std::size_t found = 0;
  tree.for_each_near(Vec<3>::filled(0.15), [&](std::size_t, const Vec<3>&) { ++found; });
  CHECK(found == points.size());
  const double d = std::sqrt(3 * 0.125 * 0.125);  // exact up to the sqrt
  CHECK(tree.nearest(Vec<3>::filled(0.0), 3) ==
        (std::vector<std::pair<std::size_t, double>>{{0, d}, {1, d}, {2, d}}));
  // Half the points equal, the rest spread out: every split still halves the count.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (std::size_t i = 0; i < points.size(); i += 2)
    points[i] = Vec<3>{{unit(rng), unit(rng), unit(rng)}};
  tree.build(box, 0.1, points);
  CHECK(tree.node_count() <= 2 * points.size() / (KdTree<3>::leaf_size / 2));
}

TEST_CASE("kd tree: non-finite points are last in order() and never reported", "[kd_tree]") {
  for (Periodicity periodicity : all_periodicities) {
    std::vector<Vec<2>> points = {Vec<2>{{0.0, 0.0}},  Vec<2>{{quiet_nan, 0.0}},
                                  Vec<2>{{0.1, 0.0}},  Vec<2>{{0.0, quiet_nan}},
                                  Vec<2>{{inf, 0.05}}, Vec<2>{{-0.1, -inf}},
                                  Vec<2>{{-0.1, 0.05}}};
    for (int i = 0; i < 40; ++i) points.push_back(Vec<2>{{0.02 * i - 0.9, 0.5}});
    Case<2> c = make_case<2>("with NaN and inf", periodicity, true, 0.15, points);
    c.queries.push_back(Vec<2>{{quiet_nan, quiet_nan}});
    c.queries.push_back(Vec<2>{{0.0, quiet_nan}});
    c.queries.push_back(Vec<2>{{inf, 0.0}});
    check_tree(c);

    KdTree<2> tree;
    tree.build(c.domain, c.radius, points);
    for (std::size_t k = 0; k < points.size(); ++k)
      CHECK(is_finite(points[tree.order()[k]]) == (k < points.size() - 4));
    CHECK(tree.nearest(Vec<2>{{quiet_nan, 0.0}}, 5).empty());
    CHECK(tree.nearest(Vec<2>{{0.0, 0.0}}, 100).size() == points.size() - 4);
  }
}

TEST_CASE("kd tree: a bad radius or periodic length is rejected", "[kd_tree]") {
  const Domain<2> box = make_domain<2>(Periodicity::mixed, true);
  const std::vector<Vec<2>> points = {Vec<2>{{0.0, 0.0}}};
  for (double radius : {0.0, -1.0, quiet_nan})
    CHECK_THROWS_WITH(KdTree<2>().build(box, radius, points),
                      Catch::Contains("radius must be positive"));
  Domain<2> flat = box;
  flat.hi[0] = flat.lo[0];
  CHECK_THROWS_AS(KdTree<2>().build(flat, 0.1, points), std::invalid_argument);
}
