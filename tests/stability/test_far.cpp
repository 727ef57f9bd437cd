// A unit box far from the origin, [1e8, 1e8 + 1)^2 (tests/stability/far.part).
// A position there is a double with ulp 2^-26 = 1.49e-8, so placing the
// particles (lo + offset) rounds each coordinate by up to 2^-27; that is the
// only loss allowed. The difference of two such doubles is exact (Sterbenz),
// so the distances, the sum of exp(-|dx| / rc) and the nearest distance must
// equal a long double reference
// - from the model's own positions, taken as offsets from lo (x - lo is exact):
//   to double rounding, relative 1e-14 (sqrt, exp and the sum's order);
// - from the offsets as written in the model, exactly: within the placement's
//   rounding, |d_model - d| <= sqrt(2) 2^-26 = 2.1e-8 per distance, hence
//   relative 2.1e-8 / rc = 2.1e-7 for each positive term of the sum.
// A search that cancelled catastrophically (differences of positions at 1e8
// formed through anything but x_j - x_i) would miss these by far more.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "brute.hpp"
#include "far.hpp"

namespace {

using LV = std::array<long double, 2>;

struct Reference {
  std::vector<long double> s, nearest;
  std::vector<int> close;
  int near_cutoff = 0;  // pairs within 3e-8 of rc: their inclusion is up to the rounding
};

Reference long_double_reference(const std::vector<LV>& off, long double rc) {
  Reference r{std::vector<long double>(off.size(), 0),
              std::vector<long double>(off.size(), std::numeric_limits<long double>::infinity()),
              std::vector<int>(off.size(), 0)};
  for (std::size_t i = 0; i < off.size(); ++i)
    for (std::size_t j = 0; j < off.size(); ++j) {
      long double d2 = 0;
      for (int k = 0; k < 2; ++k) {
        long double dx = off[j][k] - off[i][k];
        dx -= std::round(dx);  // unit box: minimum image
        d2 += dx * dx;
      }
      const long double d = std::sqrt(d2);
      if (std::abs(d - rc) < 3e-8L) ++r.near_cutoff;
      if (d < rc && d > 0) {
        r.s[i] += std::exp(-d / rc);
        r.close[i] += 1;
        r.nearest[i] = std::min(r.nearest[i], d);
      }
    }
  return r;
}

}  // namespace

TEST_CASE("in a unit box at 1e8, distances and a sum of exp(-|dx|/rc) lose only the "
          "positions' own rounding (long double reference from offsets to lo)",
          "[stability][far]") {
  Far model;
  model.init();
  model.step();
  model.check_finite();
  const int N = model.params().N;
  const long double rc = model.params().rc;
  const double lo = 1e8;

  const auto p = brute::positions_by_id<2>(model.P());
  REQUIRE(static_cast<int>(p.size()) == N);
  std::vector<LV> actual, written;
  double placement = 0;
  for (int id = 0; id < N; ++id) {
    for (int k = 0; k < 2; ++k) {
      REQUIRE(p[id][k] >= lo);
      REQUIRE(p[id][k] < lo + 1);
    }
    actual.push_back({p[id][0] - lo, p[id][1] - lo});  // exact in double
    const LV w{(((id * 29) % N) + 0.5L) / N, std::fmod(id * 0.6180339887498949L, 1.0L)};
    written.push_back(w);
    for (int k = 0; k < 2; ++k)
      placement = std::max(placement, static_cast<double>(std::abs(actual[id][k] - w[k])));
  }
  INFO("largest placement error " << placement);
  CHECK(placement <= std::ldexp(1.0, -27) * (1 + 1e-6));  // half an ulp at 1e8
  CHECK(placement > 0);  // the case is not trivially exact

  const auto s = brute::values_by_id<Far::P_s>(model.P());
  const auto s_cells = brute::values_by_id<Far::P_s_cells>(model.P());
  const auto nearest = brute::values_by_id<Far::P_nearest>(model.P());
  const auto close = brute::values_by_id<Far::P_close>(model.P());

  SECTION("against the model's own positions: double rounding only") {
    const Reference r = long_double_reference(actual, rc);
    REQUIRE(r.near_cutoff == 0);
    double worst_s = 0, worst_d = 0;
    for (int i = 0; i < N; ++i) {
      REQUIRE(r.close[i] > 0);
      CHECK(close[i] == r.close[i]);
      worst_s = std::max({worst_s, static_cast<double>(std::abs(s[i] - r.s[i]) / r.s[i]),
                          static_cast<double>(std::abs(s_cells[i] - r.s[i]) / r.s[i])});
      worst_d = std::max(worst_d, static_cast<double>(std::abs(nearest[i] - r.nearest[i]) /
                                                      r.nearest[i]));
    }
    INFO("relative errors: sum " << worst_s << ", nearest " << worst_d);
    CHECK(worst_s <= 1e-14);
    CHECK(worst_d <= 1e-15);
  }
  SECTION("against the offsets as written: the placement's rounding, no more") {
    const Reference r = long_double_reference(written, rc);
    REQUIRE(r.near_cutoff == 0);
    const double dmax = std::sqrt(2.0) * std::ldexp(1.0, -26);
    double worst_s = 0, worst_d = 0;
    for (int i = 0; i < N; ++i) {
      CHECK(close[i] == r.close[i]);
      worst_s = std::max({worst_s, static_cast<double>(std::abs(s[i] - r.s[i]) / r.s[i]),
                          static_cast<double>(std::abs(s_cells[i] - r.s[i]) / r.s[i])});
      worst_d = std::max(worst_d, static_cast<double>(std::abs(nearest[i] - r.nearest[i])));
    }
    INFO("errors: sum relative " << worst_s << ", nearest absolute " << worst_d);
    CHECK(worst_d <= dmax);
    CHECK(worst_s <= dmax / model.params().rc);
  }
}
