// Neighbourhood sums whose big terms cancel exactly (tests/stability/
// cancellation.part). Reference: the +-1e16 (1 + k mod 7) terms come in
// coincident pairs, so they cancel exactly in every neighbourhood (checked
// here in integers); the exact sum is then the sum of the small terms, taken
// here in long double. Neumaier's summation is accurate to
// 2 u |s| + 3 n u^2 sum |x| (u = 2^-53, n terms): with sum |x| ~ 1e18 that is
// ~1e-13 absolute, which every compensated sum, by every search, must meet.
// Plain summation must visibly fail (that is what makes the case hard).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>

#include "brute.hpp"
#include "cancellation.hpp"

TEST_CASE("neighbourhood sums of +-1e16 terms that cancel exactly and small ones between: "
          "compensated summation keeps the small ones, with any search",
          "[stability][summation]") {
  Cancellation model;
  model.init();
  model.step();
  model.check_finite();
  const double rc = model.params().rc;
  const auto p = brute::positions_by_id<2>(model.P());
  const auto w = brute::values_by_id<Cancellation::P_w>(model.P());
  const std::size_t N = p.size();
  const double u = std::ldexp(1.0, -53);
  const auto plain = brute::values_by_id<Cancellation::P_plain>(model.P());
  const auto kept = brute::values_by_id<Cancellation::P_kept>(model.P());
  const auto cells = brute::values_by_id<Cancellation::P_kept_cells>(model.P());
  const auto tree = brute::values_by_id<Cancellation::P_kept_tree>(model.P());
  int plain_wrong = 0, with_big = 0;
  double worst = 0;
  for (std::size_t i = 0; i < N; ++i) {
    std::int64_t big = 0;
    long double small = 0, magnitude = 0;
    int terms = 0;
    for (std::size_t j = 0; j < N; ++j) {
      const double d = brute::norm(brute::minimum_image<2>({p[j][0] - p[i][0], p[j][1] - p[i][1]}, 1.0));
      if (!(d < rc)) continue;
      ++terms;
      magnitude += std::abs(w[j]);
      if (std::abs(w[j]) >= 1e16)
        big += static_cast<std::int64_t>(w[j] / 1e16);
      else
        small += w[j];
    }
    REQUIRE(big == 0);
    with_big += magnitude > 1e16L;
    const double exact = static_cast<double>(small);
    const double bound = 2 * u * std::abs(exact) + 3 * terms * u * u * static_cast<double>(magnitude);
    for (double got : {kept[i], cells[i], tree[i]}) {
      worst = std::max(worst, std::abs(got - exact));
      CHECK(std::abs(got - exact) <= bound);
    }
    plain_wrong += std::abs(plain[i] - exact) > 1e-3;
  }
  INFO(with_big << " of " << N << " neighbourhoods hold big terms; plain summation is off in "
                << plain_wrong << "; largest compensated error " << worst);
  CHECK(with_big > static_cast<int>(N) / 2);
  CHECK(plain_wrong > static_cast<int>(N) / 4);
}
