// Positions on and just beyond the faces of a periodic line [0, 1)
// (tests/stability/wrap1d.part). After init, each position must be the
// written value wrapped exactly, as listed below (hi and anything that rounds
// to hi comes out as lo; -0.0 and denormals inside the box stay). After each
// move by t box lengths plus a shift, the position must be fl(x + t + shift)
// wrapped by x - floor(x) in long double (exact), hi again mapped to lo: no
// other rounding is allowed. The counts of |dx| <= rc (cell list, brute force)
// and the sum of dx over them must equal brute force with minimum images; the
// lattice points 0, 1/4, 1/2, 3/4 are exactly rc apart, across the face too.
#include <catch2/catch.hpp>

#include <cmath>

#include "brute.hpp"
#include "wrap1d.hpp"

namespace {

double reference_wrap(double x) {
  const long double y = static_cast<long double>(x) - std::floor(static_cast<long double>(x));
  const double d = static_cast<double>(y);
  return d == 1.0 ? 0.0 : d;
}

void check_against_brute(const Wrap1d& model) {
  const auto p = brute::positions_by_id<1>(model.P());
  const double rc = model.params().rc;
  std::vector<std::int64_t> n(p.size(), 0);
  std::vector<double> s(p.size(), 0);
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = 0; j < p.size(); ++j) {
      const double dx = brute::minimum_image<1>({p[j][0] - p[i][0]}, 1.0)[0];
      if (std::abs(dx) <= rc) {
        ++n[i];
        s[i] += dx;
      }
    }
  CHECK(brute::values_by_id<Wrap1d::P_n_cells>(model.P()) == n);
  CHECK(brute::values_by_id<Wrap1d::P_n_brute>(model.P()) == n);
  const auto sc = brute::values_by_id<Wrap1d::P_s_cells>(model.P());
  for (std::size_t i = 0; i < p.size(); ++i) CHECK(std::abs(sc[i][0] - s[i]) <= 1e-15);  // <= 17 terms of size <= 1/4
}

}  // namespace

TEST_CASE("1D: positions at hi, below lo by less than an ulp of hi, -0.0, denormals and "
          "many box lengths away wrap exactly into [lo, hi)",
          "[stability][periodic][wrap]") {
  Wrap1d model;
  model.init();
  const double u = std::ldexp(1.0, -53);
  const std::vector<double> written_wrapped = {
      0.0, 0.0 /* hi */, 0.0 /* -0.0 */, 1 - u, 0.0 /* 1 - 1e-300 rounds to hi */,
      0.0 /* 1 - 2^-54 rounds to hi */, 2 * u, 0.0, 0.0, 1e-310, 0.0 /* 1 - 1e-310 */, 0.5, 0.25,
      0.75, 0.0 /* 2^53 */, 1 - u /* -2^-53 + 1 is exact */, 0.75};
  const auto p = brute::positions_by_id<1>(model.P());
  REQUIRE(p.size() == written_wrapped.size());
  for (std::size_t k = 0; k < p.size(); ++k) {
    INFO("particle " << k << " at " << p[k][0]);
    CHECK(p[k][0] == written_wrapped[k]);
    CHECK(p[k][0] >= 0.0);
    CHECK(p[k][0] < 1.0);
  }
  CHECK(p[9][0] > 0);  // the denormal is kept, not flushed
  // The reference wrap agrees with the table on the written values.
  const double written[] = {0.0, 1.0, -0.0, 1 - u, -1e-300, -u / 2, 1 + 2 * u, 5.0, -3.0, 1e-310,
                            -1e-310, 0.5, 7.25, -7.25, 1 / u, -u, 0.75};  // x0 in the model
  for (std::size_t k = 0; k < p.size(); ++k) CHECK(reference_wrap(written[k]) == written_wrapped[k]);

  std::vector<double> x(p.size());
  for (std::size_t k = 0; k < p.size(); ++k) x[k] = p[k][0];
  const std::pair<double, double> moves[] = {{0, 0}, {3, 0}, {-5, 0}, {0, 0.5}, {-1, -0.25}, {1e6, 0.125}};
  for (const auto& [turns, shift] : moves) {
    INFO("move by " << turns << " box lengths + " << shift);
    model.params().turns = turns;
    model.params().shift = shift;
    model.step();
    const auto q = brute::positions_by_id<1>(model.P());
    for (std::size_t k = 0; k < q.size(); ++k) {
      x[k] = reference_wrap(x[k] + (turns + shift));
      INFO("particle " << k);
      CHECK(q[k][0] == x[k]);
    }
    check_against_brute(model);
  }
}
