// Mixing rules in user functions (tests/e2e/mixing.part): the pair-once
// force, which the symmetry analysis allows only by reading the functions'
// bodies, against a brute-force loop over all ordered pairs written here.
#include <catch2/catch.hpp>

#include <cmath>

#include "mixing.hpp"
#include "reference.hpp"

TEST_CASE("LJ with Lorentz-Berthelot mixing through user functions, each pair once, matches "
          "brute force over all pairs",
          "[e2e][md]") {
  Mixing model;
  model.set_seed(5);
  model.init();
  model.step();
  const auto p = reference::positions_by_id(model.P());
  const auto eps = reference::values_by_id<Mixing::P_eps>(model.P());
  const auto sigma = reference::values_by_id<Mixing::P_sigma>(model.P());
  const auto f = reference::values_by_id<Mixing::P_f>(model.P());
  const double rc = model.params().rc;
  double worst = 0, scale = 0;
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    reference::Vec2 want{0, 0};
    for (std::size_t j = 0; j < p.size(); ++j) {
      reference::Vec2 d{p[j][0] - p[i][0], p[j][1] - p[i][1]};
      for (double& x : d) x -= std::round(x);  // unit periodic box
      const double r = reference::norm(d);
      if (!(r < rc && r > 0)) continue;
      ++pairs;
      const double e = std::sqrt(eps[i] * eps[j]), s = (sigma[i] + sigma[j]) / 2;
      const double sr6 = std::pow(s / r, 6);
      const double g = 24 * e * (sr6 - 2 * sr6 * sr6) / (r * r);
      for (int k = 0; k < 2; ++k) want[k] += g * d[k];
    }
    worst = std::max(worst, reference::norm({f[i][0] - want[0], f[i][1] - want[1]}));
    scale = std::max(scale, reference::norm(want));
  }
  REQUIRE(pairs > 10000);  // about 2000 * pi rc^2 * 2000 ordered pairs
  CHECK(worst <= 1e-12 * scale);
}
