// What the search structure tests (test_search.cpp, test_kd_tree.cpp,
// test_verlet_list.cpp) share: the independent brute-force reference for
// fixed-radius queries under minimum-image periodicity, with the rounding
// allowance it grants, and the generators of their test cases (boxes, random,
// lattice and hand-made point sets, queries in and far outside the box).
#pragma once

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <cstdint>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "partc/domain.hpp"
#include "partc/vec.hpp"

namespace search_cases {

using partc::Domain;
using partc::Vec;

constexpr double eps = std::numeric_limits<double>::epsilon();

template <int D>
struct Case {
  std::string name;
  Domain<D> domain;
  double radius;
  std::vector<Vec<D>> points;
  std::vector<Vec<D>> queries;
  bool exact = false;  // dyadic points: distances from dyadic queries are exact, ties included
};

inline std::string show(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

template <int D>
std::string show(const Vec<D>& v) {
  std::ostringstream s;
  s.precision(17);
  s << "(";
  for (int k = 0; k < D; ++k) s << (k ? ", " : "") << v[k];
  return s.str() + ")";
}

// Independent of Domain::minimum_image: subtract the nearest whole number of boxes.
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

// The same over the domain's corners and all points.
template <int D>
double magnitude(const Domain<D>& domain, const std::vector<Vec<D>>& points) {
  double m = std::max(magnitude(domain.lo), magnitude(domain.hi));
  for (const auto& p : points) m = std::max(m, magnitude(p));
  return m;
}

// Per-component allowance for the rounding of positions, shifts and wrapping in a
// query at q among points of magnitude(domain, points) = points_magnitude.
template <int D>
double tolerance(double points_magnitude, const Vec<D>& q) {
  return 64 * eps * std::max(points_magnitude, magnitude(q));
}

// Structures report indices into their own order of the points: result[k] = points[order[k]].
template <int D>
std::vector<Vec<D>> in_order(const std::vector<Vec<D>>& points,
                             const std::vector<std::size_t>& order) {
  std::vector<Vec<D>> result;
  for (std::size_t i : order) result.push_back(points[i]);
  return result;
}

// What a query at q may and must report: components of dx within tol of the
// reference; nothing farther than too_far; everything with |dx|^2 within
// must_find_squared - the contract's inflated radius, less what rounding may move
// a distance: points a hair beyond r (lattice neighbours at r(1 + 1e-16)).
struct Bounds {
  double tol, too_far, must_find_squared;
};

template <int D>
Bounds bounds(double r, double points_magnitude, const Vec<D>& q) {
  const double tol = tolerance(points_magnitude, q);
  return {tol, r * (1 + 1e-12) + D * tol, std::max(r * r, r * r * (1 + 1e-12) - 2 * r * D * tol)};
}

// Where a disagreement is: the query, and the point when there is one.
template <int D>
std::string where(std::size_t iq, const Vec<D>& q, std::size_t j,
                  const std::vector<Vec<D>>& points) {
  return "query " + std::to_string(iq) + " " + show(q) + ", j " + std::to_string(j) + " " +
         (j < points.size() ? show(points[j]) : std::string("?")) + ": ";
}

// One query under the contract (each point within the radius once, with its
// shortest dx): the disagreements, appended to errors.
template <int D, class Query>
void check_nearest(const Domain<D>& domain, const std::vector<Vec<D>>& points, std::size_t iq,
                   const Vec<D>& q, const Bounds& b, const Query& query,
                   std::vector<std::string>& errors) {
  std::vector<int> hits(points.size());
  std::vector<Vec<D>> found(points.size());
  query([&](std::size_t j, const Vec<D>& dx) {
    if (j >= points.size()) {
      errors.push_back(where(iq, q, j, points) + "index out of range");
      return;
    }
    ++hits[j];
    found[j] = dx;
  });
  for (std::size_t j = 0; j < points.size(); ++j) {
    const Vec<D> ref = reference_image(domain, points[j] - q);
    if (hits[j] == 0) {
      if (squared_norm(ref) <= b.must_find_squared)
        errors.push_back(where(iq, q, j, points) + "missed, dx " + show(ref));
      continue;
    }
    if (hits[j] > 1)
      errors.push_back(where(iq, q, j, points) + "reported " + std::to_string(hits[j]) + " times");
    if (!(norm(ref) <= b.too_far))
      errors.push_back(where(iq, q, j, points) + "too far, dx " + show(ref));
    for (int k = 0; k < D; ++k) {
      const double got = found[j][k];
      if (std::abs(got - ref[k]) <= b.tol) continue;
      // A point exactly half a box away has two shortest images; either will do.
      const double half = 0.5 * (domain.hi[k] - domain.lo[k]);
      const bool tie = domain.periodic[k] && std::abs(std::abs(ref[k]) - half) <= b.tol &&
                       std::abs(got + ref[k]) <= b.tol;
      if (!tie) {
        errors.push_back(where(iq, q, j, points) + "dx " + show(found[j]) + ", expected " +
                         show(ref));
        break;
      }
    }
  }
}

// One query for a radius over half a periodic length, where every image of a
// point within the radius must be reported once (brute_force.hpp): the images
// are the nearest one plus s whole boxes, s = -m..m per periodic dimension with
// m enough to pass the radius, all checked; each reported (j, dx) must match an
// image of j not yet matched.
template <int D, class Query>
void check_all_images(const Domain<D>& domain, double r, const std::vector<Vec<D>>& points,
                      std::size_t iq, const Vec<D>& q, const Bounds& b, const Query& query,
                      std::vector<std::string>& errors) {
  struct Image {
    Vec<D> dx;
    bool required, matched;
  };
  std::vector<std::vector<Image>> images(points.size());
  for (std::size_t j = 0; j < points.size(); ++j) {
    const Vec<D> nearest = reference_image(domain, points[j] - q);
    if (!is_finite(nearest)) continue;
    std::array<std::vector<double>, D> offsets;  // per dimension: the shifts worth trying
    for (int k = 0; k < D; ++k) {
      const double L = domain.hi[k] - domain.lo[k];
      const int m = domain.periodic[k] ? static_cast<int>(std::ceil(r / L)) + 1 : 0;
      for (int s = -m; s <= m; ++s)
        if (std::abs(nearest[k] + s * L) <= b.too_far) offsets[k].push_back(s * L);
    }
    std::array<std::size_t, D> at{};
    bool done = false;
    for (int k = 0; k < D; ++k) done = done || offsets[k].empty();
    while (!done) {
      Vec<D> dx = nearest;
      for (int k = 0; k < D; ++k) dx[k] += offsets[k][at[k]];
      if (norm(dx) <= b.too_far)
        images[j].push_back({dx, squared_norm(dx) <= b.must_find_squared, false});
      int k = 0;
      while (k < D && ++at[k] == offsets[k].size()) at[k++] = 0;
      done = k == D;
    }
  }
  query([&](std::size_t j, const Vec<D>& dx) {
    if (j >= points.size()) {
      errors.push_back(where(iq, q, j, points) + "index out of range");
      return;
    }
    for (Image& image : images[j]) {
      bool close = !image.matched;
      for (int k = 0; k < D && close; ++k) close = std::abs(dx[k] - image.dx[k]) <= b.tol;
      if (!close) continue;
      image.matched = true;
      return;
    }
    errors.push_back(where(iq, q, j, points) + "dx " + show(dx) +
                     " is no image within the radius, or twice");
  });
  for (std::size_t j = 0; j < points.size(); ++j)
    for (const Image& image : images[j])
      if (image.required && !image.matched)
        errors.push_back(where(iq, q, j, points) + "missed the image dx " + show(image.dx));
}

// Runs every query through for_each_near(iq, report), which must call report(j, dx)
// for each point the structure under test finds near queries[iq] (j indexes
// `points`), and returns a description of each disagreement with the reference:
// every point within `radius` once, with its shortest dx = points[j] - queries[iq];
// with all_images (a radius over half a periodic length), every image of it.
template <int D, class ForEachNear>
std::vector<std::string> disagreements(const Domain<D>& domain, double radius,
                                       const std::vector<Vec<D>>& points,
                                       const std::vector<Vec<D>>& queries,
                                       const ForEachNear& for_each_near, bool all_images = false) {
  const double points_magnitude = magnitude(domain, points);
  std::vector<std::string> errors;
  for (std::size_t iq = 0; iq < queries.size(); ++iq) {
    const Vec<D>& q = queries[iq];
    const Bounds b = bounds<D>(radius, points_magnitude, q);
    const auto query = [&](const auto& report) { for_each_near(iq, report); };
    if (all_images)
      check_all_images(domain, radius, points, iq, q, b, query, errors);
    else
      check_nearest(domain, points, iq, q, b, query, errors);
  }
  return errors;
}

// The queries of c against a structure queried by position, for_each_near(q, report),
// whose indices refer to `points` (c.points in the structure's order).
// With all_images, every image counts (BruteForce and NeighbourSearch for a
// radius over half a periodic length).
template <int D, class Search>
std::vector<std::string> disagreements(const Case<D>& c, const std::vector<Vec<D>>& points,
                                       const Search& search, bool all_images = false) {
  return disagreements(
      c.domain, c.radius, points, c.queries,
      [&](std::size_t iq, const auto& report) { search.for_each_near(c.queries[iq], report); },
      all_images);
}

// for_each_in_box against every stored (wrapped, finite) point, for boxes around
// the queries, the whole domain, an infinite box, a point and an empty box; pts
// are the case's points in the structure's order.
template <int D, class Search>
std::vector<std::string> box_disagreements(const Case<D>& c, const std::vector<Vec<D>>& pts,
                                           const Search& search) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::vector<std::pair<Vec<D>, Vec<D>>> boxes = {
      {c.domain.lo, c.domain.hi},
      {Vec<D>::filled(-inf), Vec<D>::filled(inf)},
      {c.domain.hi, c.domain.lo}};
  for (std::size_t i = 0; i < c.queries.size(); i += 3) {
    Vec<D> half_width;
    for (int k = 0; k < D; ++k) half_width[k] = c.radius * (0.5 + 0.3 * k);
    boxes.emplace_back(c.queries[i] - half_width, c.queries[i] + half_width);
    if (i < pts.size()) {
      const Vec<D> p = c.domain.wrap(pts[i]);
      boxes.emplace_back(p, p);
    }
  }
  std::vector<std::string> errors;
  std::vector<int> hits(pts.size());
  for (const auto& [lo, hi] : boxes) {
    const std::string where = "box " + show(lo) + " - " + show(hi) + ", j ";
    std::fill(hits.begin(), hits.end(), 0);
    search.for_each_in_box(lo, hi, [&](std::size_t j, const Vec<D>& p) {
      if (j >= pts.size()) {
        errors.push_back(where + std::to_string(j) + ": index out of range");
        return;
      }
      ++hits[j];
      const Vec<D> stored = c.domain.wrap(pts[j]);
      if (std::memcmp(&p, &stored, sizeof p) != 0)
        errors.push_back(where + std::to_string(j) + ": point " + show(p) + ", stored " +
                         show(stored));
    });
    for (std::size_t j = 0; j < pts.size(); ++j) {
      const Vec<D> p = c.domain.wrap(pts[j]);
      bool inside = is_finite(p);
      for (int k = 0; k < D; ++k) inside = inside && lo[k] <= p[k] && p[k] <= hi[k];
      if (hits[j] != (inside ? 1 : 0))
        errors.push_back(where + std::to_string(j) + " " + show(p) + ": reported " +
                         std::to_string(hits[j]) + " times");
    }
  }
  return errors;
}

// One assertion per call, showing the first few disagreements when it fails.
template <class Errors>
void check_no_errors(const std::string& what, const Errors& errors) {
  std::string first;
  for (std::size_t i = 0; i < std::min<std::size_t>(errors.size(), 5); ++i)
    first += "\n  " + errors[i];
  INFO(what << ": " << errors.size() << " disagreements" << first);
  CHECK(errors.empty());
}

// ---------------------------------------------------------------------------
// Case generators

// TEMPLATE_TEST_CASE takes types: the dimension as one. The structures are tested
// in dimensions 1-4.
template <int D>
using Dim = std::integral_constant<int, D>;
#define PARTC_ALL_DIMS \
  search_cases::Dim<1>, search_cases::Dim<2>, search_cases::Dim<3>, search_cases::Dim<4>

enum class Periodicity { none, all, mixed };
constexpr Periodicity all_periodicities[] = {Periodicity::none, Periodicity::all,
                                             Periodicity::mixed};

inline const char* periodicity_name(Periodicity p) {
  return p == Periodicity::none ? "non-periodic" : p == Periodicity::all ? "periodic" : "mixed";
}

// uniform: [-1, 1] in every dimension; else [-1 - k/4, 1 + k/2) in dimension k,
// lengths 2, 2.75, 3.5, 4.25. Mixed: the even dimensions are periodic.
template <int D>
Domain<D> make_domain(Periodicity periodicity, bool uniform) {
  Domain<D> d{};
  for (int k = 0; k < D; ++k) {
    d.lo[k] = uniform ? -1.0 : -1.0 - 0.25 * k;
    d.hi[k] = uniform ? 1.0 : d.lo[k] + 2.0 + 0.75 * k;
    d.periodic[k] =
        periodicity == Periodicity::all || (periodicity == Periodicity::mixed && k % 2 == 0);
  }
  return d;
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

// Given points in a standard box, with the standard queries.
template <int D>
Case<D> make_case(const std::string& name, Periodicity periodicity, bool uniform, double radius,
                  std::vector<Vec<D>> points) {
  Case<D> c;
  c.name = name + " " + periodicity_name(periodicity);
  c.domain = make_domain<D>(periodicity, uniform);
  c.radius = radius;
  c.points = std::move(points);
  std::mt19937_64 rng(5);
  add_queries(c, rng);
  return c;
}

// Mostly uniform points in the non-uniform box; some outside it; some with
// coordinates on lo or hi, next to them, half a box away, or on the (nominal)
// cell edges lo + m * radius.
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

// Calls check on random cases of every periodicity, with 0 to 150 points and radii
// from 0.003 of the shortest box side (a capped cell count) through 0.3-0.34 (about
// 3 cells; the k-d tree's switch between images and the exact mode) to beyond half
// of it (0.5+); the seeds are first_seed + 1, + 2, ...
template <int D, class Check>
void for_each_random_case(std::uint64_t first_seed, const Check& check) {
  std::uint64_t seed = first_seed;
  for (Periodicity periodicity : all_periodicities)
    for (std::size_t n : {0, 1, 2, 31, 150})
      for (double radius_fraction : {0.003, 0.13, 0.3, 0.34, 0.5, 0.61, 1.7})
        check(random_case<D>(periodicity, n, radius_fraction, ++seed));
}

// Points on the lattice lo + m * spacing, m = 0..count-1, in [-1, 1]: on cell edges,
// and on lo and hi themselves when spacing divides the box (with spacing 0.5 and 5
// points), so that many distances are exactly the radius.
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

}  // namespace search_cases
