// partc/faces.hpp: Faces<D>, what a domain's non-periodic faces do to a
// particle that moves past them (periodic faces are Domain::wrap's).
//
// - reflect: the position is mirrored back in through the face, as a
//   specular wall does (LAMMPS's fix wall/reflect); a move longer than the box
//   folds back and forth until it lands in [lo, hi]. The set's `mirrored`
//   variables (velocities) turn their normal component with it.
// - open: the particle leaves its set; leave_through_open_faces removes it
//   and returns how many left, so a run can report them.
// Surprises:
// - A reflected coordinate may equal hi (the interval is closed); one stored
//   as float stays in [lo, hi] after rounding (round_inside, domain.hpp).
// - NaN is never moved or removed (its comparisons are false), so a blow-up
//   still reaches the finite check instead of vanishing through a face.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "partc/domain.hpp"
#include "partc/vec.hpp"

namespace partc {

template <int D>
struct Faces {
  Vec<D> lo, hi;
  std::array<bool, D> reflect;
  std::array<bool, D> open;

  // x folded into the box along reflecting axes; `turned` says along which
  // axes it was mirrored an odd number of times.
  Vec<D> reflect_position(Vec<D> x, std::array<bool, D>& turned) const {
    for (int k = 0; k < D; ++k) {
      turned[k] = false;
      if (reflect[k]) x[k] = fold(x[k], lo[k], hi[k], turned[k]);
    }
    return x;
  }

  bool outside_open(const Vec<D>& x) const {
    for (int k = 0; k < D; ++k)
      if (open[k] && (x[k] < lo[k] || x[k] >= hi[k])) return true;
    return false;
  }

 private:
  static double fold(double x, double lo, double hi, bool& turned) {
    if (x >= lo && x <= hi) return x;
    const double L = hi - lo;
    turned = true;
    if (x < lo && x >= lo - L) return lo + (lo - x);  // one bounce: the usual case, exact mirror
    if (x > hi && x <= hi + L) return hi - (x - hi);
    double y = std::fmod(x - lo, 2 * L);  // NaN stays NaN
    if (y < 0) y += 2 * L;
    turned = y > L;  // an even number of bounces leaves the direction as it was
    if (turned) y = 2 * L - y;
    return lo + y;
  }
};

// Mirrors the positions of `set` that are past a reflecting face back in,
// and turns the same components of each mirrored array (velocities).
template <class Set, int D, class... Mirrored>
void reflect_through_faces(Set& set, const Faces<D>& faces, Mirrored&... mirrored) {
  using T = typename Set::position_type::value_type;
  auto& p = set.positions();
  std::array<bool, D> turned{};
  for (std::size_t i = 0; i < set.size(); ++i) {
    const Vec<D> x = faces.reflect_position(widen(p[i]), turned);
    for (int k = 0; k < D; ++k)
      p[i][k] = faces.reflect[k] ? round_inside<T>(x[k], faces.lo[k], faces.hi[k], true)
                                 : static_cast<T>(x[k]);
    for (int k = 0; k < D; ++k)
      if (turned[k]) ((mirrored[i][k] = -mirrored[i][k]), ...);
  }
}

// Removes the particles of `set` that are past an open face (keeping the
// others in order) and returns how many were removed.
template <class Set, int D>
std::int64_t leave_through_open_faces(Set& set, const Faces<D>& faces) {
  std::int64_t left = 0;
  auto& alive = set.alive();
  const auto& p = set.positions();
  for (std::size_t i = 0; i < set.size(); ++i)
    if (faces.outside_open(p[i])) {
      alive[i] = 0;
      ++left;
    }
  if (left > 0) set.erase_dead();
  return left;
}

}  // namespace partc
