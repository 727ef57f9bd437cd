// Pairs at exactly the cutoff (tests/stability/boundary.part).
// - A lattice of spacing 1/4 in a periodic box [0, 4)^3, rc = 3/4: every
//   distance is exact, 30 lattice directions ((3,0,0) and (2,2,1), with signs
//   and permutations) lie exactly at rc, most of them off the axes. The
//   reference counts in integers: lattice coordinates, integer minimum image,
//   squared length compared with 9. No tolerance: |dx| <= rc must count
//   exactly those with 9, |dx| < rc exclude them, for the cell list, the k-d
//   tree, brute force, Verlet lists (reused between rebuilds as the lattice
//   shifts by (1, -2, 3)/64 a step) and dot(dx, dx) <= rc * rc.
// - Verlet lists' worst case: two particles rc + skin apart, each moving
//   exactly skin / 2 towards the other. The list built at distance rc + skin
//   is not rebuilt (no particle moved more than skin / 2), and must still
//   report the pair at distance rc.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>

#include "boundary.hpp"
#include "brute.hpp"

namespace {

using Site = std::array<int, 3>;

Site site_of(std::int64_t id) {
  const int s = static_cast<int>((id * 7919) % 4096);
  return {s % 16, (s / 16) % 16, s / 256};
}

int minimum_image(int d) {  // the lattice has 16 sites a side
  d = ((d % 16) + 16) % 16;
  return d > 8 ? d - 16 : d;
}

}  // namespace

TEST_CASE("lattice neighbours at exactly rc, on and off the axes: <= includes them and < "
          "excludes them, by every search and by Verlet lists",
          "[stability][boundary]") {
  Boundary model;
  model.init();
  const int N = static_cast<int>(model.params().N);
  std::vector<std::int64_t> le(N, 0), lt(N, 0);
  int at_rc = 0;
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) {
      const Site a = site_of(i), b = site_of(j);
      int d2 = 0;
      for (int k = 0; k < 3; ++k) d2 += minimum_image(b[k] - a[k]) * minimum_image(b[k] - a[k]);
      le[i] += d2 > 0 && d2 <= 9;
      lt[i] += d2 > 0 && d2 < 9;
      at_rc += d2 == 9;
    }
  REQUIRE(at_rc > 5 * N);  // about 30 * N * N / 4096 = 11 per particle
  std::array<double, 3> shift{0, 0, 0};
  for (int step = 0; step < 12; ++step) {
    INFO("step " << step);
    // Where the lattice is now: sites times 1/4 plus the shifts so far, wrapped; exact.
    const auto p = brute::positions_by_id<3>(model.L());
    const auto q = brute::positions_by_id<3>(model.V());
    for (int i = 0; i < N; ++i)
      for (int k = 0; k < 3; ++k) {
        const double want = std::fmod(site_of(i)[k] * 0.25 + shift[k] + 8.0, 4.0);
        REQUIRE(p[i][k] == want);
        REQUIRE(q[i][k] == want);
      }
    model.step();
    CHECK(brute::values_by_id<Boundary::L_le_cells>(model.L()) == le);
    CHECK(brute::values_by_id<Boundary::L_le_tree>(model.L()) == le);
    CHECK(brute::values_by_id<Boundary::L_le_brute>(model.L()) == le);
    CHECK(brute::values_by_id<Boundary::V_le_lists>(model.V()) == le);
    CHECK(brute::values_by_id<Boundary::L_le_squared>(model.L()) == le);
    CHECK(brute::values_by_id<Boundary::L_lt_cells>(model.L()) == lt);
    CHECK(brute::values_by_id<Boundary::L_lt_tree>(model.L()) == lt);
    CHECK(brute::values_by_id<Boundary::V_lt_lists>(model.V()) == lt);
    shift = {shift[0] + 1.0 / 64, shift[1] - 2.0 / 64, shift[2] + 3.0 / 64};
  }
  // 12 shifts of |(1, -2, 3)| / 64 = 0.058: the lists were reused, then rebuilt.
  for (const auto& r : model.search_report())
    if (r.serves.rfind("by_lists", 0) == 0 || r.serves.rfind("strict_lists", 0) == 0) {
      INFO(r.serves << ": " << r.structure << ", " << r.builds << " builds");
      CHECK(r.builds >= 2);
      CHECK(r.builds <= 6);
    }
}

TEST_CASE("Verlet lists' worst case: two particles rc + skin apart each move exactly half "
          "the skin towards the other, and the unrebuilt list still has the pair at rc",
          "[stability][boundary][verlet]") {
  Boundary model;
  model.params().N = 0;
  model.init();
  const auto lists_builds = [&] {
    for (const auto& r : model.search_report())
      if (r.serves.rfind("approach", 0) == 0) return r.builds;
    FAIL("no report for the approach statement's lists");
    return std::size_t{0};
  };
  // Step 1 builds at distance 1 = rc + skin (nothing within rc), then each moves 1/8.
  model.step();
  CHECK(brute::values_by_id<Boundary::W_near>(model.W()) == std::vector<std::int64_t>{0, 0});
  CHECK(brute::values_by_id<Boundary::W_gap>(model.W()) == std::vector<double>{1.0, 1.0});
  CHECK(lists_builds() == 1);
  // Step 2: displacement exactly skin / 2, so no rebuild; the pair is at rc exactly.
  model.step();
  CHECK(brute::values_by_id<Boundary::W_gap>(model.W()) == std::vector<double>{0.75, 0.75});
  CHECK(lists_builds() == 1);
  CHECK(brute::values_by_id<Boundary::W_near>(model.W()) == std::vector<std::int64_t>{1, 1});
  // Step 3: now each has moved a whole skin / 2 more: rebuilt, and at 0.5 still near.
  model.step();
  CHECK(lists_builds() == 2);
  CHECK(brute::values_by_id<Boundary::W_gap>(model.W()) == std::vector<double>{0.5, 0.5});
  CHECK(brute::values_by_id<Boundary::W_near>(model.W()) == std::vector<std::int64_t>{1, 1});
}
