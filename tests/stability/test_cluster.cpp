// Every particle in one cell (tests/stability/cluster.part): 200 particles
// within 1e-3 in a unit box with rc = 0.1. The cell list puts them all in
// one cell, the k-d tree in one leaf region; each sum must still equal brute
// force over all pairs.
#include <catch2/catch.hpp>

#include <cmath>

#include "brute.hpp"
#include "cluster.hpp"

TEST_CASE("200 particles within 1e-3 (all in one cell) sum as brute force does",
          "[stability][cluster]") {
  Cluster model;
  model.set_seed(9);
  model.init();
  model.step();
  model.check_finite();
  const double rc = model.params().rc;
  const auto p = brute::positions_by_id<2>(model.P());
  REQUIRE(p.size() == 200);
  std::vector<double> s(p.size(), 0);
  std::vector<int> n(p.size(), 0);
  std::vector<brute::Vec<2>> f(p.size(), {0, 0});
  double spread = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = 0; j < p.size(); ++j) {
      const brute::Vec<2> dx = brute::minimum_image<2>({p[j][0] - p[i][0], p[j][1] - p[i][1]}, 1.0);
      const double d = brute::norm(dx);
      spread = std::max(spread, d);
      if (d < rc) ++n[i];
      if (d < rc && d > 0) {
        s[i] += (rc - d) * (1.0 + static_cast<double>(j));  // ids are 0..N-1 in this order
        for (int k = 0; k < 2; ++k) f[i][k] += -(rc - d) * dx[k] / d;
      }
    }
  REQUIRE(spread < 1.5e-3);
  const auto cells = brute::values_by_id<Cluster::P_s_cells>(model.P());
  const auto tree = brute::values_by_id<Cluster::P_s_tree>(model.P());
  const auto automatic = brute::values_by_id<Cluster::P_s_auto>(model.P());
  const auto count = brute::values_by_id<Cluster::P_n_cells>(model.P());
  const auto force = brute::values_by_id<Cluster::P_f_cells>(model.P());
  double worst = 0, worst_f = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    CHECK(count[i] == n[i]);
    for (double v : {cells[i], tree[i], automatic[i]}) worst = std::max(worst, std::abs(v - s[i]) / s[i]);
    for (int k = 0; k < 2; ++k) worst_f = std::max(worst_f, std::abs(force[i][k] - f[i][k]));
  }
  CHECK(count[0] == 200);
  INFO("relative error of the sums " << worst << ", force error " << worst_f);
  CHECK(worst <= 1e-13);  // 199 positive terms
  CHECK(worst_f <= 1e-12);  // 199 unit vectors times 0.1, cancelling to O(1e-1)
}
