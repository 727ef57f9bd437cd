// A cutoff larger than half the box (tests/stability/big_cutoff.part): as the
// README says, every periodic image of j within rc counts, and i's own
// images too. Against an enumeration of the images written here: rc = 0.7
// (images of other particles up to 1.4 box lengths in each direction) and
// rc = 1.2 (each particle's own 4 nearest images, at distance 1, count).
#include <catch2/catch.hpp>

#include <cmath>

#include "big_cutoff.hpp"
#include "brute.hpp"

namespace {

void check_images(double rc) {
  BigCutoff model;
  model.params().rc = rc;
  model.set_seed(21);
  model.init();
  model.step();
  model.check_finite();
  const auto p = brute::positions_by_id<2>(model.P());
  std::vector<std::int64_t> n(p.size(), 0), own(p.size(), 0);
  std::vector<double> w(p.size(), 0);
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = 0; j < p.size(); ++j)
      for (int a = -3; a <= 3; ++a)
        for (int b = -3; b <= 3; ++b) {
          const double dx = p[j][0] + a - p[i][0], dy = p[j][1] + b - p[i][1];
          const double d = std::sqrt(dx * dx + dy * dy);
          if (d < rc && d > 0) ++n[i];
          if (d < rc && d > 0 && i == j) ++own[i];
          if (d < rc) w[i] += rc - d;
        }
  INFO("rc = " << rc);
  CHECK(brute::values_by_id<BigCutoff::P_n>(model.P()) == n);
  CHECK(brute::values_by_id<BigCutoff::P_n_cells>(model.P()) == n);
  const auto ws = brute::values_by_id<BigCutoff::P_w>(model.P());
  double worst = 0;
  for (std::size_t i = 0; i < p.size(); ++i) worst = std::max(worst, std::abs(ws[i] - w[i]) / w[i]);
  CHECK(worst <= 1e-13);
  // More neighbours than particles: the images count.
  CHECK(n[0] > static_cast<std::int64_t>(p.size()));
  CHECK(own[0] == (rc > 1 ? 4 : 0));
}

}  // namespace

TEST_CASE("a cutoff of 0.7 in a unit periodic box counts every image within it",
          "[stability][images]") {
  check_images(0.7);
}

TEST_CASE("a cutoff of 1.2 in a unit periodic box also counts a particle's own images",
          "[stability][images]") {
  check_images(1.2);
}
