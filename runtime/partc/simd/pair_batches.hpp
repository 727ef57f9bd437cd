// partc/simd/pair_batches.hpp: the pair walk of an OrderedCellList, each
// pair once, with each point's pairs packed into a PairBatch for vector
// arithmetic: the term of a sum is then computed on full vectors of pairs
// instead of one pair at a time.
//
// Why packed: about 1/3 of a cell list's candidates in 2D (1/6 in 3D) are
// within reach, unpredictably, so filtering and computing in one loop wastes
// most lanes or branches; filtering first (a compress-store of the hits) and
// computing on the packed buffer keeps every lane busy. The hand-written AVX2
// kernel of tests/bench/floor (compact_simd) does the same per particle with a
// permutation table, as Compressor (compress.hpp) does.
//
// Contract: for_each_pair(cells, f) calls f(i, batch) in the order and
// threads of cells.for_each_pair (slab_schedule.hpp); the batch holds the
// same pairs that for_each_pair gives i, in the same order, with the same dx
// bit for bit: (i, i) first (dx 0) where that walk gives it, then each j > i
// within the cell list's reach. Results are as independent of the thread
// count as for_each_pair's.
//
// Surprises:
// - Entries count() .. padded() - 1 are padding (j = i, dx = 0, r2 = 1): a
//   vector loop may read them, and masks its sums to the first count().
// - In exact mode (a periodic dimension with < 3 cells) the cell list has no
//   runs: the batch is filled from its scalar scan instead.
// - build copies the cell list's sorted points into per-dimension arrays
//   (SoA), which vectors load directly; rebuild after every cells.build.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "partc/ordered_cell_list.hpp"
#include "partc/simd/compress.hpp"
#include "partc/simd/highway.hpp"
#include "partc/vec.hpp"

namespace partc::simd {

// One point's pairs, packed, structure of arrays. columns(n) gives the caller
// n more arrays of the same length (a term's components kept for the
// scatter to j, say).
template <int D>
class PairBatch {
 public:
  std::size_t count() const { return count_; }
  // count() rounded up to whole vectors.
  std::size_t padded() const { return (count_ + lanes() - 1) / lanes() * lanes(); }
  const std::uint64_t* j() const { return j_.data(); }
  const double* dx(int d) const { return dx_[d].data(); }
  const double* r2() const { return r2_.data(); }
  double* column(std::size_t c) { return columns_[c].data(); }
  void columns(std::size_t n) {
    if (columns_.size() < n) columns_.resize(n);
    for (auto& column : columns_) column.resize(j_.size());
  }

  // Empties the batch, with room for `candidates` more entries and padding.
  void start(std::size_t candidates) {
    count_ = 0;
    reserve(candidates);
  }
  void reserve(std::size_t candidates) {
    const std::size_t size = count_ + candidates + 2 * lanes();
    if (j_.size() >= size) return;
    j_.resize(size);
    for (auto& d : dx_) d.resize(size);
    r2_.resize(size);
    for (auto& column : columns_) column.resize(size);
  }
  void push(std::size_t j, const Vec<D>& dx) {
    reserve(1);
    j_[count_] = j;
    double r2 = 0;
    for (int d = 0; d < D; ++d) {
      dx_[d][count_] = dx[d];
      r2 += dx[d] * dx[d];
    }
    r2_[count_++] = r2;
  }

  // The candidates first .. stop-1 of coordinate arrays x seen from qs: the
  // ones with |dx|^2 <= squared_reach appended, by compress-stores.
  HWY_INLINE void append_near(const std::array<const double*, D>& x, std::size_t first,
                              std::size_t stop, const Vec<D>& qs, double squared_reach) {
    reserve(stop - first);
    const Real d;
    const Index du;
    const std::size_t n = lanes();
    const auto reach = hn::Set(d, squared_reach);
    std::array<hn::Vec<Real>, D> q;
    for (int k = 0; k < D; ++k) q[k] = hn::Set(d, qs[k]);
    for (std::size_t j = first; j < stop; j += n) {
      std::array<hn::Vec<Real>, D> dx;
      for (int k = 0; k < D; ++k) dx[k] = hn::Sub(hn::LoadU(d, x[k] + j), q[k]);
      // Summed in dimension order, as squared_norm does: the same hits as the scalar scan.
      auto r2 = hn::Mul(dx[0], dx[0]);
      for (int k = 1; k < D; ++k) r2 = hn::Add(r2, hn::Mul(dx[k], dx[k]));
      auto hit = hn::Le(r2, reach);
      if (j + n > stop) hit = hn::And(hit, hn::FirstN(d, stop - j));
      const Compressor compress(hit);
      hn::StoreU(compress(hn::Iota(du, static_cast<std::uint64_t>(j))), du, j_.data() + count_);
      for (int k = 0; k < D; ++k) hn::StoreU(compress(dx[k]), d, dx_[k].data() + count_);
      hn::StoreU(compress(r2), d, r2_.data() + count_);
      count_ += compress.count();
    }
  }

  // Pads to whole vectors (and one more, for loads that overrun) with
  // harmless entries: j = i, dx = 0, r2 = 1.
  void finish(std::size_t i) {
    const Real d;
    hn::StoreU(hn::Set(Index(), i), Index(), j_.data() + count_);
    for (auto& dx : dx_) hn::StoreU(hn::Zero(d), d, dx.data() + count_);
    hn::StoreU(hn::Set(d, 1.0), d, r2_.data() + count_);
  }

 private:
  std::size_t count_ = 0;
  std::vector<std::uint64_t> j_;
  std::array<std::vector<double>, D> dx_;
  std::vector<double> r2_;
  std::vector<std::vector<double>> columns_;
};

template <int D>
class PairBatches {
 public:
  // After every cells.build: the sorted points as coordinate arrays.
  void build(const OrderedCellList<D>& cells, std::size_t n) {
    for (int d = 0; d < D; ++d) {
      x_[d].assign(n + lanes(), 0.0);  // padded: a vector load may overrun the last run
      for (std::size_t k = 0; k < n; ++k) x_[d][k] = cells.point(k)[d];
    }
    batches_.resize(cells.pair_slabs().count());
  }

  // f(i, batch) for i's pairs, as described at the top.
  template <class F>
  void for_each_pair(const OrderedCellList<D>& cells, F&& f) {
    std::array<const double*, D> x;
    for (int d = 0; d < D; ++d) x[d] = x_[d].data();
    const double squared_reach = cells.squared_reach();
    cells.for_each_pair_span(
        [&](std::size_t slab, std::size_t i, std::size_t from, std::size_t until, bool self) {
          PairBatch<D>& batch = batches_[slab];
          batch.start(0);
          if (self) batch.push(i, Vec<D>::zero());
          const bool by_runs = cells.for_each_run_between(
              i, from, until, [&](std::size_t first, std::size_t stop, const Vec<D>& qs) {
                batch.append_near(x, first, stop, qs, squared_reach);
              });
          if (!by_runs)
            cells.for_each_near_between(
                i, from, until, [&](std::size_t j, const Vec<D>& dx) { batch.push(j, dx); });
          batch.finish(i);
          f(i, batch);
        });
  }

 private:
  std::array<std::vector<double>, D> x_;
  std::vector<PairBatch<D>> batches_;  // one per slab: a slab runs on one thread
};

}  // namespace partc::simd
