// A Plummer sphere (tests/stability/plummer.part): 4000 points with scale
// 0.02, rc = 0.01. Every search - cell list, k-d tree, brute force and the
// automatic choice - must give brute force's counts exactly and its sums of
// (rc - |dx|) dx / |dx| to 1e-14 (hundreds of terms below 0.01 that cancel
// in the core). The case must be hard for a cell list: the densest point has
// hundreds of neighbours while the median has a few, and the automatic
// choice takes the k-d tree.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "brute.hpp"
#include "plummer.hpp"

TEST_CASE("a Plummer sphere of 4000 points: cell list, k-d tree, brute force and the "
          "automatic choice as brute force",
          "[stability][cluster][plummer]") {
  Plummer model;
  model.set_seed(3);
  model.init();
  model.step();
  model.check_finite();
  const double rc = model.params().rc;
  const auto p = brute::positions_by_id<3>(model.P());
  const std::size_t N = p.size();
  std::vector<std::int64_t> n(N, 0);
  std::vector<brute::Vec<3>> f(N, {0, 0, 0});
  int outside = 0;
  for (std::size_t i = 0; i < N; ++i) {
    outside += std::abs(p[i][0]) > 1 || std::abs(p[i][1]) > 1 || std::abs(p[i][2]) > 1;
    for (std::size_t j = 0; j < N; ++j) {
      const brute::Vec<3> dx{p[j][0] - p[i][0], p[j][1] - p[i][1], p[j][2] - p[i][2]};
      const double d = brute::norm(dx);
      if (!(d < rc)) continue;
      ++n[i];
      if (d > 0)
        for (int k = 0; k < 3; ++k) f[i][k] += (rc - d) * dx[k] / d;
    }
  }
  std::vector<std::int64_t> sorted = n;
  std::sort(sorted.begin(), sorted.end());
  INFO("neighbours: median " << sorted[N / 2] << ", max " << sorted.back() << "; " << outside
                             << " points outside the box");
  CHECK(sorted.back() > 300);
  CHECK(sorted[N / 2] < sorted.back() / 5);
  CHECK(outside > 0);
  CHECK(brute::values_by_id<Plummer::P_n_cells>(model.P()) == n);
  CHECK(brute::values_by_id<Plummer::P_n_tree>(model.P()) == n);
  CHECK(brute::values_by_id<Plummer::P_n_brute>(model.P()) == n);
  CHECK(brute::values_by_id<Plummer::P_n_auto>(model.P()) == n);
  for (const auto& got : {brute::values_by_id<Plummer::P_f_cells>(model.P()),
                          brute::values_by_id<Plummer::P_f_tree>(model.P()),
                          brute::values_by_id<Plummer::P_f_auto>(model.P())}) {
    double worst = 0;
    for (std::size_t i = 0; i < N; ++i)
      for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(got[i][k] - f[i][k]));
    INFO("largest force difference " << worst);
    CHECK(worst <= 1e-14);
  }
  bool tree_chosen = false;
  for (const auto& r : model.search_report()) {
    INFO(r.serves << ": " << r.structure);
    if (r.serves == "sums over P") tree_chosen = r.structure == "k-d tree";
  }
  CHECK(tree_chosen);
}
