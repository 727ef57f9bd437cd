// partc/domain.hpp: Domain<D>, the axis-aligned simulation box [lo, hi) with
// per-dimension periodicity, and the two periodic maps every kernel needs.
//
// Surprises:
// - minimum_image maps periodic components into the CLOSED interval [-L/2, L/2]
//   (a displacement of exactly L/2 stays +L/2); it is exact for any magnitude,
//   many box lengths included (IEEE remainder), with a branch-free path for
//   |d| <= 1.5L, which covers the difference of any two wrapped points.
// - wrap maps periodic components into the HALF-OPEN [lo, hi): x - lo + L can
//   round up to exactly L, so a result that would land on hi is returned as lo
//   (the same point of the torus).
// - NaN stays NaN through both maps (+-inf becomes NaN), so a blow-up is never
//   hidden inside the box; non-periodic components are never touched.
// - wrap_into stores a wrapped point at a position's precision (float for a
//   schedule's precision = float): the float nearest a point just below hi can
//   be hi itself, or beyond it when hi is no float, so it takes the float
//   below instead (round_inside). The box must hold a float for that: any box
//   wider than a few float ulps of its bounds does.
// - check_search_arguments validates what every neighbour search needs, so the
//   search structures share one message.
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "partc/vec.hpp"

namespace partc {

// x (in [lo, hi), or [lo, hi] when `closed`) rounded to the nearest T, or to
// its neighbour towards x when the nearest T lies outside: one step always
// suffices, the neighbour being on x's other side. NaN stays NaN.
template <class T>
T round_inside(double x, double lo, double hi, bool closed = false) {
  T r = static_cast<T>(x);
  if (closed ? r > hi : r >= hi) r = std::nextafter(r, std::numeric_limits<T>::lowest());
  if (r < lo) r = std::nextafter(r, std::numeric_limits<T>::max());
  return r;
}

template <int D>
struct Domain {
  Vec<D> lo, hi;
  std::array<bool, D> periodic;

  Vec<D> length() const { return hi - lo; }

  Vec<D> minimum_image(Vec<D> d) const {
    for (int k = 0; k < D; ++k) {
      if (!periodic[k]) continue;
      const double L = hi[k] - lo[k];
      const double half = 0.5 * L;
      // One shift covers every difference of two wrapped points and is exact
      // (Sterbenz's lemma) for L/2 < |d| <= 2L. The shift count is an int so that
      // compilers emit setcc rather than a branch: in a kernel about half of the
      // pairs need a shift, unpredictably. Longer d (or NaN): exact IEEE remainder.
      const int shift = static_cast<int>(d[k] > half) - static_cast<int>(d[k] < -half);
      const double image = d[k] - L * shift;
      d[k] = std::abs(image) <= half ? image : std::remainder(d[k], L);
    }
    return d;
  }

  Vec<D> wrap(Vec<D> x) const {
    for (int k = 0; k < D; ++k) {
      if (!periodic[k] || (x[k] >= lo[k] && x[k] < hi[k])) continue;
      const double L = hi[k] - lo[k];
      double y = lo[k] + std::fmod(x[k] - lo[k], L);  // fmod is exact; the sums round
      if (y < lo[k]) y += L;
      if (y >= hi[k] || y < lo[k]) y = lo[k];  // round-off landed on hi (or a hair below lo)
      x[k] = y;
    }
    return x;
  }

  // stored = wrap(x) at stored's precision, periodic components kept in [lo, hi).
  template <class T>
  void wrap_into(Vec<D, T>& stored, const Vec<D>& x) const {
    const Vec<D> w = wrap(x);
    for (int k = 0; k < D; ++k)
      stored[k] = periodic[k] ? round_inside<T>(w[k], lo[k], hi[k]) : static_cast<T>(w[k]);
  }
};

// Throws std::invalid_argument unless radius is positive (not NaN) and every
// periodic dimension has finite lo < hi (minimum_image and wrap need a length).
template <int D>
void check_search_arguments(const Domain<D>& domain, double radius) {
  const auto fail = [](auto&&... parts) {
    std::ostringstream message;
    message << "partc: neighbour search: ";
    (message << ... << parts);
    throw std::invalid_argument(message.str());
  };
  if (!(radius > 0.0)) fail("radius must be positive, got ", radius);
  for (int k = 0; k < D; ++k) {
    const double lo = domain.lo[k], hi = domain.hi[k];
    if (domain.periodic[k] && !(std::isfinite(lo) && std::isfinite(hi) && lo < hi))
      fail("periodic dimension ", k, " needs finite lo < hi, got [", lo, ", ", hi, ")");
  }
}

}  // namespace partc
