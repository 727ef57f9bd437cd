// partc/search/brute_force.hpp: BruteForce<D>, the O(N)-per-query neighbour search.
// Fastest for small N (see NeighbourSearch::default_margin) and the
// only structure without restrictions: any radius, any periodic box.
//
// Query contract (shared by every search structure): for_each_near(q, f) calls
// f(j, dx) exactly once for each point j with |dx|^2 <= radius^2 * (1 + 1e-12),
// dx = domain.minimum_image(points[j] - q); j itself is included when q == points[j].
//
// Radius over half a periodic length: then a point can be within the radius
// under several images, dx = minimum image + s * L (s integer, per periodic
// dimension), and BruteForce reports every one of them: f(j, dx) once per
// image within the radius (j's images in a fixed order), including the
// query's own images when q == points[j] (dx = s * L, s != 0). Only BruteForce
// does this (the others see the nearest image only), so NeighbourSearch uses
// it for such radii; all_images() says whether this build is in that regime.
//
// Surprises: build copies the points, wrapped into the periodic box, so the
// caller's vector may change afterwards. With points and query wrapped, every
// periodic component of points[j] - q lies in (-L, L), so the pair loop does
// minimum_image's single branch-free shift inline with per-dimension constants
// (non-periodic: never shifted) and needs no remainder fallback.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "partc/domain.hpp"
#include "partc/search/search_instances.hpp"
#include "partc/vec.hpp"

namespace partc {

template <int D>
class BruteForce {
 public:
  static constexpr double max_lengths_per_radius = 10.0;

  template <class T>
  void build(const Domain<D>& domain, double radius, const std::vector<Vec<D, T>>& points) {
    check_search_arguments(domain, radius);
    domain_ = domain;
    squared_reach_ = radius * radius * (1 + 1e-12);
    for (int k = 0; k < D; ++k) {
      // Non-periodic: a shift of 0 * 0 when |d| > infinity, i.e. never (and no inf * 0).
      length_[k] = domain.periodic[k] ? domain.hi[k] - domain.lo[k] : 0.0;
      half_[k] = domain.periodic[k] ? 0.5 * length_[k] : std::numeric_limits<double>::infinity();
    }
    reach_ = radius * (1 + 1e-12);
    all_images_ = needs_all_images(domain, radius);
    for (int k = 0; k < D; ++k) {
      if (!domain.periodic[k]) continue;
      // Every pair would have (2 radius / L)^D images: such a radius is a mistake.
      if (reach_ > max_lengths_per_radius * length_[k]) {
        std::ostringstream message;
        message << "partc: neighbour search: radius " << radius << " spans more than "
                << max_lengths_per_radius << " periodic lengths (" << length_[k]
                << ") in dimension " << k;
        throw std::invalid_argument(message.str());
      }
    }
    if (all_images_) make_image_shifts();
    points_.resize(points.size());
    for (std::size_t j = 0; j < points.size(); ++j) points_[j] = domain.wrap(points[j]);
  }

  template <class F>
  void for_each_near(const Vec<D>& q, F&& f) const {
    for_each_near_wrapped(domain_.wrap(q), 0, f);
  }

  // As for_each_near(point(k), f), for point k of the last build (no wrapping).
  template <class F>
  void for_each_near(std::size_t k, F&& f) const {
    for_each_near_wrapped(points_[k], 0, f);
  }

  // Each pair once (the pair walk of slab_schedule.hpp): f(i, pairs) for each
  // point i ascending, pairs(g) calling g(j, dx) for every j >= i that
  // for_each_near(i) reports, with the same dx, j ascending, then image: so
  // (i, 0) once, and i's own images if any.
  template <class F>
  void for_each_pair(F&& f) const {
    for (std::size_t i = 0; i < points_.size(); ++i)
      f(i, [&](auto&& g) { for_each_near_wrapped(points_[i], i, g); });
  }

  // f(j, point) for every point with lo <= point <= hi componentwise (point as
  // stored: wrapped into the periodic box; the box itself does not wrap).
  template <class F>
  void for_each_in_box(const Vec<D>& lo, const Vec<D>& hi, F&& f) const {
    for (std::size_t j = 0; j < points_.size(); ++j)
      if (inside(points_[j], lo, hi)) f(j, points_[j]);
  }

  // True when the radius exceeds half a periodic length: points may be reported
  // more than once, under several images (see the header).
  bool all_images() const { return all_images_; }
  static bool needs_all_images(const Domain<D>& domain, double radius) {
    for (int k = 0; k < D; ++k)
      if (domain.periodic[k] && 2 * radius * (1 + 1e-12) > domain.hi[k] - domain.lo[k]) return true;
    return false;
  }

  // Point j of the last build, wrapped into the periodic box.
  const Vec<D>& point(std::size_t j) const { return points_[j]; }

 private:
  // The query loop over points first, first + 1, ..., qw wrapped into the periodic box.
  template <class F>
  void for_each_near_wrapped(const Vec<D>& qw, std::size_t first, F&& f) const {
    if (all_images_) {
      if (one_box_)
        for_each_image(qw, first, one_box_shifts_, f);
      else
        for_each_image(qw, first, image_shifts_, f);
      return;
    }
    for (std::size_t j = first; j < points_.size(); ++j) {
      Vec<D> dx = points_[j] - qw;
      for (int k = 0; k < D; ++k) {  // as in Domain::minimum_image: setcc, not a branch
        const int shift = static_cast<int>(dx[k] > half_[k]) - static_cast<int>(dx[k] < -half_[k]);
        dx[k] -= length_[k] * shift;
      }
      if (squared_norm(dx) <= squared_reach_) f(j, dx);
    }
  }

  // f(j, d + shift) for every point j >= first and shift within reach, d = points[j] - qw.
  // Both are wrapped, so |d_k| < L_k, and the images of j within reach are
  // d + s L with |s_k| <= ceil(reach / L_k): the shifts tried, in a fixed order.
  // (Trying them on d itself, independent additions, was measured faster than
  // taking the nearest image first and fewer shifts: seed kernel, N = 10.)
  template <class Shifts, class F>
  void for_each_image(const Vec<D>& qw, std::size_t first, const Shifts& shifts, F& f) const {
    for (std::size_t j = first; j < points_.size(); ++j) {
      const Vec<D> d = points_[j] - qw;
      for (const Vec<D>& shift : shifts) {
        const Vec<D> dx = d + shift;
        if (squared_norm(dx) <= squared_reach_) f(j, dx);
      }
    }
  }

  // The shifts s * L with |s_k| <= ceil(reach / L_k) in each periodic dimension
  // (0 in the others), s_0 changing fastest. When every periodic length exceeds
  // the reach, s_k in {-1, 0, 1}: a fixed-size table instead, whose loop the
  // C++ compiler unrolls (seed kernel, N = 10: 17% faster), with an infinite
  // shift standing for s_k != 0 in a non-periodic dimension (never within reach).
  void make_image_shifts() {
    one_box_ = true;
    for (int k = 0; k < D; ++k) one_box_ = one_box_ && (!domain_.periodic[k] || reach_ < length_[k]);
    image_shifts_.clear();
    if (one_box_) {
      for (std::size_t c = 0; c < one_box_shifts_.size(); ++c) {
        std::size_t code = c;
        for (int k = 0; k < D; ++k, code /= 3) {
          const double s_k = static_cast<double>(code % 3) - 1.0;
          one_box_shifts_[c][k] = s_k == 0.0 ? 0.0
                                  : domain_.periodic[k] ? s_k * length_[k]
                                                        : std::numeric_limits<double>::infinity();
        }
      }
      return;
    }
    std::array<long, D> m{}, s{};
    for (int k = 0; k < D; ++k) {
      m[k] = domain_.periodic[k] ? static_cast<long>(std::ceil(reach_ / length_[k])) : 0;
      s[k] = -m[k];
    }
    while (true) {
      Vec<D> shift;
      for (int k = 0; k < D; ++k) shift[k] = static_cast<double>(s[k]) * length_[k];
      image_shifts_.push_back(shift);
      int k = 0;
      while (k < D && s[k] == m[k]) s[k] = -m[k], ++k;
      if (k == D) return;
      ++s[k];
    }
  }

  static constexpr std::size_t pow3(int d) { return d == 0 ? 1 : 3 * pow3(d - 1); }

  Domain<D> domain_{};
  Vec<D> length_{}, half_{};
  double reach_ = 0.0;
  double squared_reach_ = 0.0;
  bool all_images_ = false;
  // all_images_ only: one_box_ (every periodic length exceeds the reach) says
  // which table of shifts holds them.
  bool one_box_ = false;
  std::array<Vec<D>, pow3(D)> one_box_shifts_{};
  std::vector<Vec<D>> image_shifts_;
  std::vector<Vec<D>> points_;
};

// Compiled once, in the runtime library (search_instances.hpp).
PARTC_SEARCH_INSTANCES(extern template, BruteForce);

}  // namespace partc
