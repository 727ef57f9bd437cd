// A sparse solve (tests/e2e/screened_diffusion.part, CG on CRS) against the
// same system assembled here by brute force over all pairs, with the
// minimum image written out in reference.hpp, and solved by dense LU.
#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include "reference.hpp"
#include "screened_diffusion.hpp"

TEST_CASE("a sparse solve by CG matches a dense solve of the brute-force system",
          "[e2e][solve]") {
  ScreenedDiffusion model;
  model.set_seed(9);
  model.init();
  const auto x = reference::positions_by_id(model.P());
  const auto f = reference::values_by_id<ScreenedDiffusion::P_f>(model.P());
  const auto w = reference::values_by_id<ScreenedDiffusion::P_w>(model.P());
  const double h = model.params().h, k = model.params().k;
  const auto n = static_cast<Eigen::Index>(x.size());
  Eigen::MatrixXd A = Eigen::MatrixXd::Identity(n, n);
  Eigen::VectorXd b(n);
  std::size_t pairs = 0;
  for (Eigen::Index a = 0; a < n; ++a) {
    b[a] = f[a];
    for (Eigen::Index c = 0; c < n; ++c) {
      const double r = reference::norm(reference::minimum_image({x[c][0] - x[a][0], x[c][1] - x[a][1]}));
      if (r < h && r > 0) {
        A(a, a) += k;
        A(a, c) -= k;
        ++pairs;
      }
    }
  }
  REQUIRE(pairs > 10 * x.size());  // a real neighbourhood, not a diagonal system
  const Eigen::VectorXd expected = A.lu().solve(b);
  for (Eigen::Index a = 0; a < n; ++a) {
    INFO("particle id " << a);
    CHECK(w[a] == Approx(expected[a]).margin(1e-9));
  }
  const std::vector<std::string> report = model.solve_report();
  REQUIRE(!report.empty());
  CHECK_THAT(report.front(), Catch::StartsWith("solve w: CG"));
}
