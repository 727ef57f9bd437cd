// partc/search/verlet_list.hpp: VerletList<D>, neighbour lists reused across steps
// (molecular dynamics with a skin). update builds, for every particle, the list
// of particles within radius + skin (with NeighbourSearch), and rebuilds only
// when that list could have become incomplete; for_each_near filters the list
// of one particle with the current distances.
//
// Query contract: as BruteForce (brute_force.hpp), but asked by particle index:
// for_each_near(i, f) calls f(j, dx) exactly once for each particle j with
// |dx|^2 <= radius^2 * (1 + 1e-12), dx the minimum image of p[j] - p[i] for the
// positions of the last update (wrapped first, as BruteForce does: for positions
// in the box, as generated code keeps them, domain.minimum_image(p[j] - p[i])
// bit for bit); j == i is included (dx = 0). Lists are in a fixed order between
// rebuilds, so per-particle sums do not depend on how queries are scheduled.
//
// Invariant (why a list stays complete): the minimum-image distance is the
// distance on the torus, so it obeys the triangle inequality. If particles i and
// j have each moved at most skin/2 since the build, their distance has shrunk by
// at most skin; so a pair within radius now was within radius + skin at the
// build, and is in the lists. The worst case is exactly two particles each
// approaching the other by just under skin/2. update therefore rebuilds when
// some particle's minimum-image displacement since the build exceeds skin/2
// (measured exactly, from the positions kept at the build - not estimated from
// velocities or step counts), and on the first call, a radius or domain change,
// or a change of the particle count. The skin is fixed at construction.
//
// Half lists (VerletPairs::half, for sums whose pair term is the same or its
// negative seen from either particle: Newton's third law): for_each_pair walks
// each pair within radius once, from the lower index i, plus (i, i, 0) once
// per particle (the full lists include j == i too), so a caller gives the
// term to both particles and evaluates half as many. The calls run in
// parallel yet deterministically, in the slabs of the build's cell list
// (slab_schedule.hpp), which checked the slab rule for every pair it can
// report; fewer than 4 planes, a search other than the cell list (clustered
// or tiny sets), or runs breaking the rule mean one slab (serial pair calls).
// VerletPairs::both keeps both from one build, for a set with sums of either
// kind: one build and one reorder per position change, where a half and a full
// VerletList would each rebuild (and reorder the set under the other). Each
// view is bitwise the one a VerletList of that kind alone would give.
// for_each_pair_batch gives for_each_pair's pairs packed for vector
// arithmetic (simd/pair_batches.hpp), bit for bit, in the same slabs.
//
// Surprises:
// - A rebuild may REORDER the set (as NeighbourSearch::build): indices taken
//   before an update that returned true are stale afterwards (ids are not).
// - update copies the positions; queries measure that copy, never positions
//   moved after it (those were not checked against the skin). Call update after
//   every move: without a rebuild it is one O(N) pass.
// - Positions are tracked by index, not by id, and need not be: the argument
//   above holds slot by slot, so whatever reorders or replaces particles without
//   changing their number is safe (a slot whose position jumped makes update
//   rebuild). Crossing a periodic edge (and being wrapped) is no displacement.
// - The radius must be at most half of each periodic length (update throws
//   std::invalid_argument otherwise): beyond that a particle meets several
//   images of another (BruteForce reports them all), and a list keeps one j.
//   radius + skin may exceed it: the build's search then reports images, each
//   j is kept once, dx is the shortest image at every query, and the triangle
//   inequality needs no bound.
// - The build reaches a hair beyond radius + skin (round_off_guard): without
//   that, a pair on the very boundary of the radius could be lost to rounding.
// - A NaN position counts as moved (every update rebuilds) and is never reported.
// - dx is Domain::minimum_image of the wrapped positions, bit for bit, except
//   for a particle that crossed a periodic edge since the build: it is measured
//   from its position unwrapped by one box length (a few ulps of the box apart).
//
// Periodic images without a minimum image per pair: while each particle stays
// within half the skin of its build position and radius + skin is under half
// of each periodic length, a pair needs the image shift it needed at the build
// (that shift of dx from within radius + skin, or past radius + 2 skin from
// it, is the only image that can come within the radius). So the build marks
// the pairs across a periodic edge (the top bit of the entry; they follow the
// others in each list), update keeps each particle on the side of the edge it
// was built on (unwrapped by a box length if it crossed), and the walk applies
// the minimum image to the marked pairs alone: in a periodic box of 32000 LJ
// atoms it was a third of a fused LJ + Coulomb pass. When the condition fails
// (a small box) every entry is marked and positions stay wrapped.
#pragma once

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "partc/domain.hpp"
#include "partc/parallel.hpp"
#include "partc/search/neighbour_search.hpp"
#include "partc/search/slab_schedule.hpp"
#include "partc/simd/pair_batches.hpp"
#include "partc/vec.hpp"

namespace partc {

enum class VerletPairs { full, half, both };

template <int D>
class VerletList {
 public:
  // Throws std::invalid_argument unless skin is finite and >= 0 (0: rebuild on any motion).
  explicit VerletList(double skin, VerletPairs pairs = VerletPairs::full)
      : skin_(skin), pairs_(pairs) {
    if (!(skin >= 0.0 && std::isfinite(skin))) {
      std::ostringstream message;
      message << "partc: VerletList: skin must be finite and >= 0, got " << skin;
      throw std::invalid_argument(message.str());
    }
  }

  // Returns whether it rebuilt (and so may have reordered set). Throws
  // std::invalid_argument for a bad radius or periodic length (check_search_arguments).
  template <class Set>
  bool update(const Domain<D>& domain, double radius, Set& set) {
    if (BruteForce<D>::needs_all_images(domain, radius)) {
      std::ostringstream message;
      message << "partc: Verlet lists: radius " << radius
              << " exceeds half a periodic box length, so a particle would meet several images "
                 "of another and a list keeps one; enlarge the box, or search without a skin "
                 "(a search sums every image)";
      throw std::invalid_argument(message.str());
    }
    const bool rebuild = rebuild_count_ == 0 || radius != radius_ || domain.lo != domain_.lo ||
                         domain.hi != domain_.hi || domain.periodic != domain_.periodic ||
                         set.positions().size() != at_build_.size() ||
                         moved_more_than_half_skin(set.positions());
    if (rebuild) build(domain, radius, set);
    const auto& positions = set.positions();  // float ones widen in wrap
    current_.resize(positions.size());
    parallel_for(positions.size(), LoopWork::light, [&](std::size_t i) {
      current_[i] = domain.wrap(positions[i]);
      if (!unmarked_pairs_direct_) return;
      for (int k = 0; k < D; ++k) {  // back to the side of the edge it was built on
        const double moved = current_[i][k] - at_build_[i][k];
        current_[i][k] +=
            length_[k] * (static_cast<int>(moved < -half_[k]) - static_cast<int>(moved > half_[k]));
      }
    });
    return rebuild;
  }

  // Full lists: f(j, dx) for every j near particle i (an index into the set as of
  // the last update).
  template <class F>
  void for_each_near(std::size_t i, F&& f) const {
    assert(pairs_ != VerletPairs::half);
    filter(full_neighbours_, i, full_start_[i], full_start_[i + 1], f);
  }

  // Half lists, the pair walk of slab_schedule.hpp: f(i, pairs) for every
  // particle, pairs(g) calling g(i, 0) and g(j, dx) for every j > i within the
  // radius, in the deterministic parallel schedule above.
  template <class F>
  void for_each_pair(F&& f) const {
    assert(pairs_ != VerletPairs::full);
    slabs_.for_each_slab([&](std::size_t a) {
      for (std::size_t i = slabs_.start(a); i < slabs_.start(a + 1); ++i)
        f(i, [&](auto&& g) {
          g(i, Vec<D>::zero());
          filter(neighbours_, i, start_[i], across_[i], g);
        });
      if (a + 1 == slabs_.count())
        for (std::size_t i = slabs_.start(0); i < slabs_.start(1); ++i)
          f(i, [&](auto&& g) { filter(neighbours_, i, across_[i], start_[i + 1], g); });
    });
  }

  // for_each_pair's pairs packed for vector arithmetic (simd/pair_batches.hpp):
  // f(batch) for batches of them, in its order, slabs and threads, with its
  // dx bit for bit, the pair (i, i) (dx 0) first only with_self. Why: the
  // sums' terms then run on vectors of pairs, as the cell list's do; and the
  // lists are filtered a vector of entries at a time (filter_run): a point
  // with two vectors' worth of entries or more alone, shorter lists that
  // follow each other together. In 2D a point has about 5 pairs, under a
  // vector of 8 doubles: a vector per point was 60% of the seed update's
  // time, and filtering runs of lists made it 1.9x faster. Alone, a point's
  // position is broadcast, not gathered, which LJ melt's 3D lists of ~40
  // entries need. A batch holds PairBatch::batch_vectors vectors of pairs
  // or more, except a slab's last, and never spans two slabs; a point's
  // pairs may end one batch and begin the next (the walk's order is kept).
  template <class F>
  void for_each_pair_batch(bool with_self, F&& f) const {
    assert(pairs_ != VerletPairs::full);
    batches_.resize(slabs_.count());
    slabs_.for_each_slab([&](std::size_t a) {
      simd::PairBatch<D>& batch = batches_[a];
      batch.clear();
      batch.set_slab(a);
      const std::size_t chunk = simd::PairBatch<D>::batch_vectors * simd::lanes();
      const std::size_t alone = 2 * simd::lanes();  // entries of a list filtered alone
      std::size_t run = 0, run_end = 0;             // entries of short lists waiting, consecutive
      const auto flush = [&] {
        for (std::size_t k = run; k < run_end; k += chunk) {
          filter_run<false>(batch, 0, k, std::min(run_end, k + chunk));
          batch.hand_over_if_full(f);
        }
        run = run_end;
      };
      // Point i's entries first .. stop-1: most extend the run.
      const auto add = [&](std::size_t i, std::size_t first, std::size_t stop) {
        if (stop - first >= alone || first != run_end) {
          flush();
          run = first;
          if (stop - first >= alone) {
            filter_run<true>(batch, i, first, stop);
            batch.hand_over_if_full(f);
            run = stop;
          }
        }
        run_end = stop;
      };
      for (std::size_t i = slabs_.start(a); i < slabs_.start(a + 1); ++i) {
        if (with_self) {
          flush();
          batch.push(i, i, Vec<D>::zero());
        }
        add(i, start_[i], across_[i]);
      }
      if (a + 1 == slabs_.count())
        for (std::size_t i = slabs_.start(0); i < slabs_.start(1); ++i)
          add(i, across_[i], start_[i + 1]);
      flush();
      batch.hand_over_rest(f);
    });
  }

  std::size_t rebuild_count() const { return rebuild_count_; }
  // Pair walks over the lists, as NeighbourSearch::note_walk counts them.
  void note_walk() { ++walk_count_; }
  std::size_t walk_count() const { return walk_count_; }
  double skin() const { return skin_; }
  // List entries at the last build (within the build reach): pairs i < j in the
  // half lists, ordered pairs (i, j) with i == j included in the full ones (0 for
  // lists not kept).
  std::size_t pair_count() const { return start_.empty() ? 0 : start_.back(); }
  std::size_t entry_count() const { return full_neighbours_.size(); }
  // For people: "Verlet lists, skin 0.3, each pair once, 1240000 pairs, 4 slabs"
  // (both: that, then "and full, 2512000 entries").
  std::string describe() const {
    std::ostringstream text;
    text << "Verlet lists, skin " << skin_;
    if (pairs_ != VerletPairs::full)
      text << ", each pair once, " << pair_count() << " pairs, " << slab_count()
           << (slab_count() == 1 ? " slab (serial)" : " slabs");
    if (pairs_ == VerletPairs::both) text << ", and full,";
    if (pairs_ != VerletPairs::half) text << " " << entry_count() << " entries";
    return text.str();
  }
  // Half lists: the slabs of the parallel schedule (1: serial).
  std::size_t slab_count() const { return slabs_.count(); }

 private:
  // g(j, dx) for the entries first .. stop-1 of particle i's list within the radius.
  // As CellGrid::scan, a chunk of candidates is filtered without a branch before g
  // is called: most are hits, unpredictably (radius^D / (radius + skin)^D of them).
  // Measured (LJ forces, 3D, 32000 particles, 79 candidates each, g++ 12 -O3):
  // queries 1.3x faster than with a branch per candidate; Domain::minimum_image
  // instead of the shift below, 1.25x slower.
  template <class G>
  void filter(const std::vector<std::uint32_t>& neighbours, std::size_t i, std::size_t first,
              std::size_t stop, G&& g) const {
    constexpr int chunk = 32;
    std::uint32_t hit_j[chunk];
    Vec<D> hit_dx[chunk];
    const Vec<D> pi = current_[i];
    for (std::size_t k = first; k != stop;) {
      int hits = 0;
      for (int c = 0; c < chunk && k != stop; ++c, ++k) {
        const std::uint32_t entry = neighbours[k];
        const std::uint32_t j = entry & ~needs_image;
        Vec<D> dx = current_[j] - pi;
        if (entry & needs_image)  // points differ by less than L + skin: one shift
          for (int d = 0; d < D; ++d) {
            const int shift =
                static_cast<int>(dx[d] > half_[d]) - static_cast<int>(dx[d] < -half_[d]);
            dx[d] -= length_[d] * shift;
          }
        hit_j[hits] = j;
        hit_dx[hits] = dx;
        hits += static_cast<int>(squared_norm(dx) <= squared_radius_);
      }
      for (int h = 0; h < hits; ++h) g(std::size_t{hit_j[h]}, hit_dx[h]);
    }
  }

  // filter on vectors, into batch, for list entries first .. stop-1: of
  // point i alone (one_point: its position broadcast), or of any points (a
  // vector of owners loaded, their positions gathered). A vector of entries
  // loaded, the mark stripped, j's positions gathered from current_ (Vec<D>
  // is D packed doubles), dx and its image shift computed as filter does,
  // lane by lane (the same operations in the same order, so the same bits),
  // then PairBatch::append_pairs keeps the hits. The shift is one
  // subtraction of length, -length or +0, which is filter's dx - length *
  // shift exactly. neighbours_ and owner_ are padded by a vector, so loads
  // past stop stay inside them (those lanes are dropped).
  template <bool one_point>
  void filter_run(simd::PairBatch<D>& batch, std::size_t i, std::size_t first,
                  std::size_t stop) const {
    namespace hn = simd::hn;
    const simd::Real d;
    const simd::Index du;
    const hn::RebindToSigned<simd::Real> di;
    const hn::Rebind<std::uint32_t, simd::Real> d32;
    static_assert(sizeof(Vec<D>) == D * sizeof(double), "current_ is gathered as D doubles apiece");
    const double* const x = reinterpret_cast<const double*>(current_.data());
    std::array<hn::Vec<simd::Real>, D> pi, length, half, below;
    for (int k = 0; k < D; ++k) {
      pi[k] = hn::Set(d, one_point ? current_[i][k] : 0.0);
      length[k] = hn::Set(d, length_[k]);
      half[k] = hn::Set(d, half_[k]);
      below[k] = hn::Set(d, -half_[k]);
    }
    const auto mark = hn::Set(du, std::uint64_t{needs_image});
    const auto i_lanes = hn::Set(du, static_cast<std::uint64_t>(i));
    const auto times_d = [&](hn::Vec<simd::Index> index) {  // where its coordinates start
      auto at = hn::BitCast(di, index);
      for (int c = 1; c < D; ++c) at = hn::Add(at, hn::BitCast(di, index));
      return at;
    };
    const auto load = [&](std::size_t k, std::array<hn::Vec<simd::Real>, D>& dx,
                          hn::Vec<simd::Index>& owner) {
      const auto entry = hn::PromoteTo(du, hn::LoadU(d32, neighbours_.data() + k));
      owner = one_point ? i_lanes : hn::PromoteTo(du, hn::LoadU(d32, owner_.data() + k));
      const auto j = hn::AndNot(mark, entry);
      const auto marked = hn::RebindMask(d, hn::Eq(hn::And(entry, mark), mark));
      const auto at_i = times_d(owner), at_j = times_d(j);
      for (int c = 0; c < D; ++c) {
        const auto from = one_point ? pi[c] : hn::GatherIndex(d, x + c, at_i);
        const auto delta = hn::Sub(hn::GatherIndex(d, x + c, at_j), from);
        const auto up = hn::And(marked, hn::Gt(delta, half[c]));
        const auto down = hn::And(marked, hn::Lt(delta, below[c]));
        const auto shift =
            hn::IfThenElse(up, length[c], hn::IfThenElseZero(down, hn::Neg(length[c])));
        dx[c] = hn::Sub(delta, shift);
      }
      return j;
    };
    if constexpr (one_point)  // every lane's i is i: stored without a compress
      batch.append_near(i, first, stop, squared_radius_,
                        [&](std::size_t k, std::array<hn::Vec<simd::Real>, D>& dx) {
                          hn::Vec<simd::Index> owner;
                          return load(k, dx, owner);
                        });
    else
      batch.append_pairs(first, stop, squared_radius_, load);
  }

  // Blocks of particles for the parallel passes: each block's result depends on
  // the block alone, so nothing depends on the thread count.
  static constexpr std::size_t block_size = 2048;
  static std::size_t blocks_of(std::size_t n) { return (n + block_size - 1) / block_size; }

  // body(b, first, stop) for each block b of particles first .. stop-1 of n, in parallel.
  template <class Body>
  static void for_each_block(std::size_t n, Body&& body) {
    parallel_for(blocks_of(n), LoopWork::blocks, [&](std::size_t b) {
      body(b, b * block_size, std::min(n, (b + 1) * block_size));
    });
  }

  // Block by block: first a pass without branches, one shift per periodic
  // component (length_ 0 and half_ infinite elsewhere: no shift), which
  // vectorises; only a block it cannot clear (a particle moved too far, a
  // displacement beyond the one-shift range, a NaN) is measured exactly, by
  // Domain::minimum_image. At skin 0 the check was 8% of the seed update.
  template <class T>
  bool moved_more_than_half_skin(const std::vector<Vec<D, T>>& positions) {
    const double limit = 0.25 * skin_ * skin_;
    const std::size_t n = positions.size();
    moved_.assign(blocks_of(n), 0);
    for_each_block(n, [&](std::size_t b, std::size_t first, std::size_t stop) {
      static_assert(sizeof(Vec<D, T>) == D * sizeof(T), "positions are read as D numbers apiece");
      const T* const p = reinterpret_cast<const T*>(positions.data());
      const double* const q = reinterpret_cast<const double*>(at_build_.data());
      long unclear = 0;  // a NaN displacement makes r2 NaN, which is unclear too
      for (std::size_t i = first; i < stop; ++i) {
        double r2 = 0;
        for (int k = 0; k < D; ++k) {
          const double d = static_cast<double>(p[D * i + k]) - q[D * i + k];
          const double shift = d > half_[k] ? length_[k] : d < -half_[k] ? -length_[k] : 0.0;
          const double image = d - shift;
          unclear |= static_cast<long>(std::abs(image) > half_[k]);
          r2 += image * image;
        }
        unclear |= static_cast<long>(!(r2 <= limit));
      }
      if (!unclear) return;
      for (std::size_t i = first; i < stop; ++i)
        if (!(squared_norm(domain_.minimum_image(widen(positions[i]) - at_build_[i])) <= limit)) {
          moved_[b] = 1;  // also for NaN
          return;
        }
    });
    return std::find(moved_.begin(), moved_.end(), 1) != moved_.end();
  }

  template <class Set>
  void build(const Domain<D>& domain, double radius, Set& set) {
    check_search_arguments(domain, radius);  // radius + skin > 0 would pass a negative radius
    NeighbourSearch<D> search;
    const double build_radius = radius + skin_ + round_off_guard(domain, radius);
    search.build(domain, build_radius, set);
    // After the reorder: by the indices the lists use. Widened, if stored as float.
    at_build_.assign(set.positions().begin(), set.positions().end());
    const std::size_t n = at_build_.size();
    if (n >= needs_image)
      throw std::length_error("partc: VerletList: more than 2^31 - 1 particles");
    for (int k = 0; k < D; ++k) {  // non-periodic: a shift of 0 * 0 when |d| > infinity, i.e. never
      length_[k] = domain.periodic[k] ? domain.hi[k] - domain.lo[k] : 0.0;
      half_[k] = domain.periodic[k] ? 0.5 * length_[k] : std::numeric_limits<double>::infinity();
    }
    // Each pair once, from its lower index (the full lists are made from these).
    start_.resize(n + 1);
    start_[0] = 0;
    const bool images = BruteForce<D>::needs_all_images(domain, build_radius);
    unmarked_pairs_direct_ = true;
    for (int k = 0; k < D; ++k)
      unmarked_pairs_direct_ = unmarked_pairs_direct_ && !(build_radius + skin_ >= half_[k]);
    if (search.kind() == NeighbourSearch<D>::Kind::cell_list && !images)
      lists_from_batches(search, n);
    else
      lists_from_queries(search, n, images);
    block_scratch_.resize(blocks_of(n));
    for_each_block(n, [&](std::size_t b, std::size_t first_i, std::size_t stop_i) {
      for (std::size_t i = first_i; i < stop_i; ++i)
        mark_pairs_needing_images(domain, build_radius, i, entry(start_[i]), entry(start_[i + 1]),
                                  block_scratch_[b]);
    });
    // The full lists first: make_slabs reorders half lists' entries.
    if (pairs_ != VerletPairs::half) make_full_lists();
    if (pairs_ == VerletPairs::full) {
      neighbours_ = {};
      start_ = {};
    } else {
      make_slabs(search.pair_slabs());
    }
    domain_ = domain;
    radius_ = radius;
    squared_radius_ = radius * radius * (1 + 1e-12);
    ++rebuild_count_;
  }

  std::vector<std::uint32_t>::iterator entry(std::size_t k) {
    return neighbours_.begin() + static_cast<std::ptrdiff_t>(k);
  }

  // start_ and neighbours_ from a query per particle (for_each_near_after),
  // block by block in parallel, then joined in block order. With images
  // (radius + skin over half a periodic length) j once, whatever its images:
  // queries take the nearest.
  void lists_from_queries(const NeighbourSearch<D>& search, std::size_t n, bool images) {
    block_lists_.resize(blocks_of(n));
    for_each_block(n, [&](std::size_t b, std::size_t first_i, std::size_t stop_i) {
      std::vector<std::uint32_t>& list = block_lists_[b];
      list.clear();
      for (std::size_t i = first_i; i < stop_i; ++i) {
        const std::size_t first = list.size();
        search.for_each_near_after(i, [&](std::size_t j, const Vec<D>&) {
          list.push_back(static_cast<std::uint32_t>(j));
        });
        if (images) {
          std::sort(list.begin() + static_cast<std::ptrdiff_t>(first), list.end());
          list.erase(std::unique(list.begin() + static_cast<std::ptrdiff_t>(first), list.end()),
                     list.end());
        }
        start_[i + 1] = list.size() - first;  // a count until the prefix sum below
      }
    });
    for (std::size_t i = 0; i < n; ++i) start_[i + 1] += start_[i];
    neighbours_.resize(start_[n]);
    for_each_block(n, [&](std::size_t b, std::size_t first_i, std::size_t) {
      std::copy(block_lists_[b].begin(), block_lists_[b].end(), entry(start_[first_i]));
    });
  }

  // The same lists, entry for entry, from the cell list's packed pair walk
  // (simd/pair_batches.hpp), whose candidates are filtered by vectors: its
  // pairs of i are for_each_near_after(i)'s, in its order, except that a point
  // of slab 0 gets those across the periodic edge later, in the last slab's
  // walk; both parts keep their order and make_slabs puts the second last.
  // Each slab's entries are collected on its thread, then put in place in
  // parallel. (The build's search reorders the set, so the walk's indices are
  // the set's.) Measured on LJ melt (32000 atoms, one thread, bench_lj): a
  // build 18 ms by queries (their scalar scan 22% of the whole run), 12 ms so.
  void lists_from_batches(const NeighbourSearch<D>& search, std::size_t n) {
    const SlabSchedule& slabs = search.pair_slabs();
    const std::size_t last = slabs.count() - 1;
    // Points below this have pairs in the last slab's walk too (across the edge).
    const std::size_t edge_points = last > 0 ? slabs.start(1) : 0;
    slab_lists_.resize(slabs.count());
    for (auto& list : slab_lists_) list.clear();
    own_count_.assign(n, 0);
    edge_count_.assign(edge_points, 0);
    search.for_each_pair_batch(false, [&](const simd::PairBatch<D>& batch) {
      std::vector<std::uint32_t>& list = slab_lists_[batch.slab()];
      const bool last_slab = batch.slab() == last;
      for (std::size_t k = 0; k < batch.count(); ++k) {
        const std::size_t i = batch.i()[k];
        list.push_back(static_cast<std::uint32_t>(batch.j()[k]));
        ++(last_slab && i < edge_points ? edge_count_[i] : own_count_[i]);
      }
    });
    for (std::size_t i = 0; i < n; ++i)
      start_[i + 1] = start_[i] + own_count_[i] + (i < edge_points ? edge_count_[i] : 0);
    neighbours_.resize(start_[n]);
    parallel_for(slabs.count(), LoopWork::blocks, [&](std::size_t a) {
      auto from = slab_lists_[a].cbegin();
      const auto place = [&](std::size_t count, std::size_t to) {
        std::copy(from, from + static_cast<std::ptrdiff_t>(count), entry(to));
        from += static_cast<std::ptrdiff_t>(count);
      };
      for (std::size_t i = slabs.start(a); i < slabs.start(a + 1); ++i)
        place(own_count_[i], start_[i]);
      if (a == last)
        for (std::size_t i = 0; i < edge_points; ++i)
          place(edge_count_[i], start_[i] + own_count_[i]);
    });
  }

  // i's entries: those whose pair needs a periodic image get the top bit (all
  // of them unless unmarked_pairs_direct_) and go after the others, in order.
  // scratch: the block's, for the marked ones (stable_partition would allocate).
  template <class It>
  void mark_pairs_needing_images(const Domain<D>& domain, double reach, std::size_t i, It first,
                                 It stop, std::vector<std::uint32_t>& scratch) const {
    if (!unmarked_pairs_direct_) {
      for (It e = first; e != stop; ++e) *e |= needs_image;
      return;
    }
    // Farther than the build's reach from every periodic face: j's nearest
    // image is j itself, so no pair of i is across an edge.
    bool interior = true;
    for (int k = 0; k < D; ++k)
      interior = interior && (!domain.periodic[k] || (at_build_[i][k] - domain.lo[k] > reach &&
                                                      domain.hi[k] - at_build_[i][k] > reach));
    if (interior) return;
    scratch.clear();
    It kept = first;
    for (It e = first; e != stop; ++e) {
      bool across = false;
      for (int k = 0; k < D; ++k) {
        const double d = at_build_[*e][k] - at_build_[i][k];
        across = across || d > half_[k] || d < -half_[k];
      }
      if (across)
        scratch.push_back(*e | needs_image);
      else
        *kept++ = *e;
    }
    std::copy(scratch.begin(), scratch.end(), kept);
  }

  // From the half lists: the list of k is the i < k that have k (ascending i),
  // k itself, then k's own half list - a fixed order.
  void make_full_lists() {
    const std::size_t n = start_.size() - 1;
    std::vector<std::size_t>& full_start = full_start_;
    full_start.assign(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
      full_start[i + 1] += 1 + (start_[i + 1] - start_[i]);
      for (std::size_t k = start_[i]; k < start_[i + 1]; ++k)
        ++full_start[(neighbours_[k] & ~needs_image) + 1];
    }
    for (std::size_t i = 0; i < n; ++i) full_start[i + 1] += full_start[i];
    std::vector<std::uint32_t>& full = full_neighbours_;
    full.resize(full_start[n]);
    std::vector<std::size_t> cursor(full_start.begin(), full_start.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t k = start_[i]; k < start_[i + 1]; ++k)
        full[cursor[neighbours_[k] & ~needs_image]++] =
            static_cast<std::uint32_t>(i) | (neighbours_[k] & needs_image);
    for (std::size_t i = 0; i < n; ++i) {
      full[cursor[i]++] = static_cast<std::uint32_t>(i);
      std::copy(neighbours_.begin() + static_cast<std::ptrdiff_t>(start_[i]),
                neighbours_.begin() + static_cast<std::ptrdiff_t>(start_[i + 1]),
                full.begin() + static_cast<std::ptrdiff_t>(cursor[i]));
    }
  }

  // The slabs of for_each_pair: the build search's (NeighbourSearch::pair_slabs),
  // which found every list entry j > i and checked that all such pairs obey
  // the slab rule. across_: per particle, where its pairs across the periodic
  // edge (slab 0 to the last slab) begin, moved to the end of its list.
  // Then owner_ (whose list each entry is in) and a vector of padding after
  // both, for filter_run.
  void make_slabs(const SlabSchedule& slabs) {
    slabs_ = slabs;
    across_.assign(start_.begin() + 1, start_.end());
    const std::size_t n = start_.size() - 1;
    neighbours_.resize(start_[n] + simd::lanes(), 0);
    owner_.resize(start_[n] + simd::lanes());
    std::fill(owner_.begin() + static_cast<std::ptrdiff_t>(start_[n]), owner_.end(), 0);
    for_each_block(n, [&](std::size_t, std::size_t first_i, std::size_t stop_i) {
      for (std::size_t i = first_i; i < stop_i; ++i)
        std::fill(owner_.begin() + static_cast<std::ptrdiff_t>(start_[i]),
                  owner_.begin() + static_cast<std::ptrdiff_t>(start_[i + 1]),
                  static_cast<std::uint32_t>(i));
    });
    if (slabs.count() == 1) return;
    const std::size_t edge = slabs.start(slabs.count() - 1);
    for (std::size_t i = slabs.start(0); i < slabs.start(1); ++i) {
      const auto first = neighbours_.begin() + static_cast<std::ptrdiff_t>(start_[i]);
      const auto stop = neighbours_.begin() + static_cast<std::ptrdiff_t>(start_[i + 1]);
      const auto across = std::stable_partition(
          first, stop, [&](std::uint32_t e) { return (e & ~needs_image) < edge; });
      across_[i] = start_[i] + static_cast<std::size_t>(across - first);
    }
  }

  // The search measures a pair with the query point shifted by a box length, the
  // queries and displacements subtract stored positions first: the results can
  // differ by a few ulps of the radius and of the periodic coordinates (up to
  // |lo|, |hi|; more for positions far outside the box). The invariant leaves
  // the contract's 1e-12 of skin for that, nothing when skin = 0, so the build
  // reaches 1e-12 of those magnitudes further: thousands of ulps, and a
  // negligible number of extra candidates.
  static double round_off_guard(const Domain<D>& domain, double radius) {
    double magnitude = radius;
    for (int k = 0; k < D; ++k)
      if (domain.periodic[k])
        magnitude = std::max({magnitude, std::abs(domain.lo[k]), std::abs(domain.hi[k])});
    return 1e-12 * magnitude;
  }

  // An entry's top bit: its pair needs the periodic minimum image.
  static constexpr std::uint32_t needs_image = std::uint32_t{1} << 31;

  double skin_;
  VerletPairs pairs_;
  bool unmarked_pairs_direct_ = false;  // see the top of the file
  std::size_t rebuild_count_ = 0;
  std::size_t walk_count_ = 0;
  Domain<D> domain_{};
  double radius_ = 0.0;
  double squared_radius_ = 0.0;
  Vec<D> length_{}, half_{};        // per dimension, for the queries' image shift
  std::vector<Vec<D>> at_build_;    // positions at the last build, after its reorder
  std::vector<Vec<D>> current_;     // positions at the last update (see the top): walked
  std::vector<std::size_t> start_;  // half: i's list is neighbours_[start_[i] .. start_[i+1]-1]
  std::vector<std::uint32_t> neighbours_;  // half: padded by a vector (filter_run)
  std::vector<std::uint32_t> owner_;       // half: the i whose list holds each entry; padded
  std::vector<std::size_t> full_start_;    // full: as start_ and neighbours_
  std::vector<std::uint32_t> full_neighbours_;
  std::vector<std::vector<std::uint32_t>> block_lists_;    // build scratch, kept for its memory
  std::vector<std::vector<std::uint32_t>> block_scratch_;  // likewise
  std::vector<std::vector<std::uint32_t>> slab_lists_;     // likewise, lists_from_batches's
  std::vector<std::size_t> own_count_, edge_count_;        // likewise
  std::vector<char> moved_;                                // update scratch: per block
  SlabSchedule slabs_;               // half: the parallel schedule of for_each_pair
  std::vector<std::size_t> across_;  // half: i's pairs across the periodic edge: across_[i] ..
  mutable std::vector<simd::PairBatch<D>> batches_;  // for_each_pair_batch's: one per slab
};

}  // namespace partc
