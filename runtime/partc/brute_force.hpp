// partc/brute_force.hpp: BruteForce<D>, the O(N)-per-query neighbour search.
// Fastest for small N (see NeighbourSearch::default_brute_force_below) and the
// only structure without restrictions: any radius, any periodic box.
//
// Query contract (shared by every search structure): for_each_near(q, f) calls
// f(j, dx) exactly once for each point j with |dx|^2 <= radius^2 * (1 + 1e-12),
// dx = domain.minimum_image(points[j] - q); j itself is included when q == points[j].
//
// Surprises: build copies the points (wrapped into the periodic box), so the
// caller's vector may change afterwards; queries see the state at build time.
#pragma once

#include <cstddef>
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
    // Wrapped points and queries keep every displacement within one box length,
    // where minimum_image takes its cheap path.
    points_.resize(points.size());
    for (std::size_t j = 0; j < points.size(); ++j) points_[j] = domain.wrap(points[j]);
  }

  template <class F>
  void for_each_near(const Vec<D>& q, F&& f) const {
    const Vec<D> qw = domain_.wrap(q);
    for (std::size_t j = 0; j < points_.size(); ++j) {
      const Vec<D> dx = domain_.minimum_image(points_[j] - qw);
      if (squared_norm(dx) <= squared_reach_) f(j, dx);
    }
  }

 private:
  Domain<D> domain_{};
  double squared_reach_ = 0.0;
  std::vector<Vec<D>> points_;
};

}  // namespace partc
