// partc/brute_force.hpp: BruteForce<D>, the O(N)-per-query neighbour search.
// Fastest for small N (see NeighbourSearch::default_margin) and the
// only structure without restrictions: any radius, any periodic box.
//
// Query contract (shared by every search structure): for_each_near(q, f) calls
// f(j, dx) exactly once for each point j with |dx|^2 <= radius^2 * (1 + 1e-12),
// dx = domain.minimum_image(points[j] - q); j itself is included when q == points[j].
//
// Surprises: build copies the points, wrapped into the periodic box, so the
// caller's vector may change afterwards. With points and query wrapped, every
// periodic component of points[j] - q lies in (-L, L), so the pair loop does
// minimum_image's single branch-free shift inline with per-dimension constants
// (non-periodic: never shifted) and needs no remainder fallback.
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "partc/domain.hpp"
#include "partc/vec.hpp"

namespace partc {

template <int D>
class BruteForce {
 public:
  void build(const Domain<D>& domain, double radius, const std::vector<Vec<D>>& points) {
    check_search_arguments(domain, radius);
    domain_ = domain;
    squared_reach_ = radius * radius * (1 + 1e-12);
    for (int k = 0; k < D; ++k) {
      // Non-periodic: a shift of 0 * 0 when |d| > infinity, i.e. never (and no inf * 0).
      length_[k] = domain.periodic[k] ? domain.hi[k] - domain.lo[k] : 0.0;
      half_[k] = domain.periodic[k] ? 0.5 * length_[k] : std::numeric_limits<double>::infinity();
    }
    points_.resize(points.size());
    for (std::size_t j = 0; j < points.size(); ++j) points_[j] = domain.wrap(points[j]);
  }

  template <class F>
  void for_each_near(const Vec<D>& q, F&& f) const {
    const Vec<D> qw = domain_.wrap(q);
    for (std::size_t j = 0; j < points_.size(); ++j) {
      Vec<D> dx = points_[j] - qw;
      for (int k = 0; k < D; ++k) {  // as in Domain::minimum_image: setcc, not a branch
        const int shift = static_cast<int>(dx[k] > half_[k]) - static_cast<int>(dx[k] < -half_[k]);
        dx[k] -= length_[k] * shift;
      }
      if (squared_norm(dx) <= squared_reach_) f(j, dx);
    }
  }

 // Point j of the last build, wrapped into the periodic box.
  const Vec<D>& point(std::size_t j) const { return points_[j]; }

 private:
  Domain<D> domain_{};
  Vec<D> length_{}, half_{};
  double squared_reach_ = 0.0;
  std::vector<Vec<D>> points_;
};

}  // namespace partc
