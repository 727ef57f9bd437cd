// The 3D wrap (tests/stability/wrap3d.part), in [-1, 1) x [0, 1) x [2, 3):
// every position must be its written value wrapped exactly along each axis,
// lo + (x - lo) - L floor((x - lo) / L) in long double (exact for these
// values) and hi mapped to lo, after init and after each move; the counts
// of |dx| <= rc by cell list, k-d tree and brute force, and the cell list's
// sum of dx, must equal brute force with minimum images (many particles sit
// at exactly rc = 1/4 of each other, across the faces too).
#include <catch2/catch.hpp>

#include <cmath>

#include "brute.hpp"
#include "wrap3d.hpp"

namespace {

constexpr double lo[3] = {-1, 0, 2}, hi[3] = {1, 1, 3};

double reference_wrap(double x, int k) {
  const long double L = hi[k] - lo[k], t = static_cast<long double>(x) - lo[k];
  const double d = static_cast<double>(lo[k] + (t - L * std::floor(t / L)));
  return d == hi[k] ? lo[k] : d;
}

double written(int digit, int k) {
  const double a = lo[k], b = hi[k];
  const double values[] = {a, b, a - 1e-300, -0.0, b + 3.25 * (b - a), a - 0.5 * (b - a)};
  return values[digit];
}

}  // namespace

TEST_CASE("3D: positions on hi, a hair below lo, at -0.0 and boxes away wrap exactly on "
          "every axis, and every search matches brute force",
          "[stability][periodic][wrap]") {
  Wrap3d model;
  model.init();
  std::vector<brute::Vec<3>> x(216);
  for (int id = 0; id < 216; ++id)
    for (int k = 0; k < 3; ++k) {
      const int digit = k == 0 ? id % 6 : k == 1 ? (id / 6) % 6 : id / 36;
      x[id][k] = reference_wrap(written(digit, k), k);
    }
  // By hand for a few: hi -> lo, lo - 1e-300 -> lo, -0.0 in z (two boxes below lo) -> 2.
  CHECK(x[1][0] == -1.0);
  CHECK(x[2][0] == -1.0);
  CHECK(x[3 * 36][2] == 2.0);
  CHECK(x[4][0] == -0.5);  // 1 + 6.5 wraps to -0.5
  const double moves[][3] = {{0, 0, 0}, {2, -1, 3}, {-0.5, 0.25, -0.75}, {1e3, -1e3 + 0.5, 0.125}};
  for (const auto& m : moves) {
    INFO("move (" << m[0] << ", " << m[1] << ", " << m[2] << ")");
    model.params().mx = m[0];
    model.params().my = m[1];
    model.params().mz = m[2];
    model.step();
    const auto p = brute::positions_by_id<3>(model.P());
    for (int id = 0; id < 216; ++id)
      for (int k = 0; k < 3; ++k) {
        x[id][k] = reference_wrap(x[id][k] + m[k], k);
        INFO("particle " << id << " axis " << k);
        REQUIRE(p[id][k] == x[id][k]);
      }
    const double rc = model.params().rc;
    std::vector<std::int64_t> n(216, 0);
    std::vector<brute::Vec<3>> s(216, {0, 0, 0});
    int at_rc = 0;
    for (int i = 0; i < 216; ++i)
      for (int j = 0; j < 216; ++j) {
        brute::Vec<3> dx;
        for (int k = 0; k < 3; ++k) {
          const double L = hi[k] - lo[k];
          dx[k] = p[j][k] - p[i][k];
          dx[k] -= L * std::round(dx[k] / L);
        }
        const double d = brute::norm(dx);
        at_rc += d == rc;
        if (d <= rc) {
          ++n[i];
          for (int k = 0; k < 3; ++k) s[i][k] += dx[k];
        }
      }
    CHECK(at_rc > 0);
    CHECK(brute::values_by_id<Wrap3d::P_n_cells>(model.P()) == n);
    CHECK(brute::values_by_id<Wrap3d::P_n_tree>(model.P()) == n);
    CHECK(brute::values_by_id<Wrap3d::P_n_brute>(model.P()) == n);
    const auto sc = brute::values_by_id<Wrap3d::P_s_cells>(model.P());
    double worst = 0;
    for (int i = 0; i < 216; ++i)
      for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(sc[i][k] - s[i][k]));
    CHECK(worst <= 1e-14);  // dyadic terms of size <= 1/4: exact but for order
  }
}
