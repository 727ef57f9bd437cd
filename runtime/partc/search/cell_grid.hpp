// partc/search/cell_grid.hpp: CellGrid<D>, the geometry shared by LinkedCellList and
// OrderedCellList: cell sizes, the cell of a point, and the walk over the cells
// near a query point with per-cell periodic shifts, and scan, the pair loop.
// It stores no points; each cell list supplies how to walk the points of a run
// of cells.
//
// Cells: row-major with the last dimension contiguous, n_k = floor(L_k / radius)
// cells of width L_k / n_k >= radius, the total capped at 2 * points + 64 by
// widening all cells by one factor (a tiny radius cannot exhaust memory). A
// non-periodic dimension without a finite positive length gets one cell.
//
// Surprises:
// - The cells visited per dimension are not a fixed 3-cell stencil: they are the
//   cells of [q - reach, q + reach] (reach = radius * (1 + 1e-12)). Cell indices
//   are computed by one monotone floating-point map, so every point within reach
//   lies in a visited cell whatever the rounding (points exactly on cell edges,
//   cell widths a hair below radius). Usually that is 2 or 3 cells, at most 4.
// - Periodic dimensions: points are stored wrapped into [lo, hi) and the query
//   is examined as up to three images qs = q - s*L (s = -1, 0, 1). Then
//   dx = p - qs is the minimum image with no per-pair minimum_image call: with
//   >= 3 cells, L >= 3 * radius, so at most one image of a point is within reach
//   (a cell visited under two images cannot report a point twice).
// - A periodic dimension with < 3 cells (radius > L/3, or widened cells) would
//   break that; there every cell is visited once and the pair falls back to the
//   exact minimum image in that dimension ("exact mode"). shifts_suffice() tells
//   a caller that no dimension needs it.
// - Points/queries outside a non-periodic dimension are clamped to the edge cell
//   (exact: clamping keeps the index map monotone). NaN coordinates go to cell 0
//   and never match (NaN fails the distance test).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

#include "partc/domain.hpp"
#include "partc/vec.hpp"

namespace partc {

template <int D>
class CellGrid {
 public:
  CellGrid() = default;

  // Throws std::invalid_argument for a bad radius or periodic length (check_search_arguments).
  CellGrid(const Domain<D>& domain, double radius, std::size_t n_points) : domain_(domain) {
    check_search_arguments(domain, radius);
    reach_ = radius * (1 + 1e-12);
    squared_reach_ = radius * radius * (1 + 1e-12);
    const std::array<double, D> cells = cells_per_dim(domain, radius, n_points);
    exact_domain_ = domain;
    for (int k = D - 1; k >= 0; --k) {
      const double L = domain.hi[k] - domain.lo[k];
      n_[k] = static_cast<std::size_t>(cells[k]);
      inv_width_[k] = has_length(L) ? cells[k] / L : 0.0;  // 0: every coordinate maps to cell 0
      last_[k] = cells[k] - 1;
      stride_[k] = k == D - 1 ? 1 : stride_[k + 1] * n_[k + 1];
      exact_domain_.periodic[k] = domain.periodic[k] && n_[k] < 3;
      exact_ = exact_ || exact_domain_.periodic[k];
    }
    cell_count_ = stride_[0] * n_[0];
  }

  std::size_t cell_count() const { return cell_count_; }
  // Cells along dimension k.
  std::size_t cells_along(int k) const { return n_[k]; }

  // The fraction of uniformly spread points a query examines: per dimension, the
  // cells an interval of 2 * reach overlaps on average, out of all cells.
  double visited_fraction() const {
    double fraction = 1.0;
    for (int k = 0; k < D; ++k) {
      const double L = domain_.hi[k] - domain_.lo[k];
      const double n = static_cast<double>(n_[k]);
      fraction *= has_length(L) ? std::min(n, 1.0 + 2.0 * reach_ * inv_width_[k]) / n : 1.0;
    }
    return fraction;
  }

  // Whether every cell is wider than the reach, by more than rounding, and at
  // most `widest` reaches wide (a dimension of one cell without a length
  // does not count): then the runs of a cell's box (cell_box) take 3 cells
  // per dimension, as a box of its points does unless they all keep clear of
  // a face by a reach.
  bool cells_fit_reach(double widest) const {
    for (int k = 0; k < D; ++k) {
      if (inv_width_[k] == 0.0) continue;
      const double width = 1.0 / inv_width_[k];
      if (!(width > reach_ + 4 * box_margin(k) && width <= widest * reach_)) return false;
    }
    return true;
  }

  // A box [lo, hi] holding every point cell_of puts in `cell`, whatever the
  // rounding: the cell's faces moved out by box_margin, and unbounded on the
  // outer side of an edge cell in a dimension without periodicity (where
  // cell_of clamps) or a length.
  void cell_box(std::size_t cell, Vec<D>& lo, Vec<D>& hi) const {
    constexpr double infinity = std::numeric_limits<double>::infinity();
    for (int k = 0; k < D; ++k) {
      const std::size_t c = cell / stride_[k] % n_[k];
      if (inv_width_[k] == 0.0) {
        lo[k] = -infinity;
        hi[k] = infinity;
        continue;
      }
      const double width = 1.0 / inv_width_[k];
      const bool clamped = !domain_.periodic[k];
      lo[k] = clamped && c == 0 ? -infinity
                                : domain_.lo[k] + static_cast<double>(c) * width - box_margin(k);
      hi[k] = clamped && c + 1 == n_[k]
                  ? infinity
                  : domain_.lo[k] + static_cast<double>(c + 1) * width + box_margin(k);
    }
  }

  // Whether `other` has the same cells, reach and periodicity.
  bool same_cells(const CellGrid& other) const {
    for (int k = 0; k < D; ++k)
      if (domain_.lo[k] != other.domain_.lo[k] || domain_.hi[k] != other.domain_.hi[k] ||
          domain_.periodic[k] != other.domain_.periodic[k] || n_[k] != other.n_[k])
        return false;
    return reach_ == other.reach_;
  }

  // True when every periodic dimension has >= 3 cells: no pair needs minimum_image.
  bool shifts_suffice() const { return !exact_; }
  // The squared distance within which scan reports a candidate.
  double squared_reach() const { return squared_reach_; }

  // The (linear) cell of p; p must already be wrapped into the periodic box.
  std::size_t cell_of(const Vec<D>& p) const {
    std::size_t cell = 0;
    for (int k = 0; k < D; ++k) cell += coord(k, p[k]) * stride_[k];
    return cell;
  }

  // Calls run(first_cell, last_cell, qs, exact) for every run of cells
  // first_cell..last_cell (consecutive in the last dimension) that may hold a
  // point within reach of q. qs is the query image to subtract from the points
  // of those cells; exact is std::true_type in exact mode; run passes both to scan.
  template <class Run>
  void for_each_run(const Vec<D>& q, Run&& run) const {
    const Vec<D> qw = domain_.wrap(q);
    for_each_run_of_box(qw, qw, [&](std::size_t first, std::size_t last, const Vec<D>& shift,
                                    auto exact) { run(first, last, qw + shift, exact); });
  }

  // As for_each_run, for every query point in the box [lo, hi] at once (lo, hi
  // wrapped into the periodic box): the runs of cells that may hold a point within
  // reach of any of them, and per run the shift s (0 or +-L per dimension) that
  // gives a query q its image qs = q + s. Each point's runs are a superset of its
  // own for_each_run's, in the same order, with the same images: a scan finds the
  // same points in the same order, and qs is the same bit for bit.
  template <class Run>
  void for_each_run_of_box(const Vec<D>& lo, const Vec<D>& hi, Run&& run) const {
    Spans spans;
    spans.count.fill(0);
    for (int k = 0; k < D; ++k) {
      const double L = domain_.hi[k] - domain_.lo[k];
      if (!domain_.periodic[k]) {
        add_span(spans, k, lo[k], hi[k], 0.0);
      } else if (exact_domain_.periodic[k]) {
        spans.span[k][spans.count[k]++] = {0.0, 0, n_[k] - 1};
      } else {
        // The image q - L (q near hi meeting points near lo) matters only if some
        // q - L + reach reaches lo, q + L only if some q + L - reach is below hi; the
        // tests are exact (see header) and monotone in q, so the box's edge decides.
        if (hi[k] - L + reach_ >= domain_.lo[k]) add_span(spans, k, lo[k], hi[k], -L);
        add_span(spans, k, lo[k], hi[k], 0.0);
        if (!(lo[k] + L - reach_ > domain_.hi[k])) add_span(spans, k, lo[k], hi[k], L);
      }
    }
    Vec<D> shift{};
    if (exact_)
      visit<0, std::true_type>(spans, 0, shift, run);
    else
      visit<0, std::false_type>(spans, 0, shift, run);
  }

  // Calls run(first_cell, last_cell) for every run of cells that may hold a
  // stored (wrapped) point p with lo <= p <= hi componentwise; none if some
  // lo[k] > hi[k] or is NaN. No images: the box is not periodic.
  template <class Run>
  void for_each_run_in_box(const Vec<D>& lo, const Vec<D>& hi, Run&& run) const {
    Spans spans;
    for (int k = 0; k < D; ++k) {
      if (!(lo[k] <= hi[k])) return;
      spans.span[k][0] = {0.0, coord(k, lo[k]), coord(k, hi[k])};
      spans.count[k] = 1;
    }
    Vec<D> shift{};
    auto cells = [&](std::size_t first, std::size_t last, const Vec<D>&, auto) {
      run(first, last);
    };
    visit<0, std::false_type>(spans, 0, shift, cells);
  }

  // The hot loop of every query: calls f(j, dx) for each candidate j, advance(j),
  // ... (until stop) with |dx|^2 <= radius^2 (1 + 1e-12), in that order. Many
  // candidates are hits (about 1/3 in 2D, 1/6 in 3D), unpredictably, so a chunk
  // of candidates is filtered without a branch (store each one, count the hits)
  // before f is called (measured: queries ~30% faster in 2D and 3D, N >= 4096).
  template <class Exact, class Advance, class F>
  void scan(Exact, std::size_t j, std::size_t stop, Advance advance,
            const std::vector<Vec<D>>& points, const Vec<D>& qs, F& f) const {
    constexpr int chunk = 32;
    std::size_t hit_j[chunk];
    Vec<D> hit_dx[chunk];
    while (j != stop) {
      int hits = 0;
      for (int c = 0; c < chunk && j != stop; ++c, j = advance(j)) {
        Vec<D> dx = points[j] - qs;
        if constexpr (Exact::value) dx = exact_domain_.minimum_image(dx);
        hit_j[hits] = j;
        hit_dx[hits] = dx;
        hits += static_cast<int>(squared_norm(dx) <= squared_reach_);
      }
      for (int h = 0; h < hits; ++h) f(hit_j[h], hit_dx[h]);
    }
  }

 private:
  // Per dimension: up to three query images (shifts), each with its range of cell coordinates.
  struct Span {
    double shift;
    std::size_t first, last;
  };
  struct Spans {
    std::array<std::array<Span, 3>, D> span;
    std::array<int, D> count;
  };

  static bool has_length(double L) { return L > 0.0 && std::isfinite(L); }

  // floor(L / (radius * widen)) cells per dimension, with widen = 1 unless the
  // total would exceed the cap; the cap is soft by the rounding of the logs.
  static std::array<double, D> cells_per_dim(const Domain<D>& domain, double radius,
                                             std::size_t n_points) {
    const double log_cap = std::log(2.0 * static_cast<double>(n_points) + 64.0);
    std::array<double, D> cells;
    for (double widen = 1.0;;) {
      double log_total = 0.0;
      for (int k = 0; k < D; ++k) {
        const double L = domain.hi[k] - domain.lo[k];
        cells[k] = has_length(L) ? std::max(1.0, std::floor(L / (radius * widen))) : 1.0;
        log_total += std::log(cells[k]);
      }
      if (log_total <= log_cap) return cells;
      // Dimensions held at one cell make one step undershoot; the 1.001 ensures progress.
      widen *= std::max(1.001, std::exp((log_total - log_cap) / D));
    }
  }

  // Cell coordinate of x in dimension k, clamped to the grid (NaN -> 0); monotone in x.
  // Truncation is floor here because negative t is clamped first (std::floor is a
  // library call on baseline x86-64, and this is in every query).
  std::size_t coord(int k, double x) const {
    const double t = (x - domain_.lo[k]) * inv_width_[k];
    if (!(t > 0.0)) return 0;
    if (!(t < last_[k])) return n_[k] - 1;
    return static_cast<std::size_t>(static_cast<std::int64_t>(t));  // signed: one instruction
  }

  // More than the rounding of a cell's faces and of coord in dimension k: a
  // few ulps of the coordinates' magnitude, and 1e-12 of a cell.
  double box_margin(int k) const {
    const double L = domain_.hi[k] - domain_.lo[k];
    return 8 * std::numeric_limits<double>::epsilon() *
               (std::abs(domain_.lo[k]) + std::abs(domain_.hi[k]) + L) +
           1e-12 * L / static_cast<double>(n_[k]);
  }

  // The cells within reach of [lo + shift, hi + shift] in dimension k.
  void add_span(Spans& spans, int k, double lo, double hi, double shift) const {
    spans.span[k][spans.count[k]++] = {shift, coord(k, (lo + shift) - reach_),
                                       coord(k, (hi + shift) + reach_)};
  }

  template <int K, class Exact, class Run>
  void visit(const Spans& spans, std::size_t base, Vec<D>& shift, Run& run) const {
    for (int m = 0; m < spans.count[K]; ++m) {
      const Span& s = spans.span[K][m];
      shift[K] = s.shift;
      if constexpr (K + 1 == D) {
        run(base + s.first, base + s.last, static_cast<const Vec<D>&>(shift), Exact{});
      } else {
        for (std::size_t i = s.first; i <= s.last; ++i)
          visit<K + 1, Exact>(spans, base + i * stride_[K], shift, run);
      }
    }
  }

  Domain<D> domain_{};
  Domain<D> exact_domain_{};  // periodic only in the dimensions that need minimum_image
  std::array<std::size_t, D> n_{};
  std::array<std::size_t, D> stride_{};
  Vec<D> inv_width_{};
  Vec<D> last_{};  // n_ - 1 as double: coord compares with it in every query
  double reach_ = 0.0;
  double squared_reach_ = 0.0;
  std::size_t cell_count_ = 0;
  bool exact_ = false;
};

}  // namespace partc
