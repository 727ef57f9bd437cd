// The packed pair walks (simd/pair_batches.hpp, VerletList::for_each_pair_batch,
// NeighbourSearch::for_each_near_batch) against the scalar ones they pack
// (OrderedCellList::for_each_pair, itself tested against brute force in
// test_search.cpp; VerletList::for_each_pair, in test_verlet_list.cpp): every
// point's pairs in the same order with the same dx bit for bit; padding as
// documented; the compress of every mask against the obvious loop. Built
// twice, with the runtime's flags and with -march=native: with PARTC_NATIVE
// off that covers both the narrowest and the widest vectors of the machine;
// with it on (the default) both builds get the widest (the test prints the
// lane count).
#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "partc/domain.hpp"
#include "partc/parallel.hpp"
#include "partc/particle_set.hpp"
#include "partc/search/neighbour_search.hpp"
#include "partc/search/ordered_cell_list.hpp"
#include "partc/search/verlet_list.hpp"
#include "partc/simd/compress.hpp"
#include "partc/simd/pair_batches.hpp"

using partc::Domain;
using partc::Vec;
namespace simd = partc::simd;
namespace hn = partc::simd::hn;

namespace {

// Points uniform in the box, or (clustered) in a few tight blobs; every 97th
// a NaN when asked.
template <int D>
std::vector<Vec<D>> points(std::size_t n, bool clustered, bool with_nan, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 0.02);
  std::vector<Vec<D>> centres(4);
  for (auto& c : centres)
    for (int d = 0; d < D; ++d) c[d] = u(rng);
  std::vector<Vec<D>> p(n);
  for (std::size_t k = 0; k < n; ++k)
    for (int d = 0; d < D; ++d)
      p[k][d] = clustered ? std::fmod(centres[k % 4][d] + g(rng) + 1.0, 1.0) : u(rng);
  if (with_nan)
    for (std::size_t k = 0; k < n; k += 97) p[k][0] = std::numeric_limits<double>::quiet_NaN();
  return p;
}

// A walk's pairs by i, as (j, dx).
template <int D>
using PairsByI = std::vector<std::vector<std::pair<std::size_t, Vec<D>>>>;

// Points whose pairs differ between two walks (j or dx's bits, NaN and -0
// included), and the pairs compared.
template <int D>
std::pair<std::size_t, std::size_t> compare_walks(const PairsByI<D>& scalar,
                                                  const PairsByI<D>& packed) {
  std::size_t differing = 0, pairs = 0;
  for (std::size_t i = 0; i < scalar.size(); ++i) {
    bool same = packed[i].size() == scalar[i].size();
    for (std::size_t k = 0; same && k < scalar[i].size(); ++k)
      same = packed[i][k].first == scalar[i][k].first &&
             std::memcmp(&packed[i][k].second, &scalar[i][k].second, sizeof(Vec<D>)) == 0;
    differing += !same;
    pairs += scalar[i].size();
  }
  return {differing, pairs};
}

// Batch b's pairs appended to `packed` by i, and the batches holding each
// i's pairs counted (batches_of); returns the padding entries not as
// PairBatch::finish makes them. Batches run at once never share a point.
template <int D>
std::size_t record_batch(const simd::PairBatch<D>& b, PairsByI<D>& packed,
                         std::vector<int>& batches_of) {
  REQUIRE(b.count() > 0);
  const std::size_t last = b.i()[b.count() - 1];
  for (std::size_t k = 0; k < b.count(); ++k) {
    const std::size_t i = b.i()[k];
    if (k == 0 || b.i()[k - 1] != i) ++batches_of[i];
    Vec<D> dx;
    for (int d = 0; d < D; ++d) dx[d] = b.dx(d)[k];
    packed[i].push_back({static_cast<std::size_t>(b.j()[k]), dx});
  }
  std::size_t bad_padding = 0;
  for (std::size_t k = b.count(); k < b.padded(); ++k) {
    bad_padding += b.i()[k] != last || b.j()[k] != last || b.r2()[k] != 1.0;
    for (int d = 0; d < D; ++d) bad_padding += b.dx(d)[k] != 0.0;
  }
  return bad_padding;
}

// Both walks over one structure: for every point, the pairs the batches give
// it, in their order, must be the scalar walk's (the pair (i, i) included only
// with_self); batches must be as documented (padding, a point's pairs together).
template <int D>
void check_walks(const Domain<D>& domain, double radius, const std::vector<Vec<D>>& p,
                 bool with_self) {
  partc::OrderedCellList<D> cells;
  cells.build(domain, radius, p);
  // By i: calls for one i never run at once (slab_schedule.hpp), for one or more threads.
  PairsByI<D> scalar(p.size()), packed(p.size());
  cells.for_each_pair([&](std::size_t i, const auto& pairs_of_i) {
    pairs_of_i([&](std::size_t j, const Vec<D>& dx) {
      if (j != i || with_self) scalar[i].push_back({j, dx});
    });
  });
  simd::PairBatches<D> batches;
  batches.build(cells, p.size());
  std::atomic<std::size_t> bad_padding{0};
  std::vector<int> batches_of(p.size(), 0);  // batches holding i's pairs, counted per call
  batches.for_each_pair(cells, with_self, [&](simd::PairBatch<D>& b) {
    bad_padding += record_batch(b, packed, batches_of);
  });
  CHECK(bad_padding == 0);
  // A point's pairs in one batch: once, or twice for slab 0's pairs across the edge.
  CHECK(*std::max_element(batches_of.begin(), batches_of.end()) <= 2);
  const auto [differing, pairs] = compare_walks(scalar, packed);
  CHECK(differing == 0);
  CHECK(pairs > p.size() / 2);  // not a vacuous comparison
}

// VerletList's packed walk against its for_each_pair, on the lists as they
// are: the same pairs per i, in order, bit for bit; batches as documented
// (padding; full but for one per slab at most; a point's pairs in at most two
// consecutive batches, or three for slab 0's pairs across the edge). Returns
// the pairs compared.
template <int D>
std::size_t check_verlet_walks(const partc::VerletList<D>& list, std::size_t n, bool with_self) {
  PairsByI<D> scalar(n), packed(n);
  list.for_each_pair([&](std::size_t i, const auto& pairs_of_i) {
    pairs_of_i([&](std::size_t j, const Vec<D>& dx) {
      if (j != i || with_self) scalar[i].push_back({j, dx});
    });
  });
  std::atomic<std::size_t> bad_padding{0}, short_batches{0};
  std::vector<int> batches_of(n, 0);
  list.for_each_pair_batch(with_self, [&](simd::PairBatch<D>& b) {
    short_batches += b.count() < simd::PairBatch<D>::batch_vectors * simd::lanes();
    bad_padding += record_batch(b, packed, batches_of);
  });
  CHECK(bad_padding == 0);
  CHECK(short_batches <= list.slab_count());
  if (n > 0) CHECK(*std::max_element(batches_of.begin(), batches_of.end()) <= 3);
  const auto [differing, pairs] = compare_walks(scalar, packed);
  CHECK(differing == 0);
  return pairs;
}

// Steps of random motion of at most `move` per coordinate, wrapped (so
// particles cross periodic edges), each followed by update and both walks;
// some steps must keep the lists (moves measured without a rebuild).
template <int D>
void check_verlet_steps(const Domain<D>& domain, double radius, double skin, std::size_t n,
                        double move, std::uint64_t seed) {
  const std::vector<Vec<D>> start = points<D>(n, false, false, seed);
  partc::ParticleSet<D> set;
  for (const Vec<D>& p : start) set.push_back(domain.wrap(p));
  partc::VerletList<D> list(skin, partc::VerletPairs::half);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> step(-move, move);
  std::size_t kept = 0, crossings = 0, pairs = 0;
  for (int s = 0; s < 8; ++s) {
    INFO("step " << s);
    kept += !list.update(domain, radius, set);
    for (const bool with_self : {false, true}) pairs += check_verlet_walks(list, n, with_self);
    for (auto& p : set.positions()) {
      const Vec<D> before = p;
      for (int k = 0; k < D; ++k) p[k] += step(rng);
      p = domain.wrap(p);
      for (int k = 0; k < D; ++k) crossings += std::abs(p[k] - before[k]) > 2 * move;
    }
  }
  CHECK(kept >= 2);
  CHECK(pairs > 8 * n);  // not a vacuous comparison
  INFO("D = " << D);
  // In 1D (2000 points) a step carries few across: no crossing is asked of it.
  if (domain.periodic[0] && D > 1) CHECK(crossings > 0);
}

// NeighbourSearch's packed queries against its for_each_near(i), on each
// structure and both orders: every particle's neighbours in one batch, in
// the query's order, bit for bit (the pair (i, i) only with_self), and no
// batch claiming each pair once. Returns the pairs compared.
template <int D>
std::size_t check_near_batches(const Domain<D>& domain, double radius, const std::vector<Vec<D>>& p,
                               partc::NeighbourSearch<D>& search, bool with_self) {
  partc::ParticleSet<D> set;
  for (const Vec<D>& x : p) set.push_back(domain.wrap(x));
  search.build(domain, radius, set);
  PairsByI<D> scalar(p.size()), packed(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    search.for_each_near(i, [&](std::size_t j, const Vec<D>& dx) {
      if (with_self || j != i || dx != Vec<D>::zero()) scalar[i].push_back({j, dx});
    });
  std::atomic<std::size_t> bad_padding{0}, claims_once{0};
  std::vector<int> batches_of(p.size(), 0);
  search.for_each_near_batch(with_self, [&](simd::PairBatch<D>& b) {
    claims_once += b.each_pair_once();
    bad_padding += record_batch(b, packed, batches_of);
  });
  CHECK(bad_padding == 0);
  CHECK(claims_once == 0);
  if (!p.empty()) CHECK(*std::max_element(batches_of.begin(), batches_of.end()) <= 1);
  const auto [differing, pairs] = compare_walks(scalar, packed);
  CHECK(differing == 0);
  return pairs;
}

template <int D>
Domain<D> unit_box(bool periodic) {
  Domain<D> domain;
  for (int d = 0; d < D; ++d) {
    domain.lo[d] = 0.0;
    domain.hi[d] = 1.0;
    domain.periodic[d] = periodic;
  }
  return domain;
}

}  // namespace

TEST_CASE("compress moves the kept lanes to the front, in order", "[simd]") {
  const simd::Real d;
  const simd::Index du;
  const std::size_t lanes = hn::Lanes(d);
  INFO("lanes of double: " << lanes);
  std::vector<double> in(lanes), out(lanes);
  std::vector<std::uint64_t> in_j(lanes), out_j(lanes);
  for (std::size_t k = 0; k < lanes; ++k) in[k] = 10.0 + static_cast<double>(k), in_j[k] = 100 + k;
  for (std::uint64_t mask = 0; mask < (std::uint64_t{1} << lanes); ++mask) {
    std::vector<double> keep(lanes);
    std::vector<double> expected;
    for (std::size_t k = 0; k < lanes; ++k) {
      keep[k] = (mask >> k & 1) ? 1.0 : 0.0;
      if (mask >> k & 1) expected.push_back(in[k]);
    }
    const simd::Compressor compress(hn::Gt(hn::LoadU(d, keep.data()), hn::Zero(d)));
    REQUIRE(compress.count() == expected.size());
    hn::StoreU(compress(hn::LoadU(d, in.data())), d, out.data());
    hn::StoreU(compress(hn::LoadU(du, in_j.data())), du, out_j.data());
    for (std::size_t k = 0; k < expected.size(); ++k) {
      CHECK(out[k] == expected[k]);
      CHECK(static_cast<double>(out_j[k]) == expected[k] + 90.0);
    }
  }
}

TEST_CASE("the packed walk gives the scalar walk's pairs, bit for bit", "[simd]") {
  INFO("lanes of double: " << simd::lanes());
  for (const bool periodic : {true, false})
    for (const bool clustered : {false, true})
      for (const bool with_self : {false, true}) {
        INFO("periodic " << periodic << ", clustered " << clustered << ", with (i, i) "
                         << with_self);
        check_walks<2>(unit_box<2>(periodic), 0.05, points<2>(3000, clustered, false, 1),
                       with_self);
        check_walks<3>(unit_box<3>(periodic), 0.1, points<3>(3000, clustered, false, 2), with_self);
        check_walks<1>(unit_box<1>(periodic), 0.002, points<1>(2000, clustered, false, 3),
                       with_self);
      }
  SECTION("NaN points have no pairs") {
    check_walks<2>(unit_box<2>(true), 0.05, points<2>(3000, false, true, 4), true);
  }
  SECTION("exact mode: a periodic dimension with fewer than 3 cells") {
    check_walks<2>(unit_box<2>(true), 0.4, points<2>(500, false, false, 5), true);
  }
  SECTION("two threads") {
    partc::with_threads(2, [] {
      check_walks<2>(unit_box<2>(true), 0.02, points<2>(20000, false, false, 6), false);
    });
  }
}

TEST_CASE("packed queries give for_each_near's neighbours, bit for bit", "[simd]") {
  using Search = partc::NeighbourSearch<2>;
  for (const bool periodic : {true, false})
    for (const bool with_self : {false, true})
      for (const auto kind :
           {Search::Kind::cell_list, Search::Kind::kd_tree, Search::Kind::brute_force})
        for (const auto order : {Search::Order::reorder, Search::Order::keep}) {
          INFO("periodic " << periodic << ", with (i, i) " << with_self << ", structure "
                           << static_cast<int>(kind) << ", order kept "
                           << (order == Search::Order::keep));
          Search search(kind, order);
          const std::size_t pairs = check_near_batches<2>(
              unit_box<2>(periodic), 0.05, points<2>(3000, false, true, 21), search, with_self);
          CHECK(pairs > 3000);  // not a vacuous comparison
        }
  SECTION("3D, clustered, two threads") {
    partc::with_threads(2, [] {
      partc::NeighbourSearch<3> search;
      CHECK(check_near_batches<3>(unit_box<3>(true), 0.08, points<3>(20000, true, false, 22),
                                  search, false) > 20000);
    });
  }
  SECTION("an empty set") {
    partc::NeighbourSearch<1> search;
    CHECK(check_near_batches<1>(unit_box<1>(true), 0.1, {}, search, true) == 0);
  }
}

// The half lists hold 23 entries a point on average in 2D, 14 in 3D, 6 in
// 1D and 120-130 in the small boxes: points filtered alone (two vectors of
// entries or more) and runs of short lists, both within one slab.
TEST_CASE("the packed Verlet walk gives for_each_pair's pairs, bit for bit", "[simd][verlet]") {
  INFO("lanes of double: " << simd::lanes());
  for (const bool periodic : {true, false}) {
    INFO("periodic " << periodic);
    check_verlet_steps<2>(unit_box<2>(periodic), 0.05, 0.02, 3000, 0.003, 11);
    check_verlet_steps<3>(unit_box<3>(periodic), 0.1, 0.03, 3000, 0.004, 12);
    check_verlet_steps<1>(unit_box<1>(periodic), 0.002, 0.001, 2000, 0.0001, 13);
  }
  SECTION("a small periodic box: every entry needs the image shift") {
    check_verlet_steps<2>(unit_box<2>(true), 0.3, 0.25, 300, 0.02, 14);
    check_verlet_steps<3>(unit_box<3>(true), 0.4, 0.2, 300, 0.02, 15);
  }
  SECTION("NaN positions have no pairs") {
    const Domain<2> domain = unit_box<2>(true);
    partc::ParticleSet<2> set;
    for (const Vec<2>& p : points<2>(3000, false, true, 16)) set.push_back(p);
    partc::VerletList<2> list(0.02, partc::VerletPairs::half);
    list.update(domain, 0.05, set);
    for (const bool with_self : {false, true}) check_verlet_walks(list, set.size(), with_self);
  }
  SECTION("two threads, several slabs") {
    partc::with_threads(2, [] {
      const Domain<2> domain = unit_box<2>(true);
      partc::ParticleSet<2> set;
      for (const Vec<2>& p : points<2>(20000, false, false, 17)) set.push_back(p);
      partc::VerletList<2> list(0.005, partc::VerletPairs::half);
      list.update(domain, 0.02, set);
      CHECK(list.slab_count() >= 4);
      for (const bool with_self : {false, true}) check_verlet_walks(list, set.size(), with_self);
    });
  }
}
