// partc/simd/pair_batches.hpp: the pair walk of an OrderedCellList, each
// pair once, with the pairs packed into PairBatches for vector arithmetic: the
// term of a sum is then computed on full vectors of pairs instead of one pair
// at a time.
//
// Why packed: about 1/3 of a cell list's candidates in 2D (1/6 in 3D) are
// within reach, unpredictably, so filtering and computing in one loop wastes
// most lanes or branches; filtering first (a compress-store of the hits) and
// computing on the packed buffer keeps every lane busy. The hand-written AVX2
// kernel of tests/bench/floor (compact_simd) does the same per particle with a
// permutation table, as Compressor (compress.hpp) does. Why several points a
// batch: taking each pair once leaves a point about 5 pairs in 2D, under one
// vector of 8 doubles; a batch of consecutive points fills its vectors, and
// both ends of a pair then take their terms in the scatter after the vector
// loop (i's += and j's -=), which also keeps that loop free of stores to
// particles.
//
// Contract: for_each_pair(cells, with_self, f) calls f(batch) for batches of
// the pairs that cells.for_each_pair gives, in its order, threads and slabs
// (slab_schedule.hpp): each point's pairs are consecutive entries (i, j, dx,
// r2) of one batch, in that walk's order and with its dx bit for bit, the
// pair (i, i) (dx 0) first when with_self, else left out. A batch never
// spans two slabs, so results are as independent of the thread count as
// for_each_pair's. append_query packs one point's whole query the same way
// (NeighbourSearch::for_each_near_batch's packed queries).
//
// Surprises:
// - Entries count() .. padded() - 1 are padding (i and j the batch's last i,
//   dx = 0, r2 = 1): a vector loop may read them, and masks them out. The
//   padding covers a vector of floats too (Float: twice the lanes),
//   for a loop to padded(hn::Lanes(Float())).
// - In exact mode (a periodic dimension with < 3 cells) the cell list has no
//   runs: the batch is filled from its scalar scan instead.
// - build copies the cell list's sorted points into per-dimension arrays
//   (SoA), which vectors load directly; rebuild after every cells.build.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <tuple>
#include <vector>

#include "partc/parallel.hpp"
#include "partc/search/ordered_cell_list.hpp"
#include "partc/simd/compress.hpp"
#include "partc/simd/float_lanes.hpp"  // for the batches' readers: generated vector terms
#include "partc/simd/highway.hpp"
#include "partc/vec.hpp"

namespace partc::simd {

// Pairs of consecutive points, packed, structure of arrays. columns(n) gives
// the caller n more arrays of the same length (a term's components kept for
// the scatter, say), of doubles or, columns<float>(n), of floats.
template <int D>
class PairBatch {
 public:
  std::size_t count() const { return count_; }
  // count() rounded up to whole vectors of `vector_lanes` (at most those of Float).
  std::size_t padded(std::size_t vector_lanes = lanes()) const {
    return (count_ + vector_lanes - 1) / vector_lanes * vector_lanes;
  }
  const std::uint64_t* i() const { return i_.data(); }
  const std::uint64_t* j() const { return j_.data(); }
  const double* dx(int d) const { return dx_[d].data(); }
  const double* r2() const { return r2_.data(); }
  template <class T = double>
  T* column(std::size_t c) {
    return std::get<Columns<T>>(columns_)[c].data();
  }
  // The slab of the walk whose pairs the batch holds (0 for a serial walk):
  // one slab's batches are handed over on one thread, in the walk's order.
  std::size_t slab() const { return slab_; }
  void set_slab(std::size_t a) { slab_ = a; }
  // Whether the batch holds each pair once (a pair walk: j takes its term
  // too) or particles' whole neighbourhoods (packed queries: i alone).
  bool each_pair_once() const { return each_pair_once_; }
  void set_each_pair_once(bool once) { each_pair_once_ = once; }
  template <class T = double>
  void columns(std::size_t n) {
    Columns<T>& of_t = std::get<Columns<T>>(columns_);
    if (of_t.size() < n) of_t.resize(n);
    for (auto& column : of_t) column.resize(j_.size());
  }

  void clear() { count_ = 0; }
  // i and j (padding included) renamed: k becomes name[k].
  void renumber(const std::vector<std::size_t>& name) {
    for (std::size_t k = 0; k < count_ + padding(); ++k) {
      i_[k] = name[i_[k]];
      j_[k] = name[j_[k]];
    }
  }
  // Room for `candidates` more entries, padding and a vector's overrun.
  void reserve(std::size_t candidates) {
    const std::size_t size = count_ + candidates + 2 * lanes();
    if (j_.size() >= size) return;
    const std::size_t grown = std::max(size, 2 * j_.size());
    i_.resize(grown);
    j_.resize(grown);
    for (auto& d : dx_) d.resize(grown);
    r2_.resize(grown);
    for (auto& column : std::get<Columns<double>>(columns_)) column.resize(grown);
    for (auto& column : std::get<Columns<float>>(columns_)) column.resize(grown);
  }
  void push(std::size_t i, std::size_t j, const Vec<D>& dx) {
    reserve(1);
    i_[count_] = i;
    j_[count_] = j;
    for (int d = 0; d < D; ++d) dx_[d][count_] = dx[d];
    r2_[count_++] = squared_norm(dx);
  }

  // Point i's candidates first .. stop-1 of coordinate arrays x, seen from
  // qs: the ones with |dx|^2 <= squared_reach appended, by compress-stores.
  HWY_INLINE void append_near(std::size_t i, const std::array<const double*, D>& x,
                              std::size_t first, std::size_t stop, const Vec<D>& qs,
                              double squared_reach) {
    const Real d;
    const Index du;
    std::array<hn::Vec<Real>, D> q;
    for (int k = 0; k < D; ++k) q[k] = hn::Set(d, qs[k]);
    // j's lanes as first + iota + a step: GCC builds Iota(du, j) through the stack.
    auto j_lanes = hn::Add(hn::Iota(du, 0), hn::Set(du, static_cast<std::uint64_t>(first)));
    const auto step = hn::Set(du, static_cast<std::uint64_t>(lanes()));
    append_near(i, first, stop, squared_reach,
                [&](std::size_t j, std::array<hn::Vec<Real>, D>& dx) {
                  for (int k = 0; k < D; ++k) dx[k] = hn::Sub(hn::LoadU(d, x[k] + j), q[k]);
                  const auto loaded = j_lanes;
                  j_lanes = hn::Add(j_lanes, step);
                  return loaded;
                });
  }

  // Point i's candidates first .. stop-1, a vector at a time: load(k, dx)
  // returns the j of candidates k .. k + lanes() - 1 and sets their dx (lanes
  // from stop on are dropped, whatever they hold); those with |dx|^2 <=
  // squared_reach are appended, by compress-stores.
  template <class Load>
  HWY_INLINE void append_near(std::size_t i, std::size_t first, std::size_t stop,
                              double squared_reach, Load&& load) {
    const auto i_lanes = hn::Set(Index(), static_cast<std::uint64_t>(i));
    append_hits<true>(first, stop, squared_reach,
                      [&](std::size_t k, std::array<hn::Vec<Real>, D>& dx, hn::Vec<Index>& i_of) {
                        i_of = i_lanes;
                        return load(k, dx);
                      });
  }

  // As append_near, for candidate pairs of several points: load(k, dx, i)
  // also sets the i of each lane.
  template <class Load>
  HWY_INLINE void append_pairs(std::size_t first, std::size_t stop, double squared_reach,
                               Load&& load) {
    append_hits<false>(first, stop, squared_reach, load);
  }

  // f(*this), then clear(), once the batch holds batch_vectors vectors of
  // pairs; hand_over_rest: once it holds any. The walks call the one after
  // each point and the other at the end of a slab, so that a point's pairs
  // stay in one batch and a batch in one slab.
  template <class F>
  void hand_over_if_full(F& f) {
    if (count_ >= batch_vectors * lanes()) hand_over(f);
  }
  template <class F>
  void hand_over_rest(F& f) {
    if (count_ > 0) hand_over(f);
  }

  // A batch is handed over once it holds this many vectors of pairs: enough
  // to amortise the call, few enough to stay in L1 with its columns.
  static constexpr std::size_t batch_vectors = 8;

  // Pads to whole vectors of floats (and so of doubles) with harmless
  // entries: i and j the last entry's i, dx = 0, r2 = 1.
  void finish() {
    const std::size_t last = count_ > 0 ? i_[count_ - 1] : 0;
    const std::size_t end = count_ + padding();
    std::fill(i_.begin() + count_, i_.begin() + end, last);
    std::fill(j_.begin() + count_, j_.begin() + end, last);
    for (auto& dx : dx_) std::fill(dx.begin() + count_, dx.begin() + end, 0.0);
    std::fill(r2_.begin() + count_, r2_.begin() + end, 1.0);
  }

 private:
  template <class T>
  using Columns = std::vector<std::vector<T>>;

  // The filter of append_near and append_pairs; one_i: every lane has the
  // same i, stored without a compress.
  template <bool one_i, class Load>
  HWY_INLINE void append_hits(std::size_t first, std::size_t stop, double squared_reach,
                              Load&& load) {
    reserve(stop - first);
    const Real d;
    const Index du;
    const std::size_t n = lanes();
    const auto reach = hn::Set(d, squared_reach);
    // Locals, not members: a store through a double* could alias them, and
    // reloading them after every store costs as much as the filter.
    std::size_t count = count_;
    std::uint64_t* i_out = i_.data();
    std::uint64_t* j_out = j_.data();
    std::array<double*, D> dx_out;
    for (int k = 0; k < D; ++k) dx_out[k] = dx_[k].data();
    double* r2_out = r2_.data();
    for (std::size_t j = first; j < stop; j += n) {
      std::array<hn::Vec<Real>, D> dx;
      hn::Vec<Index> i_lanes;
      const hn::Vec<Index> j_lanes = load(j, dx, i_lanes);
      // Summed in dimension order, as squared_norm does: the same hits as the scalar scan.
      auto r2 = hn::Mul(dx[0], dx[0]);
      for (int k = 1; k < D; ++k) r2 = hn::Add(r2, hn::Mul(dx[k], dx[k]));
      auto hit = hn::Le(r2, reach);
      if (j + n > stop) hit = hn::And(hit, hn::FirstN(d, stop - j));
      const Compressor compress(hit);
      hn::StoreU(one_i ? i_lanes : compress(i_lanes), du, i_out + count);
      hn::StoreU(compress(j_lanes), du, j_out + count);
      for (int k = 0; k < D; ++k) hn::StoreU(compress(dx[k]), d, dx_out[k] + count);
      hn::StoreU(compress(r2), d, r2_out + count);
      count += compress.count();
    }
    count_ = count;
  }
  // Entries of padding after count(): a vector of floats (reserve keeps
  // 2 * lanes() spare, which holds it).
  static std::size_t padding() { return hn::Lanes(Float()); }

  template <class F>
  void hand_over(F& f) {
    finish();
    f(*this);
    clear();
  }

  std::size_t count_ = 0;
  std::size_t slab_ = 0;
  bool each_pair_once_ = true;
  std::vector<std::uint64_t> i_, j_;
  std::array<std::vector<double>, D> dx_;
  std::vector<double> r2_;
  std::tuple<Columns<double>, Columns<float>> columns_;
};

template <int D>
class PairBatches {
 public:
  // After every cells.build: the sorted points as coordinate arrays.
  void build(const OrderedCellList<D>& cells, std::size_t n) {
    for (int d = 0; d < D; ++d)
      x_[d].assign(n + lanes(), 0.0);  // padded: a vector load may overrun the last run
    parallel_for(n, LoopWork::light, [&](std::size_t k) {
      for (int d = 0; d < D; ++d) x_[d][k] = cells.point(k)[d];
    });
    batches_.resize(cells.pair_slabs().count());
    for (std::size_t a = 0; a < batches_.size(); ++a) batches_[a].set_slab(a);
  }

  // f(batch) for the pairs, as described at the top.
  template <class F>
  void for_each_pair(const OrderedCellList<D>& cells, bool with_self, F&& f) {
    std::array<const double*, D> x;
    for (int d = 0; d < D; ++d) x[d] = x_[d].data();
    const double squared_reach = cells.squared_reach();
    cells.for_each_pair_span(
        [&](std::size_t slab, std::size_t i, std::size_t from, std::size_t until, bool self) {
          PairBatch<D>& batch = batches_[slab];
          if (self && with_self) batch.push(i, i, Vec<D>::zero());
          const bool by_runs = cells.for_each_run_between(
              i, from, until, [&](std::size_t first, std::size_t stop, const Vec<D>& qs) {
                batch.append_near(i, x, first, stop, qs, squared_reach);
              });
          if (!by_runs)
            cells.for_each_near_between(
                i, from, until, [&](std::size_t j, const Vec<D>& dx) { batch.push(i, j, dx); });
          batch.hand_over_if_full(f);
        },
        [&](std::size_t slab) { batches_[slab].hand_over_rest(f); });
  }

  // Point k's query, cells.for_each_near(k), packed into batch: its runs of
  // candidates filtered by compress-stores as for_each_pair's are, so with
  // the scan's neighbours, order and dx bit for bit; (k, k) itself left out
  // unless with_self (it lies in the unshifted run of k's own cell: with
  // shifts, periodic sides have 3 cells or more, so no image of k is a
  // candidate). Only where the cell list has runs (cells.shifts_suffice(),
  // not its exact mode).
  void append_query(const OrderedCellList<D>& cells, std::size_t k, bool with_self,
                    PairBatch<D>& batch) const {
    std::array<const double*, D> x;
    for (int d = 0; d < D; ++d) x[d] = x_[d].data();
    const double squared_reach = cells.squared_reach();
    cells.for_each_run_between(
        k, 0, cells.order().size(), [&](std::size_t first, std::size_t stop, const Vec<D>& qs) {
          if (with_self || k < first || k >= stop)
            return batch.append_near(k, x, first, stop, qs, squared_reach);
          batch.append_near(k, x, first, k, qs, squared_reach);
          batch.append_near(k, x, k + 1, stop, qs, squared_reach);
        });
  }

 private:
  std::array<std::vector<double>, D> x_;
  std::vector<PairBatch<D>> batches_;  // one per slab: a slab runs on one thread
};

}  // namespace partc::simd
