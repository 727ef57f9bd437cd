// Points with many equal coordinates (tests/stability/ties.part): all on one
// plane, three rows, 40 of them coincident. The k-d tree, the cell list, brute
// force and the automatic choice must count |dx| <= rc exactly as brute force
// does here, and the sums of (rc - |dx|) dx match it to 1e-16 absolute (terms
// below rc^2 = 4e-4, rounded in a different order).
#include <catch2/catch.hpp>

#include <cmath>

#include "brute.hpp"
#include "ties.hpp"

TEST_CASE("points on one plane, in three rows, 40 coincident: every search counts and sums "
          "as brute force",
          "[stability][ties]") {
  Ties model;
  model.init();
  model.step();
  model.check_finite();
  const double rc = model.params().rc;
  const auto p = brute::positions_by_id<3>(model.P());
  const std::size_t N = p.size();
  std::vector<std::int64_t> n(N, 0);
  std::vector<brute::Vec<3>> s(N, {0, 0, 0});
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t j = 0; j < N; ++j) {
      const brute::Vec<3> dx{p[j][0] - p[i][0], p[j][1] - p[i][1], p[j][2] - p[i][2]};
      const double d = brute::norm(dx);
      if (!(d <= rc)) continue;
      ++n[i];
      for (int k = 0; k < 3; ++k) s[i][k] += (rc - d) * dx[k];
    }
  CHECK(n[0] >= 40);  // the coincident ones, and the row points near them
  for (std::size_t i = 0; i < N; ++i) CHECK(p[i][0] == 0.5);
  CHECK(brute::values_by_id<Ties::P_n_cells>(model.P()) == n);
  CHECK(brute::values_by_id<Ties::P_n_tree>(model.P()) == n);
  CHECK(brute::values_by_id<Ties::P_n_brute>(model.P()) == n);
  CHECK(brute::values_by_id<Ties::P_n_auto>(model.P()) == n);
  for (const auto& got : {brute::values_by_id<Ties::P_s_tree>(model.P()),
                          brute::values_by_id<Ties::P_s_cells>(model.P())}) {
    double worst = 0;
    for (std::size_t i = 0; i < N; ++i)
      for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(got[i][k] - s[i][k]));
    INFO("largest difference " << worst);
    CHECK(worst <= 1e-16);
  }
}
