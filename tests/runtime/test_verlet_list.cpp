// VerletList against the O(N^2) reference of search_cases.hpp over the current
// positions, step after step of motion: the same j for every i, each once, with
// the same dx; and its rebuild rule, probed just under and just over half the
// skin, with the worst case of two particles approaching each other.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>
#include <utility>
#include <stdexcept>
#include <vector>

#include "search_cases.hpp"
#include "partc/domain.hpp"
#include "partc/parallel.hpp"
#include "partc/particle_set.hpp"
#include "partc/search/verlet_list.hpp"
#include "partc/vec.hpp"

using partc::Domain;
using partc::Vec;
using partc::VerletList;
using namespace search_cases;  // disagreements, check_no_errors, make_domain, Dim

namespace {

template <int D>
using Set = partc::ParticleSet<D>;

template <int D>
Domain<D> unit_box(bool periodic) {
  Domain<D> d{};
  for (int k = 0; k < D; ++k) {
    d.lo[k] = 0.0;
    d.hi[k] = 1.0;
    d.periodic[k] = periodic;
  }
  return d;
}

template <int D>
std::size_t index_of_id(const Set<D>& set, std::int64_t id) {
  const auto& ids = set.ids();
  return static_cast<std::size_t>(std::find(ids.begin(), ids.end(), id) - ids.begin());
}

// The j reported for particle i, as ids.
template <int D>
std::vector<std::int64_t> near_ids(const VerletList<D>& list, const Set<D>& set, std::size_t i) {
  std::vector<std::int64_t> ids;
  list.for_each_near(i, [&](std::size_t j, const Vec<D>&) { ids.push_back(set.ids()[j]); });
  std::sort(ids.begin(), ids.end());
  return ids;
}

template <int D>
Set<D> random_set(const Domain<D>& domain, std::size_t n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Set<D> set;
  for (std::size_t i = 0; i < n; ++i) {
    Vec<D> p;
    for (int k = 0; k < D; ++k) p[k] = domain.lo[k] + (domain.hi[k] - domain.lo[k]) * unit(rng);
    set.push_back(domain.wrap(p));  // lo + L * u can round up to hi
  }
  return set;
}

// Every particle's query against the reference over the set as it is now.
template <int D>
void check_exact(const VerletList<D>& list, const Domain<D>& domain, double radius,
                 const Set<D>& set) {
  check_no_errors("VerletList",
                  disagreements(domain, radius, set.positions(), set.positions(),
                                [&](std::size_t i, const auto& report) {
                                  list.for_each_near(i, report);
                                }));
}

// Half lists: each call of for_each_pair seen from both of its particles must
// give exactly the reference's neighbours, and the calls must follow the
// contract: one self call (dx = 0) per particle, other pairs from the lower index.
template <int D>
void check_half_exact(const VerletList<D>& list, const Domain<D>& domain, double radius,
                      const Set<D>& set) {
  const std::size_t n = set.size();
  std::vector<std::vector<std::pair<std::size_t, Vec<D>>>> near(n);
  std::vector<int> self_calls(n, 0);
  std::size_t bad_order = 0;
  list.for_each_pair([&](std::size_t i, const auto& pairs) {
    pairs([&](std::size_t j, const Vec<D>& dx) {
      if (i == j) {
        ++self_calls[i];
        bad_order += dx != Vec<D>::zero();
      } else {
        bad_order += !(i < j);
        near[j].push_back({i, Vec<D>::zero() - dx});
      }
      near[i].push_back({j, dx});
    });
  });
  CHECK(bad_order == 0);
  CHECK(std::count(self_calls.begin(), self_calls.end(), 1) == static_cast<std::ptrdiff_t>(n));
  check_no_errors("VerletList (half)",
                  disagreements(domain, radius, set.positions(), set.positions(),
                                [&](std::size_t i, const auto& report) {
                                  for (const auto& [j, dx] : near[i]) report(j, dx);
                                }));
}

}  // namespace

#define PARTC_VERLET_DIMS Dim<1>, Dim<2>, Dim<3>

TEMPLATE_TEST_CASE("half lists give every pair once, over many steps of random motion", "[verlet]",
                   PARTC_VERLET_DIMS) {
  constexpr int D = TestType::value;
  // As the full-list test below, plus a set large enough for several slabs.
  const std::pair<std::size_t, double> cases[] = {{400, 0.15}, {60, 0.7}, {60, 0.95}, {30, 3.0}};
  std::uint64_t seed = 300 * D;
  for (Periodicity periodicity : all_periodicities) {
    for (const auto& [n, radius] : cases) {
      if (periodicity != Periodicity::none && radius > 1.0) continue;  // refused: see below
      const double skin = 0.1;
      INFO(periodicity_name(periodicity) << ", D = " << D << ", N = " << n << ", radius "
                                         << radius);
      const Domain<D> domain = make_domain<D>(periodicity, false);
      std::mt19937_64 rng(++seed);
      Set<D> set = random_set(domain, n, rng);
      VerletList<D> list(skin, partc::VerletPairs::half);
      std::uniform_real_distribution<double> step(-0.15 * skin, 0.15 * skin);
      std::size_t most_slabs = 0;
      for (int s = 0; s < 20; ++s) {
        INFO("step " << s);
        list.update(domain, radius, set);
        most_slabs = std::max(most_slabs, list.slab_count());
        check_half_exact(list, domain, radius, set);
        for (auto& p : set.positions()) {
          for (int k = 0; k < D; ++k) p[k] += step(rng);
          p = domain.wrap(p);
        }
      }
      // The 400-particle sets have >= 8 planes of cells along x: the parallel schedule is used.
      if (n == 400) CHECK(most_slabs >= 4);
      CHECK(list.rebuild_count() >= 2);
    }
  }
}

TEST_CASE("half-list sums are bitwise the same for 1 and 2 threads", "[verlet]") {
  // Sums of an odd pair term (a force) given to both particles of each pair, as
  // generated code does; with threads, calls running at once must never share a
  // particle (a race would lose terms) and each particle must get its terms in
  // the same order (else the rounding differs).
  const Domain<3> domain = make_domain<3>(Periodicity::all, true);
  std::mt19937_64 rng(4);
  Set<3> set = random_set(domain, 6000, rng);
  VerletList<3> half(0.05, partc::VerletPairs::half);
  VerletList<3> full(0.05);
  const double radius = 0.2;
  half.update(domain, radius, set);
  const std::vector<std::int64_t> ids = set.ids();
  full.update(domain, radius, set);
  REQUIRE(set.ids() == ids);  // sorted by the same cells already: half's indices still hold
  REQUIRE(half.slab_count() >= 4);
  const auto forces = [&] {
    std::vector<Vec<3>> f(set.size(), Vec<3>::zero());
    half.for_each_pair([&](std::size_t i, const auto& pairs) {
      pairs([&](std::size_t j, const Vec<3>& dx) {
        if (i == j) return;
        const Vec<3> term = std::exp(-squared_norm(dx)) * dx;
        f[i] += term;
        f[j] -= term;
      });
    });
    return f;
  };
  const std::vector<Vec<3>> one = partc::with_threads(1, forces);
  const std::vector<Vec<3>> two = partc::with_threads(2, forces);
  CHECK(std::memcmp(one.data(), two.data(), one.size() * sizeof(Vec<3>)) == 0);
  // And the same sums, to rounding, as the full lists give particle by particle.
  double worst = 0.0;
  for (std::size_t i = 0; i < set.size(); ++i) {
    Vec<3> sum = Vec<3>::zero();
    full.for_each_near(i, [&](std::size_t j, const Vec<3>& dx) {
      if (j != i) sum += std::exp(-squared_norm(dx)) * dx;
    });
    worst = std::max(worst, norm(sum - one[i]));
  }
  CHECK(worst < 1e-12);
}

TEST_CASE("lists built on 1 and 2 threads are the same, entry for entry", "[verlet]") {
  // The build collects each slab's lists on its own thread (from the cell
  // list's packed walk) and puts them in place after: the lists, and so the
  // order of every sum's terms, must not depend on which thread built what.
  const Domain<3> domain = make_domain<3>(Periodicity::all, true);
  std::mt19937_64 rng(5);
  const Set<3> start = random_set(domain, 6000, rng);
  const auto pairs_built_on = [&](int threads) {
    Set<3> set = start;
    VerletList<3> half(0.05, partc::VerletPairs::half);
    partc::with_threads(threads, [&] { half.update(domain, 0.2, set); });
    REQUIRE(half.slab_count() >= 4);
    std::vector<std::pair<std::int64_t, std::int64_t>> pairs;  // by id, as walked on one thread
    partc::with_threads(1, [&] {
      half.for_each_pair([&](std::size_t i, const auto& pairs_of_i) {
        pairs_of_i(
            [&](std::size_t j, const Vec<3>&) { pairs.emplace_back(set.ids()[i], set.ids()[j]); });
      });
    });
    return pairs;
  };
  const auto one = pairs_built_on(1);
  CHECK(one.size() > 6000);
  CHECK(one == pairs_built_on(2));
}

TEMPLATE_TEST_CASE("queries match the reference over many steps of random motion", "[verlet]",
                   PARTC_VERLET_DIMS) {
  constexpr int D = TestType::value;
  struct Params {
    std::size_t n;
    double radius, skin;
  };
  // Box lengths 2 to 3.5. Small reach: NeighbourSearch takes its cell list; reach
  // beyond half the shortest box (1.1, 1.45): brute force, which reports several
  // images of a point, each kept once; and without periodicity a radius beyond a
  // whole box (3). (A radius over half a periodic box is refused: see below.)
  const Params cases[] = {{150, 0.2, 0.1}, {60, 0.7, 0.4}, {60, 0.95, 0.5}, {30, 3.0, 0.5}};
  std::uint64_t seed = 100 * D;
  for (Periodicity periodicity : all_periodicities) {
    for (const Params& c : cases) {
      if (periodicity != Periodicity::none && c.radius > 1.0) continue;
      INFO(periodicity_name(periodicity) << ", D = " << D << ", N = " << c.n << ", radius "
                                         << c.radius << ", skin " << c.skin);
      const Domain<D> domain = make_domain<D>(periodicity, false);
      std::mt19937_64 rng(++seed);
      Set<D> set = random_set(domain, c.n, rng);
      VerletList<D> list(c.skin);
      // Per component: a random walk the skin outlasts for a few steps at a time.
      std::uniform_real_distribution<double> step(-0.15 * c.skin, 0.15 * c.skin);
      const int steps = 40;
      std::size_t rebuilds = 0, pairs_across = 0, pairs_with_crossed = 0;
      std::vector<Vec<D>> built_at;  // by id: positions at the last rebuild
      for (int s = 0; s < steps; ++s) {
        INFO("step " << s);
        const std::vector<std::int64_t> ids_before = set.ids();
        const bool rebuilt = list.update(domain, c.radius, set);
        rebuilds += rebuilt;
        CHECK(list.rebuild_count() == rebuilds);
        if (!rebuilt) CHECK(set.ids() == ids_before);  // only a rebuild may reorder
        if (rebuilt) {
          built_at.resize(set.size());
          for (std::size_t k = 0; k < set.size(); ++k)
            built_at[static_cast<std::size_t>(set.ids()[k])] = set.positions()[k];
        }
        check_exact(list, domain, c.radius, set);
        // Positions in the box: dx is Domain::minimum_image's, bit for bit, but for
        // a particle that crossed a periodic edge since the build (moved by over
        // half a box length, as wrapped), a few ulps of the box length from it.
        const auto crossed = [&](std::size_t k) {
          const auto id = static_cast<std::size_t>(set.ids()[k]);
          const Vec<D> moved = set.positions()[k] - built_at[id];
          for (int d = 0; d < D; ++d)
            if (std::abs(moved[d]) > 0.5 * (domain.hi[d] - domain.lo[d])) return true;
          return false;
        };
        std::size_t inexact = 0, far = 0, across_edge = 0;
        const double ulps = 4 * std::numeric_limits<double>::epsilon() * 3.5;  // L <= 3.5
        for (std::size_t i = 0; i < set.size(); ++i)
          list.for_each_near(i, [&](std::size_t j, const Vec<D>& dx) {
            const Vec<D> raw = set.positions()[j] - set.positions()[i];
            const Vec<D> nearest = domain.minimum_image(raw);
            across_edge += raw != nearest;
            if (crossed(i) || crossed(j)) {
              ++pairs_with_crossed;
              far += !(squared_norm(dx - nearest) <= ulps * ulps);
            } else {
              inexact += dx != nearest;
            }
          });
        CHECK(inexact == 0);
        CHECK(far == 0);
        pairs_across += across_edge;
        for (auto& p : set.positions()) {
          for (int k = 0; k < D; ++k) p[k] += step(rng);
          p = domain.wrap(p);  // as generated code does after a move
        }
      }
      // Both kinds of step happened: lists were reused and rebuilt; and with
      // periodic edges, pairs across them and particles that crossed one.
      CHECK(rebuilds >= 2);
      if (periodicity != Periodicity::none) {
        CHECK(pairs_across > 0);
        CHECK(pairs_with_crossed > 0);
      }
      CHECK(rebuilds <= steps / 2);
    }
  }
}

TEMPLATE_TEST_CASE("both lists are, bit for bit, the half and the full lists alone", "[verlet]",
                   PARTC_VERLET_DIMS) {
  // One build serving sums of both kinds must give each exactly what a list of
  // that kind alone gives: the same rebuilds, reorders, entries and order.
  constexpr int D = TestType::value;
  const Domain<D> domain = make_domain<D>(Periodicity::all, false);
  std::mt19937_64 rng(700 + D);
  Set<D> half_set = random_set(domain, 400, rng);
  Set<D> full_set = half_set, both_set = half_set;
  const double radius = 0.15, skin = 0.1;
  VerletList<D> half(skin, partc::VerletPairs::half), full(skin);
  VerletList<D> both(skin, partc::VerletPairs::both);
  using Entries = std::vector<std::vector<std::pair<std::size_t, Vec<D>>>>;
  const auto near_of = [&](const VerletList<D>& list, std::size_t n) {
    Entries near(n);
    for (std::size_t i = 0; i < n; ++i)
      list.for_each_near(i, [&](std::size_t j, const Vec<D>& dx) { near[i].push_back({j, dx}); });
    return near;
  };
  const auto pairs_of = [&](const VerletList<D>& list, std::size_t n) {
    Entries near(n);
    partc::with_threads(1, [&] {  // a particle's calls may come from two slabs
      list.for_each_pair([&](std::size_t i, const auto& pairs) {
        pairs([&](std::size_t j, const Vec<D>& dx) { near[i].push_back({j, dx}); });
      });
    });
    return near;
  };
  std::uniform_real_distribution<double> step(-0.15 * skin, 0.15 * skin);
  for (int s = 0; s < 20; ++s) {
    INFO("step " << s);
    const bool rebuilt = both.update(domain, radius, both_set);
    CHECK(half.update(domain, radius, half_set) == rebuilt);
    CHECK(full.update(domain, radius, full_set) == rebuilt);
    REQUIRE(both_set.ids() == half_set.ids());
    REQUIRE(both_set.ids() == full_set.ids());
    CHECK(both.pair_count() == half.pair_count());
    CHECK(both.entry_count() == full.entry_count());
    CHECK(both.slab_count() == half.slab_count());
    CHECK(pairs_of(both, both_set.size()) == pairs_of(half, half_set.size()));
    CHECK(near_of(both, both_set.size()) == near_of(full, full_set.size()));
    check_exact(both, domain, radius, both_set);
    for (std::size_t k = 0; k < both_set.size(); ++k) {
      Vec<D>& p = both_set.positions()[k];
      for (int d = 0; d < D; ++d) p[d] += step(rng);
      p = domain.wrap(p);
      half_set.positions()[k] = full_set.positions()[k] = p;
    }
  }
  CHECK(both.rebuild_count() >= 2);
  CHECK(both.slab_count() >= 4);
}

TEST_CASE("a move just under half the skin keeps the lists, just over rebuilds", "[verlet]") {
  // One particle moves diagonally (so only the Euclidean norm of the displacement
  // decides) from near the hi corner, across the periodic edges: it is wrapped,
  // and the minimum image must see through that.
  const Domain<3> domain = unit_box<3>(true);
  const double radius = 0.2, skin = 0.1;
  std::mt19937_64 rng(7);
  Set<3> set = random_set(domain, 300, rng);
  const std::int64_t mover = set.ids()[0];
  set.positions()[0] = Vec<3>::filled(0.99);

  VerletList<3> list(skin);
  REQUIRE(list.update(domain, radius, set));
  REQUIRE(list.rebuild_count() == 1);
  CHECK(list.skin() == skin);
  const Vec<3> start = set.positions()[index_of_id(set, mover)];
  const Vec<3> direction = Vec<3>::filled(1.0 / std::sqrt(3.0));
  const auto move_to = [&](double distance) {
    set.positions()[index_of_id(set, mover)] = domain.wrap(start + direction * distance);
  };

  move_to(0.5 * skin * (1 - 1e-9));
  REQUIRE(set.positions()[index_of_id(set, mover)][0] < 0.1);  // it did cross the edge
  CHECK_FALSE(list.update(domain, radius, set));
  CHECK(list.rebuild_count() == 1);
  check_exact(list, domain, radius, set);

  move_to(0.5 * skin * (1 + 1e-9));
  CHECK(list.update(domain, radius, set));
  CHECK(list.rebuild_count() == 2);
  check_exact(list, domain, radius, set);

  // Measured from the last build: back to start is a move of just over skin/2 again.
  move_to(0.0);
  CHECK(list.update(domain, radius, set));
  CHECK(list.rebuild_count() == 3);
  // And an unchanged set never rebuilds.
  CHECK_FALSE(list.update(domain, radius, set));
  CHECK(list.rebuild_count() == 3);
}

TEMPLATE_TEST_CASE("two particles approaching each other by just under half the skin are found",
                   "[verlet]", PARTC_VERLET_DIMS) {
  constexpr int D = TestType::value;
  const double radius = 0.1, skin = 0.04;
  const double start_distance = radius + skin * (1 - 2e-9);  // outside radius, inside the list
  const double approach = 0.5 * skin * (1 - 1e-9);           // each; ends at radius - 1e-9 skin
  for (bool periodic : {false, true}) {
    INFO((periodic ? "periodic, across the edge" : "non-periodic") << ", D = " << D);
    const Domain<D> domain = unit_box<D>(periodic);
    std::mt19937_64 rng(11 + D);
    Set<D> set = random_set(domain, 200, rng);  // others: enough for the cell-list path
    Vec<D> a = Vec<D>::filled(0.5), b = a;
    // Periodic: a just above lo, b just below hi, facing each other across the edge.
    a[0] = periodic ? 0.01 : 0.45;
    b[0] = periodic ? 1.0 - (start_distance - 0.01) : 0.45 + start_distance;
    const double toward_b = periodic ? -1.0 : 1.0;
    const std::int64_t id_a = set.ids()[set.push_back(a)];
    const std::int64_t id_b = set.ids()[set.push_back(b)];

    VerletList<D> list(skin);
    list.update(domain, radius, set);
    const auto b_near_a = [&] {
      const std::vector<std::int64_t> ids = near_ids(list, set, index_of_id(set, id_a));
      return std::binary_search(ids.begin(), ids.end(), id_b);
    };
    REQUIRE_FALSE(b_near_a());

    Vec<D> step{};
    step[0] = toward_b * approach;
    set.positions()[index_of_id(set, id_a)] = domain.wrap(a + step);
    set.positions()[index_of_id(set, id_b)] = domain.wrap(b - step);
    CHECK_FALSE(list.update(domain, radius, set));
    CHECK(list.rebuild_count() == 1);
    CHECK(b_near_a());
    check_exact(list, domain, radius, set);
  }
}

TEST_CASE("pairs on the boundary of the radius across a periodic edge are all found", "[verlet]") {
  // Skin 0 leaves no slack: the build (cell list: query images shifted by L) and
  // the query (difference first, then shifted) round differently, so without the
  // header's round-off guard some of these pairs, a few ulps either side of the
  // contract's |dx|^2 = radius^2 (1 + 1e-12), would be lost. Checked here with no
  // tolerance, dx as the contract defines it.
  const double L = std::cbrt(32000 / 0.8442);  // the LJ benchmark's box
  const Domain<1> domain{{{0.0}}, {{L}}, {{true}}};
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 3; ++trial) {
    const double radius = 2.5 * (1 + 0.1 * unit(rng));
    Set<1> set = random_set(domain, 200, rng);  // enough for the cell-list path
    for (int pair = 0; pair < 20; ++pair) {
      const double xi = 0.5 * radius * unit(rng);
      double xj = xi - radius * std::sqrt(1 + 1e-12) + L;
      for (int ulp = 0; ulp < 40; ++ulp) xj = std::nextafter(xj, 0.0);
      for (int ulp = 0; ulp < 80; ++ulp, xj = std::nextafter(xj, L)) {
        set.push_back(Vec<1>{{xi}});
        set.push_back(Vec<1>{{xj}});
      }
    }
    VerletList<1> list(0.0);
    list.update(domain, radius, set);
    const auto& p = set.positions();
    std::size_t missed = 0;
    std::vector<char> hit(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      std::fill(hit.begin(), hit.end(), 0);
      list.for_each_near(i, [&](std::size_t j, const Vec<1>&) { hit[j] = 1; });
      for (std::size_t j = 0; j < p.size(); ++j)
        missed += !hit[j] && squared_norm(domain.minimum_image(p[j] - p[i])) <=
                                 radius * radius * (1 + 1e-12);
    }
    CHECK(missed == 0);
    CHECK_FALSE(list.update(domain, radius, set));  // skin 0: nothing moved, no rebuild
  }
}

TEST_CASE("empty and one-particle sets; a change of count rebuilds", "[verlet]") {
  const Domain<2> domain = unit_box<2>(true);
  Set<2> set;
  VerletList<2> list(0.1);
  CHECK(list.update(domain, 0.2, set));
  CHECK_FALSE(list.update(domain, 0.2, set));
  CHECK(list.entry_count() == 0);

  set.push_back(Vec<2>{{0.3, 0.4}});
  CHECK(list.update(domain, 0.2, set));
  CHECK(list.entry_count() == 1);  // itself
  std::vector<std::size_t> js;
  list.for_each_near(0, [&](std::size_t j, const Vec<2>& dx) {
    js.push_back(j);
    CHECK(dx == Vec<2>::zero());
  });
  CHECK(js == std::vector<std::size_t>{0});
  CHECK_FALSE(list.update(domain, 0.2, set));

  set.push_back(Vec<2>{{0.35, 0.4}});
  CHECK(list.update(domain, 0.2, set));
  CHECK(list.entry_count() == 4);
  check_exact(list, domain, 0.2, set);

  set.alive()[0] = 0;
  set.erase_dead();
  CHECK(list.update(domain, 0.2, set));
  CHECK(list.entry_count() == 1);
  check_exact(list, domain, 0.2, set);
  CHECK(list.rebuild_count() == 4);
}

TEST_CASE("a change of radius or domain rebuilds", "[verlet]") {
  Domain<2> domain = unit_box<2>(true);
  std::mt19937_64 rng(3);
  Set<2> set = random_set(domain, 100, rng);
  VerletList<2> list(0.05);
  CHECK(list.update(domain, 0.2, set));
  const std::size_t pairs = list.entry_count();
  CHECK(list.update(domain, 0.1, set));
  CHECK(list.entry_count() < pairs);
  check_exact(list, domain, 0.1, set);
  CHECK_FALSE(list.update(domain, 0.1, set));
  CHECK(list.update(domain, 0.2, set));  // back again
  CHECK(list.entry_count() == pairs);

  domain.periodic[1] = false;
  CHECK(list.update(domain, 0.2, set));
  check_exact(list, domain, 0.2, set);
  domain.hi[0] = 1.5;  // the particles stay where they are, the box grows
  CHECK(list.update(domain, 0.2, set));
  check_exact(list, domain, 0.2, set);
  CHECK_FALSE(list.update(domain, 0.2, set));
  CHECK(list.rebuild_count() == 5);
}

TEST_CASE("reordering the set outside update is safe", "[verlet]") {
  // Positions are tracked by index: a permutation moves most slots far (a
  // rebuild), while swapping two particles closer than skin/2 needs none.
  const Domain<2> domain = unit_box<2>(true);
  std::mt19937_64 rng(5);
  Set<2> set = random_set(domain, 200, rng);
  set.push_back(Vec<2>{{0.5, 0.5}});
  set.push_back(Vec<2>{{0.5, 0.5 + 0.01}});
  VerletList<2> list(0.05);
  list.update(domain, 0.15, set);

  std::vector<std::size_t> order(set.size());
  std::iota(order.begin(), order.end(), 0);
  const std::size_t a = index_of_id(set, 200), b = index_of_id(set, 201);
  std::swap(order[a], order[b]);
  set.permute(order);
  CHECK_FALSE(list.update(domain, 0.15, set));
  check_exact(list, domain, 0.15, set);

  std::shuffle(order.begin(), order.end(), rng);
  set.permute(order);
  CHECK(list.update(domain, 0.15, set));
  check_exact(list, domain, 0.15, set);
}

TEST_CASE("NaN positions rebuild and are never reported", "[verlet]") {
  const Domain<2> domain = unit_box<2>(true);
  std::mt19937_64 rng(9);
  Set<2> set = random_set(domain, 50, rng);
  VerletList<2> list(0.05);
  list.update(domain, 0.2, set);
  set.positions()[7][1] = std::numeric_limits<double>::quiet_NaN();
  CHECK(list.update(domain, 0.2, set));
  CHECK(list.update(domain, 0.2, set));  // NaN never counts as "not moved"
  for (std::size_t i = 0; i < set.size(); ++i)
    list.for_each_near(i, [&](std::size_t j, const Vec<2>& dx) {
      CHECK(is_finite(set.positions()[j]));
      CHECK(is_finite(dx));
    });
}

TEST_CASE("a bad skin or radius is rejected", "[verlet]") {
  for (double skin : {-0.1, std::numeric_limits<double>::quiet_NaN(),
                      std::numeric_limits<double>::infinity()}) {
    INFO("skin " << skin);
    CHECK_THROWS_AS(VerletList<2>(skin), std::invalid_argument);
  }
  const Domain<2> domain = unit_box<2>(true);
  Set<2> set;
  set.push_back(Vec<2>{{0.5, 0.5}});
  VerletList<2> list(0.3);
  // radius + skin would be positive: the radius itself is checked.
  for (double radius : {0.0, -0.1, std::numeric_limits<double>::quiet_NaN()}) {
    INFO("radius " << radius);
    CHECK_THROWS_WITH(list.update(domain, radius, set), Catch::Contains("radius must be positive"));
  }
  CHECK(list.rebuild_count() == 0);
}

TEST_CASE("a radius over half a periodic box length is refused, not cut to one image",
          "[verlet]") {
  Domain<2> domain = unit_box<2>(false);
  domain.periodic[0] = true;  // length 1 in x; y is not periodic
  Set<2> set;
  set.push_back(Vec<2>{{0.1, 0.5}});
  set.push_back(Vec<2>{{0.9, 0.5}});
  VerletList<2> list(0.1);
  CHECK_THROWS_WITH(list.update(domain, 0.55, set), Catch::Contains("exceeds half a periodic box"));
  CHECK(list.rebuild_count() == 0);
  // Just under half the box: one image, found across the edge; radius + skin
  // beyond half the box is fine (the build sees both images of j and keeps it once).
  REQUIRE(list.update(domain, 0.49, set));
  std::vector<std::size_t> found;
  list.for_each_near(0, [&](std::size_t j, const Vec<2>& dx) {
    found.push_back(j);
    if (j != 0) CHECK(std::abs(std::abs(dx[0]) - 0.2) < 1e-15);
  });
  CHECK(found.size() == 2);
  // Not periodic in y: a radius of 10 box lengths there is fine.
  domain.periodic[0] = false;
  CHECK_NOTHROW(list.update(domain, 10.0, set));
}
