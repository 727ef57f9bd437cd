// The conditional and the built-in functions (tests/e2e/builtins.part)
// against the same formulas written out here: floored mod and division as
// Python defines them, the minimum image from reference.hpp, and
// brute-force neighbour sums.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>

#include "builtins.hpp"
#include "reference.hpp"

namespace {

// Python's a % b and a // b for b > 0.
std::int64_t floored_mod(std::int64_t a, std::int64_t b) { return ((a % b) + b) % b; }
std::int64_t floored_div(std::int64_t a, std::int64_t b) {
  return static_cast<std::int64_t>(std::floor(static_cast<double>(a) / static_cast<double>(b)));
}
double sign(double x) { return x > 0 ? 1 : x < 0 ? -1 : 0; }

}  // namespace

TEST_CASE("if() and the built-ins give what the formulas say", "[e2e][builtins]") {
  Builtins model;
  model.set_seed(5);
  model.init();
  const auto x = reference::positions_by_id(model.P());
  model.step();
  const auto k = reference::values_by_id<Builtins::P_k>(model.P());
  const auto g = reference::values_by_id<Builtins::P_g>(model.P());
  const auto c = reference::values_by_id<Builtins::P_c>(model.P());
  const auto w = reference::values_by_id<Builtins::P_w>(model.P());
  const auto s = reference::values_by_id<Builtins::P_s>(model.P());
  const auto u = reference::values_by_id<Builtins::P_u>(model.P());
  const auto torque = reference::values_by_id<Builtins::P_torque>(model.P());
  const double rc = model.params().rc;
  const std::size_t n = x.size();
  REQUIRE(n == 300);

  int negative_quotients = 0, with_neighbours = 0;
  for (std::size_t a = 0; a < n; ++a) {
    INFO("particle id " << a);
    const auto id = static_cast<std::int64_t>(a);
    CHECK(k[a] == floored_mod(id - 7, 5) * 1000 + floored_div(id - 150, 7));
    negative_quotients += id < 150;
    CHECK(g[a] == (x[a][0] > 0.5 ? 1 / (x[a][0] - 0.5) : -1.0));
    const double angle = std::atan2(x[a][1] - 0.5, x[a][0] - 0.5) / M_PI;
    CHECK(c[a] == std::min(std::max(angle, -0.5), 0.75));
    const reference::Vec2 w_expected =
        x[a][1] > 0.5 ? reference::Vec2{1, 0} : reference::Vec2{0, std::round(x[a][0] * 4)};
    CHECK(w[a][0] == w_expected[0]);
    CHECK(w[a][1] == w_expected[1]);

    double s_expected = 0, torque_expected = 0;
    reference::Vec2 u_expected{0, 0};
    for (std::size_t b = 0; b < n; ++b) {
      const reference::Vec2 d = reference::minimum_image({x[b][0] - x[a][0], x[b][1] - x[a][1]});
      const double r = reference::norm(d);
      if (r >= rc) continue;
      if (r > 0) s_expected += (d[0] > 0 ? 1 : -1) * std::tanh(r / rc) * sign(d[1]);
      const double scale = r < rc / 2 ? 1.0 : -2.0;
      u_expected[0] += scale * d[0];
      u_expected[1] += scale * d[1];
      torque_expected += d[0] * 2 - d[1] * 1;
    }
    with_neighbours += s_expected != 0;
    CHECK(s[a] == Approx(s_expected).margin(1e-12));
    CHECK(u[a][0] == Approx(u_expected[0]).margin(1e-12));
    CHECK(u[a][1] == Approx(u_expected[1]).margin(1e-12));
    CHECK(torque[a] == Approx(torque_expected).margin(1e-12));
  }
  CHECK(negative_quotients == 150);
  CHECK(with_neighbours > 250);  // the sums are not trivially zero
}
