// partc/solve/schwarz_preconditioner.hpp: a two-level restricted Schwarz
// preconditioner for dense systems whose rows and columns are points, as an
// RBF or Kansa matrix A(i, j) = phi(|x_i - x_j|): it needs the points, a
// function giving one entry and, for its coarse level, the product A x;
// never the whole matrix.
//
//   const auto entry = [&](std::size_t i, std::size_t j) {
//     return phi(partc::norm(points[j] - points[i]));
//   };
//   partc::RestrictedSchwarz<2> schwarz(points, entry);
//   Eigen::VectorXd z = schwarz.apply(r, product);  // z ~ A^-1 r; product(x, y): y = A x
//
// Local level (restricted additive Schwarz, Cai & Sarkis 1999): the points
// are split by median cuts of the longer axis into clusters of at most
// cluster_size points. Each cluster is grown by the points nearest its
// bounding box to overlap times its size, and the block of A on the grown
// cluster is LU-factored once. Each block is solved against r on its grown
// cluster and keeps the solution on the cluster's own points only
// (restricted: the overlap shapes the answer but no point is written twice,
// so nothing depends on the order of clusters or threads).
//
// Blocks in float: the blocks are the preconditioner's memory, and in double
// N = 1e6 needed 8.7 GB. A block is LU-factored in float, its substitutions
// done in double (rounding them in float too lost 5-10% per block solve and
// cost Franke's solve 26 -> 40 iterations at N = 1e5); GMRES still iterates
// to the double residual. If a solve with the float LU misses a known answer
// by more than float_error (ill-conditioned blocks: flat kernels, where it
// may miss by 500% or give inf), that block is factored in double instead.
// Measured (bench_matrix_free_solve, Franke, eps h = 0.5): block misses 0.5%
// at N = 1e4 to 2.7% at 1e6, none in double; iterations and the answer as
// in double (17 at 1e4, 26 at 1e5; the interpolant 7e-10 apart), and the
// time; peak memory of the whole solve 847 -> 615 MB at 1e5, of the
// preconditioner alone 8.7 -> 4.7 GB at 1e6 (its setup 4.5 min there in
// float or double alike, so not the LUs: growing the clusters is
// O(N^2 / cluster_size)); Kansa
// (eps h = 0.6, N = 1e4), rows scaled: none in double, 31 iterations either
// way. At eps h = 0.3 (Franke, N = 900) every block misses by 25% or more,
// all-float GMRES does not converge, and the check puts them all in double
// (63 iterations).
//
// Coarse level (multiplicative, as Beatson, Light & Billings 2000 do for RBF
// interpolation): every coarse_stride-th point in the clusters' order (so
// spread over the domain), at most coarse_max of them; A on them is
// LU-factored once, and after the local solves their residual r - A z on
// the coarse points is solved for there and added. The local blocks capture
// the near field; without the coarse level the smooth, global part of the
// error is left to the Krylov method, and its iterations grow with the
// number of clusters (measured on Franke's multiquadric interpolation,
// eps h = 0.5, N = 1e4: 145 GMRES iterations with the local level alone, 16
// with both).
//
// The coarse cap is what limits N now, not memory: the iterations hang on
// coarse_stride, and the cap raises it beyond N = 16 coarse_max (measured,
// Franke at N = 1e5: 1491 coarse points 337 iterations, 2937 26, 5874 13).
// At N = 1e6 the cap leaves every 334th point, sparser than the 1e5 run
// that took 337; a coarse level that grows with N needs its own iterative
// (multilevel) solve, not a bigger dense LU ((N / 16)^2 entries).
//
// Costs: the split O(N log N); growing the clusters O(N^2 / cluster_size)
// distance tests; the blocks (overlap * cluster_size)^3 * 2/3 flops and
// (overlap * cluster_size)^2 floats each (at the defaults 0.6 MB per 128
// points; doubles where float fails); the coarse LU (N / coarse_stride)^3 *
// 2/3 flops; apply one product A z plus 2 (overlap * cluster_size)^2 flops
// per cluster.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <utility>
#include <vector>

#include "partc/parallel.hpp"
#include "partc/vec.hpp"

namespace partc {

struct SchwarzOptions {
  std::size_t cluster_size = 128;  // points a cluster owns, at most
  double overlap = 3.0;            // a grown cluster's points over its own
  std::size_t coarse_stride = 16;  // one coarse point per this many; 0: no coarse level
  std::size_t coarse_max = 3000;   // coarse points at most (their LU is dense)
  // A block's LU is kept in float when a solve with it is off by at most this
  // (relative, measured on one vector), else in double; 0: all in double.
  double float_error = 5e-2;
};

template <int D>
class RestrictedSchwarz {
 public:
  template <class T, class Entry>
  RestrictedSchwarz(const std::vector<Vec<D, T>>& points, Entry entry, SchwarzOptions options = {})
      : n_(points.size()) {
    split(points, std::max<std::size_t>(options.cluster_size, 1));
    blocks_.resize(clusters_.size());
    // The blocks are factored on parallel_for's threads with Eigen's own
    // OpenMP threads off (and the coarse LU too): nested in ours they
    // oversubscribe the cores, and libgomp's threads then spin through the
    // solve's later work (measured: the whole solve 2.6x slower on 2 cores).
    // The model's thread is the only one calling Eigen meanwhile, so the
    // setting is restored unseen.
    const int eigen_threads = Eigen::nbThreads();
    Eigen::setNbThreads(1);
    parallel_for(clusters_.size(), LoopWork::blocks, [&](std::size_t c) {
      Block& block = blocks_[c];
      block.grown = grow(points, clusters_[c], options.overlap);
      const auto m = static_cast<Eigen::Index>(block.grown.size());
      Eigen::MatrixXd a(m, m);
      for (Eigen::Index r = 0; r < m; ++r)
        for (Eigen::Index s = 0; s < m; ++s) a(r, s) = entry(block.grown[r], block.grown[s]);
      factor(a, options.float_error, block);
      for (std::size_t i : clusters_[c])
        block.own_at.push_back(static_cast<Eigen::Index>(
            std::lower_bound(block.grown.begin(), block.grown.end(), i) - block.grown.begin()));
    });
    if (options.coarse_stride > 0 && clusters_.size() > 1) coarse_level(entry, options);
    Eigen::setNbThreads(eigen_threads);
  }

  // z = M^-1 r: the local solves, then (with a coarse level) the coarse
  // correction of their residual, product(x, y) computing y = A x.
  template <class Product>
  Eigen::VectorXd apply(const Eigen::VectorXd& r, const Product& product) const {
    Eigen::VectorXd z = apply_local(r);
    if (coarse_.empty()) return z;
    Eigen::VectorXd az(r.size());
    product(z, az);
    Eigen::VectorXd residual(static_cast<Eigen::Index>(coarse_.size()));
    for (std::size_t k = 0; k < coarse_.size(); ++k) {
      const auto i = static_cast<Eigen::Index>(coarse_[k]);
      residual[static_cast<Eigen::Index>(k)] = r[i] - az[i];
    }
    const Eigen::VectorXd correction = coarse_lu_.solve(residual);
    for (std::size_t k = 0; k < coarse_.size(); ++k)
      z[static_cast<Eigen::Index>(coarse_[k])] += correction[static_cast<Eigen::Index>(k)];
    return z;
  }

  // The local level alone: each cluster's own entries from its grown block's solve.
  Eigen::VectorXd apply_local(const Eigen::VectorXd& r) const {
    Eigen::VectorXd z(r.size());
    parallel_for(clusters_.size(), LoopWork::blocks, [&](std::size_t c) {
      const Block& block = blocks_[c];
      Eigen::VectorXd local(static_cast<Eigen::Index>(block.grown.size()));
      for (std::size_t k = 0; k < block.grown.size(); ++k)
        local[static_cast<Eigen::Index>(k)] = r[static_cast<Eigen::Index>(block.grown[k])];
      const Eigen::VectorXd solved = block.in_double ? Eigen::VectorXd(block.lu_double.solve(local))
                                                     : solve_in_double(block, local);
      for (std::size_t k = 0; k < clusters_[c].size(); ++k)
        z[static_cast<Eigen::Index>(clusters_[c][k])] = solved[block.own_at[k]];
    });
    return z;
  }

  std::size_t clusters() const { return clusters_.size(); }
  std::size_t coarse_points() const { return coarse_.size(); }
  std::size_t size() const { return n_; }
  // Blocks whose LU is in double: a float one was off by more than float_error.
  std::size_t double_blocks() const {
    return static_cast<std::size_t>(
        std::count_if(blocks_.begin(), blocks_.end(), [](const Block& b) { return b.in_double; }));
  }
  // The largest grown cluster: the blocks' size.
  std::size_t largest_block() const {
    std::size_t largest = 0;
    for (const Block& b : blocks_) largest = std::max(largest, b.grown.size());
    return largest;
  }

 private:
  struct Block {
    std::vector<std::size_t> grown;  // sorted point indices
    std::vector<Eigen::Index> own_at;  // where each own point sits in grown
    Eigen::PartialPivLU<Eigen::MatrixXf> lu;         // of the scaled rows; empty when in_double
    Eigen::VectorXd row_scale;                       // powers of 2, so scaling rounds nothing
    Eigen::PartialPivLU<Eigen::MatrixXd> lu_double;  // empty unless in_double
    bool in_double = false;
  };

  // The float LU's solve, its substitutions in double: rounding them in
  // float too would lose several times more.
  static Eigen::VectorXd solve_in_double(const Block& block, const Eigen::VectorXd& b) {
    Eigen::VectorXd y = block.lu.permutationP() * block.row_scale.cwiseProduct(b);
    const Eigen::MatrixXf& f = block.lu.matrixLU();
    const Eigen::Index m = f.rows();
    for (Eigen::Index k = 0; k + 1 < m; ++k)
      y.tail(m - k - 1) -= f.col(k).tail(m - k - 1).cast<double>() * y[k];
    for (Eigen::Index k = m - 1; k >= 0; --k) {
      y[k] /= double(f(k, k));
      y.head(k) -= f.col(k).head(k).cast<double>() * y[k];
    }
    return y;
  }

  // The block's LU in float, unless solving a x = a t with it misses a known
  // t by more than max_error (relative): then in double. The miss is the
  // float LU's backward error (float rounding of a) amplified by a's
  // conditioning, the thing that decides whether the float block still
  // approximates a^-1; t's entries are generic enough that the rounding
  // excites every direction. Rows are scaled to a largest entry near 1
  // first: Kansa's boundary and interior rows differ by about 4 eps^2 (1e4),
  // and unscaled, float's rounding of the large rows swamps the small ones
  // (Kansa, N = 1e4: 18 of 128 blocks missed by more than 5%, none scaled).
  static void factor(const Eigen::MatrixXd& a, double max_error, Block& block) {
    if (max_error > 0) {
      block.row_scale = a.cwiseAbs().rowwise().maxCoeff().unaryExpr([](double largest) {
        return largest > 0 && std::isfinite(largest) ? std::exp2(-std::ilogb(largest)) : 1.0;
      });
      block.lu.compute((block.row_scale.asDiagonal() * a).template cast<float>());
      const Eigen::VectorXd t =
          (Eigen::ArrayXd::LinSpaced(a.rows(), 0, double(a.rows() - 1)).sin() + 1.5).matrix();
      const Eigen::VectorXd at = a * t;
      if ((solve_in_double(block, at) - t).norm() <= max_error * t.norm()) return;
      block.lu = Eigen::PartialPivLU<Eigen::MatrixXf>();
      block.row_scale = Eigen::VectorXd();
    }
    block.lu_double.compute(a);
    block.in_double = true;
  }

  template <class T>
  static std::pair<Vec<D>, Vec<D>> bounds(const std::vector<Vec<D, T>>& points,
                                          const std::size_t* first, const std::size_t* last) {
    Vec<D> lo, hi;
    for (int d = 0; d < D; ++d) lo[d] = hi[d] = static_cast<double>(points[*first][d]);
    for (const std::size_t* k = first; k != last; ++k)
      for (int d = 0; d < D; ++d) {
        lo[d] = std::min(lo[d], static_cast<double>(points[*k][d]));
        hi[d] = std::max(hi[d], static_cast<double>(points[*k][d]));
      }
    return {lo, hi};
  }

  // Every stride-th point of the clusters in turn (at most coarse_max),
  // sorted, and the LU of A on them.
  template <class Entry>
  void coarse_level(Entry& entry, const SchwarzOptions& options) {
    const std::size_t stride =
        std::max(options.coarse_stride, (n_ + options.coarse_max - 1) / options.coarse_max);
    std::size_t k = 0;
    for (const std::vector<std::size_t>& cluster : clusters_)
      for (std::size_t i : cluster)
        if (k++ % stride == 0) coarse_.push_back(i);
    std::sort(coarse_.begin(), coarse_.end());
    const auto m = static_cast<Eigen::Index>(coarse_.size());
    Eigen::MatrixXd a(m, m);
    parallel_for(coarse_.size(), LoopWork::heavy, [&](std::size_t r) {
      for (Eigen::Index s = 0; s < m; ++s)
        a(static_cast<Eigen::Index>(r), s) = entry(coarse_[r], coarse_[static_cast<std::size_t>(s)]);
    });
    coarse_lu_.compute(a);
  }

  // Median cuts of the longer axis, ties by index, so the clusters depend on
  // the points alone.
  template <class T>
  void split(const std::vector<Vec<D, T>>& points, std::size_t cluster_size) {
    std::vector<std::size_t> index(n_);
    std::iota(index.begin(), index.end(), std::size_t{0});
    std::vector<std::pair<std::size_t, std::size_t>> pending;
    if (n_ > 0) pending.emplace_back(0, n_);
    while (!pending.empty()) {
      const auto [lo, hi] = pending.back();
      pending.pop_back();
      if (hi - lo <= cluster_size) {
        clusters_.emplace_back(index.begin() + lo, index.begin() + hi);
        std::sort(clusters_.back().begin(), clusters_.back().end());
        continue;
      }
      const auto [low, high] = bounds(points, index.data() + lo, index.data() + hi);
      int axis = 0;
      for (int d = 1; d < D; ++d)
        if (high[d] - low[d] > high[axis] - low[axis]) axis = d;
      const std::size_t mid = lo + (hi - lo) / 2;
      std::nth_element(index.begin() + lo, index.begin() + mid, index.begin() + hi,
                       [&](std::size_t a, std::size_t b) {
                         const double pa = points[a][axis], pb = points[b][axis];
                         return pa < pb || (pa == pb && a < b);
                       });
      pending.emplace_back(mid, hi);
      pending.emplace_back(lo, mid);
    }
  }

  // The cluster and the points nearest its bounding box, overlap times its
  // size in all (ties by index), sorted. `own` is sorted.
  template <class T>
  std::vector<std::size_t> grow(const std::vector<Vec<D, T>>& points,
                                const std::vector<std::size_t>& own, double overlap) const {
    const auto [lo, hi] = bounds(points, own.data(), own.data() + own.size());
    std::vector<std::pair<double, std::size_t>> distance(n_);
    for (std::size_t k = 0; k < n_; ++k) {
      double d2 = 0;
      for (int d = 0; d < D; ++d) {
        const double x = static_cast<double>(points[k][d]);
        const double out = std::max({lo[d] - x, 0.0, x - hi[d]});
        d2 += out * out;
      }
      // Its own points come first whatever else shares the box (a median's ties).
      distance[k] = {std::binary_search(own.begin(), own.end(), k) ? -1.0 : d2, k};
    }
    const auto m = std::clamp<std::size_t>(static_cast<std::size_t>(overlap * double(own.size())),
                                           own.size(), n_);
    std::nth_element(distance.begin(), distance.begin() + static_cast<std::ptrdiff_t>(m) - 1,
                     distance.end());
    std::vector<std::size_t> grown(m);
    for (std::size_t k = 0; k < m; ++k) grown[k] = distance[k].second;
    std::sort(grown.begin(), grown.end());
    return grown;
  }

  std::size_t n_;
  std::vector<std::vector<std::size_t>> clusters_;  // sorted point indices
  std::vector<Block> blocks_;
  std::vector<std::size_t> coarse_;  // sorted point indices; empty: no coarse level
  Eigen::PartialPivLU<Eigen::MatrixXd> coarse_lu_;
};

}  // namespace partc
