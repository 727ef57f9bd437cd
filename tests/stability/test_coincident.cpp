// Coincident particles (tests/stability/coincident.part): ids 3k, 3k+1, 3k+2
// share a position, where dx / |dx| is 0 / 0. A condition |dx| > 0 (first or
// second in the `and`) or an if(|dx| > 0, ...) excludes those pairs, so no
// variable is NaN, and the sums equal brute force skipping coincident pairs.
#include <catch2/catch.hpp>

#include <cmath>

#include "brute.hpp"
#include "coincident.hpp"

TEST_CASE("dx / |dx| guarded by |dx| > 0 gives no NaN on coincident particles and "
          "matches brute force skipping them",
          "[stability][coincident]") {
  Coincident model;
  model.init();
  model.step();
  CHECK_NOTHROW(model.check_finite());
  const double rc = model.params().rc;
  const auto p = brute::positions_by_id<2>(model.P());
  using V = brute::Vec<2>;
  std::vector<V> f(p.size(), {0, 0}), g(p.size(), {0, 0}), u(p.size(), {0, 0});
  int coincident = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = 0; j < p.size(); ++j) {
      const V dx = brute::minimum_image<2>({p[j][0] - p[i][0], p[j][1] - p[i][1]}, 1.0);
      const double d = brute::norm(dx);
      if (d == 0 && i != j) ++coincident;
      if (!(d < rc)) continue;
      if (d == 0) {
        u[i][0] += 1;
        continue;
      }
      for (int k = 0; k < 2; ++k) {
        f[i][k] += -(rc - d) * dx[k] / d;
        g[i][k] += dx[k] / d * (1.0 + static_cast<double>(j));
        u[i][k] += dx[k] / d;
      }
    }
  REQUIRE(coincident == 600);  // 100 triples, 6 ordered pairs each
  const auto check = [&](const std::vector<V>& got, const std::vector<V>& want, double tol,
                         const char* name) {
    double worst = 0;
    for (std::size_t i = 0; i < got.size(); ++i)
      for (int k = 0; k < 2; ++k) {
        REQUIRE(std::isfinite(got[i][k]));
        worst = std::max(worst, std::abs(got[i][k] - want[i][k]));
      }
    INFO(name << ": largest error " << worst);
    CHECK(worst <= tol);
  };
  std::vector<V> got;
  for (const auto& v : brute::values_by_id<Coincident::P_f>(model.P())) got.push_back({v[0], v[1]});
  check(got, f, 1e-14, "f");
  got.clear();
  for (const auto& v : brute::values_by_id<Coincident::P_f_cells>(model.P())) got.push_back({v[0], v[1]});
  check(got, f, 1e-14, "f_cells");
  got.clear();
  for (const auto& v : brute::values_by_id<Coincident::P_f_brute>(model.P())) got.push_back({v[0], v[1]});
  check(got, f, 1e-14, "f_brute");
  got.clear();
  for (const auto& v : brute::values_by_id<Coincident::P_g>(model.P())) got.push_back({v[0], v[1]});
  check(got, g, 1e-11, "g");  // terms up to 300 in size
  got.clear();
  for (const auto& v : brute::values_by_id<Coincident::P_u>(model.P())) got.push_back({v[0], v[1]});
  check(got, u, 1e-13, "u");
}
