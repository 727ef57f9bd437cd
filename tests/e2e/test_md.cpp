// The seed's molecular-dynamics example (examples/md.part), compiled by
// partc, against the same equations written out by hand: an O(N^2) loop
// over all pairs and every periodic image of each within the cutoff (at
// N = 10 the cutoff sqrt(3/N) = 0.55 passes half the box, and a particle
// feels two images of some others), no search structure at all.
#include <catch2/catch.hpp>

#include "md.hpp"
#include "reference.hpp"

namespace {

using reference::Vec2;

struct BruteForceMd {
  std::vector<Vec2> p, v;
  double c, rc;

  // v += c * sum_j -exp(-|dx|) dx / |dx| over 0 < |dx| < rc; then p += v.
  void step() {
    const std::size_t n = p.size();
    std::vector<Vec2> force(n, Vec2{0, 0});
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n; ++j)
        for (int sx = -1; sx <= 1; ++sx)  // rc < 1: images one box away at most
          for (int sy = -1; sy <= 1; ++sy) {
            const Vec2 dx = {p[j][0] - p[i][0] + sx, p[j][1] - p[i][1] + sy};
            const double r = reference::norm(dx);
            if (r < rc && r > 0)
              for (int k = 0; k < 2; ++k) force[i][k] += -std::exp(-r) * dx[k] / r;
          }
    for (std::size_t i = 0; i < n; ++i)
      for (int k = 0; k < 2; ++k) {
        v[i][k] += c * force[i][k];
        p[i][k] += v[i][k];
        p[i][k] -= std::floor(p[i][k]);  // back into [0, 1)
      }
  }
};

void compare(const Md& model, const BruteForceMd& ref) {
  const auto p = reference::positions_by_id(model.P());
  const auto v = reference::values_by_id<Md::P_v>(model.P());
  REQUIRE(p.size() == ref.p.size());
  double v_scale = 0;
  for (const Vec2& x : ref.v) v_scale = std::max(v_scale, reference::norm(x));
  REQUIRE(v_scale > 0);  // the force acted: the comparison is not of zeros
  double worst_p = 0, worst_v = 0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const Vec2 dp = reference::minimum_image({p[k][0] - ref.p[k][0], p[k][1] - ref.p[k][1]});
    worst_p = std::max(worst_p, reference::norm(dp));
    worst_v = std::max(worst_v, reference::norm({v[k][0] - ref.v[k][0], v[k][1] - ref.v[k][1]}));
  }
  INFO("worst position error " << worst_p << ", worst velocity error " << worst_v << " of "
                               << v_scale);
  CHECK(worst_p <= 1e-9);
  CHECK(worst_v <= 1e-9 * v_scale);
}

}  // namespace

TEST_CASE("md.part agrees with a brute-force O(N^2) reference", "[e2e][md]") {
  // 1000 particles use the cell list; 50 and 10 fall back to brute force
  // (few particles, or fewer than 3 cells across the box).
  const std::int64_t n = GENERATE(1000, 50, 10);
  Md model;
  model.params().N = n;
  model.set_seed(2017);
  model.init();
  const auto p0 = reference::positions_by_id(model.P());
  REQUIRE(p0.size() == static_cast<std::size_t>(n));

  BruteForceMd ref{p0, std::vector<Vec2>(p0.size(), Vec2{0, 0}), model.params().c,
                   std::sqrt(3.0 / static_cast<double>(n))};
  for (int step = 0; step < 10; ++step) {
    model.step();
    ref.step();
  }
  INFO("N = " << n);
  compare(model, ref);
}

TEST_CASE("md.part is reproducible from its seed", "[e2e][md]") {
  auto run = [](std::uint64_t seed) {
    Md model;
    model.params().N = 300;
    model.set_seed(seed);
    model.init();
    for (int step = 0; step < 5; ++step) model.step();
    return reference::positions_by_id(model.P());
  };
  CHECK(run(1) == run(1));
  CHECK(run(1) != run(2));
}
