// partc/search/ordered_cell_list.hpp: OrderedCellList<D>, a cell list whose points are
// sorted by cell (stable counting sort), so a cell - and a run of cells along
// the last dimension - is one contiguous range of points: the query's inner
// loop is a linear scan.
//
// Query contract: as BruteForce (brute_force.hpp); geometry and periodic
// handling: cell_grid.hpp. Any radius works (a periodic dimension with < 3 cells
// uses exact mode).
//
// Surprises:
// - j in f(j, dx) indexes the SORTED order, not the caller's: order() maps it
//   back (sorted[k] = points[order()[k]]); a caller wanting j to index its
//   particle arrays permutes them with order() right after build
//   (ParticleSet::permute(order())).
// - Within a cell the original relative order is kept, so results are
//   deterministic; build copies the points (wrapped into the periodic box).
// - for_each_near(k, f) asks about point k itself (sorted order) and finds the
//   same points, in the same order, with the same dx, as for_each_near(point k).
//   It is faster: build finds the runs of cells near each occupied cell once -
//   for the bounding box of the cell's points, so no particle's query costs the
//   cell search of for_each_near(q) (at 3 points per cell in 2D, measured: that
//   search was ~25% of a query). The runs are a table of a few entries per
//   occupied cell, rebuilt with the list.
// - for_each_pair walks each pair once, in parallel slabs of cell planes when
//   the runs allow it (slab_schedule.hpp), which build checks.
#pragma once

#include <algorithm>
#include <cstddef>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

#include "partc/domain.hpp"
#include "partc/parallel.hpp"
#include "partc/search/cell_grid.hpp"
#include "partc/search/search_instances.hpp"
#include "partc/search/slab_schedule.hpp"
#include "partc/vec.hpp"

namespace partc {

template <int D>
class OrderedCellList {
 public:
  template <class T>
  void build(const Domain<D>& domain, double radius, const std::vector<Vec<D, T>>& points) {
    const std::size_t n = points.size();
    grid_ = CellGrid<D>(domain, radius, n);
    cell_of_point_.resize(n);
    parallel_for(n, LoopWork::light,
                 [&](std::size_t i) { cell_of_point_[i] = grid_.cell_of(domain.wrap(points[i])); });
    sort_by_cell();
    points_.resize(n);
    cell_of_sorted_.resize(n);
    parallel_for(n, LoopWork::light, [&](std::size_t k) {
      points_[k] = domain.wrap(points[order_[k]]);
      cell_of_sorted_[k] = cell_of_point_[order_[k]];
    });
    make_pair_slabs(build_runs_of_cells());
  }

  template <class F>
  void for_each_near(const Vec<D>& q, F&& f) const {
    grid_.for_each_run(q, [&](std::size_t first, std::size_t last, const Vec<D>& qs, auto exact) {
      grid_.scan(exact, start_[first], start_[last + 1], [](std::size_t j) { return j + 1; },
                 points_, qs, f);
    });
  }

  // As for_each_near(point(k), f), for point k of the last build (sorted order).
  template <class F>
  void for_each_near(std::size_t k, F&& f) const {
    for_each_near_between(k, 0, points_.size(), f);
  }

  // f(j, point) for every point with lo <= point <= hi componentwise (point as
  // stored: wrapped into the periodic box; the box itself does not wrap).
  template <class F>
  void for_each_in_box(const Vec<D>& lo, const Vec<D>& hi, F&& f) const {
    grid_.for_each_run_in_box(lo, hi, [&](std::size_t first, std::size_t last) {
      for (std::size_t j = start_[first]; j < start_[last + 1]; ++j)
        if (inside(points_[j], lo, hi)) f(j, points_[j]);
    });
  }

  // The same, for the points j > k only: each pair of points once, from its
  // first point. About half the work: runs of points before k are skipped.
  template <class F>
  void for_each_near_after(std::size_t k, F&& f) const {
    for_each_near_between(k, k + 1, points_.size(), f);
  }

  // Each pair once (the pair walk of slab_schedule.hpp): f(i, pairs), pairs(g)
  // calling g(i, 0) (not for a NaN point) and g(j, dx) for every j > i that
  // for_each_near(i) reports, with the same dx; in the slabs of pair_slabs(),
  // in parallel when build found that every pair obeys the slab rule, else
  // serially, i ascending.
  template <class F>
  void for_each_pair(F&& f) const {
    for_each_pair_span(
        [&](std::size_t, std::size_t i, std::size_t from, std::size_t until, bool self) {
          f(i, [&](auto&& g) {
            if (self) g(i, Vec<D>::zero());
            for_each_near_between(i, from, until, g);
          });
        },
        [](std::size_t) {});
  }

  // The schedule of for_each_pair, for walks of their own (simd/pair_batches.hpp):
  // f(slab, i, from, until, self) says that i's pairs are its near points j
  // with from <= j < until, and (self) the pair (i, i); calls of one slab run
  // on one thread, then slab_done(slab) on it. A point of slab 0 is called
  // twice, the second time (self false, slab the last) for its pairs across
  // the periodic edge.
  template <class F, class SlabDone>
  void for_each_pair_span(F&& f, SlabDone&& slab_done) const {
    const std::size_t n = points_.size(), last = pair_slabs_.count() - 1;
    // Slab 0's pairs from here on cross the periodic edge: they run with the last slab.
    const std::size_t edge = last > 0 ? pair_slabs_.start(last) : n;
    pair_slabs_.for_each_slab([&](std::size_t a) {
      for (std::size_t i = pair_slabs_.start(a); i < pair_slabs_.start(a + 1); ++i)
        if (is_finite(points_[i])) f(a, i, i + 1, a == 0 ? edge : n, true);
      if (a == last && a > 0)
        for (std::size_t i = pair_slabs_.start(0); i < pair_slabs_.start(1); ++i)
          f(a, i, edge, n, false);
      slab_done(a);
    });
  }

  // The runs of candidates of point k's member query, for from <= j < until:
  // run(first, stop, qs) for points first .. stop-1, seen from the query image
  // qs (dx = point(j) - qs); for_each_near_between scans the same runs. False,
  // and no call, in exact mode (!shifts_suffice()), which has no runs.
  template <class Run>
  bool for_each_run_between(std::size_t k, std::size_t from, std::size_t until, Run&& run) const {
    if (!grid_.shifts_suffice()) return false;
    const std::size_t cell = cell_of_sorted_[k];
    for (std::size_t r = run_start_[cell]; r != run_start_[cell + 1]; ++r) {
      const std::size_t first = std::max(start_[runs_[r].first_cell], from);
      const std::size_t stop = std::min(start_[runs_[r].stop_cell], until);
      if (first < stop) run(first, stop, points_[k] + runs_[r].shift);
    }
    return true;
  }

  // The member query of point k, for the points from <= j < until only.
  template <class F>
  void for_each_near_between(std::size_t k, std::size_t from, std::size_t until, F&& f) const {
    const bool by_runs = for_each_run_between(k, from, until, [&](std::size_t first,
                                                                  std::size_t stop,
                                                                  const Vec<D>& qs) {
      grid_.scan(std::false_type{}, first, stop, [](std::size_t j) { return j + 1; }, points_, qs,
                 f);
    });
    if (!by_runs)
      for_each_near(points_[k], [&](std::size_t j, const Vec<D>& dx) {
        if (j >= from && j < until) f(j, dx);
      });
  }
  double squared_reach() const { return grid_.squared_reach(); }
  const SlabSchedule& pair_slabs() const { return pair_slabs_; }

  // Where each plane of cells along the first dimension begins, and its end:
  // plane a holds points plane_starts()[a] .. plane_starts()[a+1]-1. Cells are
  // at least the radius wide, so points near a point of plane a lie in planes
  // a - 1, a, a + 1 (mod the plane count where periodic), up to rounding at
  // the planes' edges: a caller relying on it checks its pairs.
  std::vector<std::size_t> plane_starts() const {
    const std::size_t planes = grid_.cells_along(0), per_plane = grid_.cell_count() / planes;
    std::vector<std::size_t> starts(planes + 1);
    for (std::size_t a = 0; a <= planes; ++a) starts[a] = start_[a * per_plane];
    return starts;
  }
  bool shifts_suffice() const { return grid_.shifts_suffice(); }

  // The mean number of points a member query (for_each_near(k)) examines,
  // over the points of the last build: how much a clustered distribution
  // costs this structure. Counted from the runs of cells as build found them;
  // in exact mode, which has none, each cell's first point stands for all of
  // its points.
  double mean_examined() const {
    if (points_.empty()) return 0.0;
    if (grid_.shifts_suffice())
      return static_cast<double>(examined_) / static_cast<double>(points_.size());
    double total = 0.0;
    for (std::size_t c = 0; c + 1 < start_.size(); ++c) {
      const std::size_t in_cell = start_[c + 1] - start_[c];
      if (in_cell == 0) continue;
      std::size_t examined = 0;
      grid_.for_each_run(points_[start_[c]],
                         [&](std::size_t first, std::size_t last, const Vec<D>&, auto) {
                           examined += start_[last + 1] - start_[first];
                         });
      total += static_cast<double>(in_cell) * static_cast<double>(examined);
    }
    return total / static_cast<double>(points_.size());
  }

  // The permutation of the last build: sorted[k] = points[order()[k]].
  const std::vector<std::size_t>& order() const { return order_; }
  std::size_t cell_count() const { return grid_.cell_count(); }
  // Point k of the last build (sorted order), wrapped into the periodic box.
  const Vec<D>& point(std::size_t k) const { return points_[k]; }

 private:
  // The points of cells first_cell .. stop_cell-1, seen from a query q as
  // neighbours of q + shift.
  struct Run {
    std::size_t first_cell, stop_cell;
    Vec<D> shift;
  };

  // order_ and start_ from cell_of_point_: the stable counting sort by cell,
  // in parallel by blocks of consecutive points. Each block counts its points
  // per cell; cell c's range then holds block 0's points of c, block 1's, ...,
  // and each block fills its places in ascending order. That is the serial
  // sort's order whatever the blocks, so the thread count only sizes them.
  void sort_by_cell() {
    const std::size_t n = cell_of_point_.size(), cells = grid_.cell_count();
    // Blocks only where cells are fewer than points: the scratch and the
    // prefix pass grow with blocks * cells.
    const std::size_t blocks = n >= 2 * min_parallel(LoopWork::light) && cells <= n
                                   ? static_cast<std::size_t>(std::max(1, max_threads()))
                                   : 1;
    // Each block's bounds and pointers in locals: the stores through count and
    // place may alias anything else, so bounds read through captures would be
    // reloaded, and b * n / blocks divided again, every iteration.
    const auto block_begin = [n, blocks](std::size_t b) { return b * n / blocks; };
    const std::size_t* cell_of_point = cell_of_point_.data();
    // block_place_[b * cells + c]: first block b's points in cell c, then where they go.
    block_place_.assign(blocks * cells, 0);
    parallel_for(blocks, LoopWork::blocks, [&](std::size_t b) {
      std::size_t* count = block_place_.data() + b * cells;
      for (std::size_t i = block_begin(b), stop = block_begin(b + 1); i < stop; ++i)
        ++count[cell_of_point[i]];
    });
    start_.resize(cells + 1);
    std::size_t placed = 0;
    for (std::size_t c = 0; c < cells; ++c) {
      start_[c] = placed;
      for (std::size_t b = 0; b < blocks; ++b)
        placed += std::exchange(block_place_[b * cells + c], placed);
    }
    start_[cells] = placed;
    order_.resize(n);
    std::size_t* order = order_.data();
    parallel_for(blocks, LoopWork::blocks, [&](std::size_t b) {
      std::size_t* place = block_place_.data() + b * cells;
      for (std::size_t i = block_begin(b), stop = block_begin(b + 1); i < stop; ++i)
        order[place[cell_of_point[i]]++] = i;
    });
  }

  // The runs near each cell, for the member queries (none in exact mode,
  // where they take the per-point path), and examined_. Returns whether every
  // run stays within its cell's plane and the next, or, from plane 0, reaches
  // only the last plane (across the periodic edge).
  //
  // Where every cell is at most 1.5 reaches wide, the box of a cell's points
  // seldom trims its runs (with cells 1.003 reaches wide, as md's at N = 1e5,
  // all the points of a cell would have to lie in its inner 0.3%), so the
  // runs are those of the whole cell: they depend on the grid alone, are
  // found once for all builds on the same grid, and a build only counts what
  // they examine. The extra cells they may take hold no point within reach of
  // the cell's, so a query finds the same points in the same order either way.
  bool build_runs_of_cells() {
    examined_ = 0;
    if (!grid_.shifts_suffice()) {
      runs_.clear();
      run_start_.assign(grid_.cell_count() + 1, 0);
      runs_grid_.reset();
      return false;
    }
    if (!grid_.cells_fit_reach(1.5)) {
      runs_grid_.reset();
      return find_runs([&](std::size_t c, Vec<D>& lo, Vec<D>& hi) { return box_of_points(c, lo, hi); },
                       true);
    }
    if (!runs_grid_ || !runs_grid_->same_cells(grid_)) {
      runs_within_next_plane_ = find_runs(
          [&](std::size_t c, Vec<D>& lo, Vec<D>& hi) {
            grid_.cell_box(c, lo, hi);
            return true;
          },
          false);
      runs_grid_ = grid_;
    }
    examined_ = examined_by_runs();
    return runs_within_next_plane_;
  }

  // The box of cell c's finite points (a NaN or Inf coordinate has no
  // neighbours: it does not widen the box); false for none.
  bool box_of_points(std::size_t c, Vec<D>& lo, Vec<D>& hi) const {
    bool any = false;
    for (std::size_t k = start_[c]; k < start_[c + 1]; ++k) {
      if (!is_finite(points_[k])) continue;
      for (int d = 0; d < D; ++d) {
        lo[d] = any ? std::min(lo[d], points_[k][d]) : points_[k][d];
        hi[d] = any ? std::max(hi[d], points_[k][d]) : points_[k][d];
      }
      any = true;
    }
    return any;
  }

  // runs_ and run_start_ from box(c, lo, hi), the box each cell's runs must
  // reach from (false: no runs); skip_empty leaves out runs without points.
  // In parallel, by blocks of cells: each block's runs depend on the block
  // alone, and are joined in block order, so nothing depends on the threads.
  template <class Box>
  bool find_runs(Box&& box, bool skip_empty) {
    runs_.clear();
    run_start_.assign(grid_.cell_count() + 1, 0);
    const std::size_t blocks = (grid_.cell_count() + cells_per_block - 1) / cells_per_block;
    block_runs_.resize(blocks);
    std::vector<char> block_within(blocks);
    std::vector<std::size_t> block_examined(blocks);
    parallel_for(blocks, LoopWork::blocks, [&](std::size_t b) {
      const std::size_t first = b * cells_per_block;
      block_within[b] =
          runs_of_cells(first, std::min(grid_.cell_count(), first + cells_per_block), box,
                        skip_empty, block_runs_[b], block_examined[b]);
    });
    bool within_next_plane = true;
    for (std::size_t b = 0; b < blocks; ++b) {
      examined_ += block_examined[b];
      const std::size_t offset = runs_.size();
      for (std::size_t c = b * cells_per_block;
           c < std::min(grid_.cell_count(), (b + 1) * cells_per_block); ++c)
        run_start_[c] += offset;
      runs_.insert(runs_.end(), block_runs_[b].begin(), block_runs_[b].end());
      within_next_plane = within_next_plane && block_within[b];
    }
    run_start_.back() = runs_.size();
    return within_next_plane;
  }

  // find_runs for cells from .. until-1: their runs into `runs` (run_start_
  // relative to it), and the points their member queries examine into
  // `examined`; whether each stays within its cell's plane and the next
  // (from plane 0, or the last plane across the periodic edge).
  template <class Box>
  bool runs_of_cells(std::size_t from, std::size_t until, Box& box, bool skip_empty,
                     std::vector<Run>& runs, std::size_t& examined) {
    runs.clear();
    examined = 0;
    // Cells are numbered plane by plane (planes of cells along dimension 0):
    // cell c lies in plane a, which ends at cell next_plane, the one after at
    // after_next.
    const std::size_t per_plane = grid_.cell_count() / grid_.cells_along(0);
    const std::size_t last_plane = grid_.cell_count() - per_plane;
    std::size_t a = from / per_plane, next_plane = (a + 1) * per_plane;
    bool within_next_plane = true;
    for (std::size_t c = from; c < until; ++c) {
      if (c == next_plane) ++a, next_plane += per_plane;
      const std::size_t after_next = next_plane + per_plane;
      run_start_[c] = runs.size();
      Vec<D> lo{}, hi{};
      if (!box(c, lo, hi)) continue;
      grid_.for_each_run_of_box(
          lo, hi, [&](std::size_t first, std::size_t last, const Vec<D>& shift, auto) {
            if (skip_empty && start_[first] == start_[last + 1]) return;
            // Field by field into the vector: a Run built on the stack and
            // copied by one wide load stalls on its narrower stores (42% of
            // this loop's time, measured).
            Run& added = runs.emplace_back();
            added.first_cell = first;
            added.stop_cell = last + 1;
            for (int d = 0; d < D; ++d) added.shift[d] = shift[d];
            examined += (start_[c + 1] - start_[c]) * (start_[last + 1] - start_[first]);
            // Beyond the next plane, only plane 0 meeting the last plane (across
            // the periodic edge) keeps the slab rule of for_each_pair.
            if (last >= after_next && !(a == 0 && first >= last_plane)) within_next_plane = false;
          });
    }
    return within_next_plane;
  }

  // What the member queries examine through the runs as they stand.
  std::size_t examined_by_runs() const {
    const std::size_t blocks = (grid_.cell_count() + cells_per_block - 1) / cells_per_block;
    std::vector<std::size_t> block_examined(blocks);
    parallel_for(blocks, LoopWork::blocks, [&](std::size_t b) {
      std::size_t examined = 0;
      for (std::size_t c = b * cells_per_block;
           c < std::min(grid_.cell_count(), (b + 1) * cells_per_block); ++c) {
        const std::size_t in_cell = start_[c + 1] - start_[c];
        if (in_cell == 0) continue;
        for (std::size_t r = run_start_[c]; r != run_start_[c + 1]; ++r)
          examined += in_cell * (start_[runs_[r].stop_cell] - start_[runs_[r].first_cell]);
      }
      block_examined[b] = examined;
    });
    std::size_t total = 0;
    for (std::size_t e : block_examined) total += e;
    return total;
  }

  // The slabs of for_each_pair from the planes of cells, when every run of
  // every occupied cell stays within its own plane and the next (or, from
  // plane 0, the last plane across the periodic edge): then the pairs j > i of
  // a point of plane a join it to planes a and a + 1, or plane 0 to the last
  // one, as the slab rule asks. Cells are at least the radius wide, so this
  // fails only by rounding at a plane's edge; then one slab.
  void make_pair_slabs(bool runs_within_next_plane) {
    const std::size_t n = points_.size();
    pair_slabs_ = runs_within_next_plane ? SlabSchedule::of_planes(plane_starts(), n)
                                         : SlabSchedule(n);
  }

  CellGrid<D> grid_;
  std::vector<Vec<D>> points_;               // wrapped, sorted by cell
  std::vector<std::size_t> start_;           // cell c holds points start_[c] .. start_[c+1]-1
  std::vector<std::size_t> order_;
  std::vector<std::size_t> cell_of_point_;   // build scratch, kept to reuse its memory
  std::vector<std::size_t> block_place_;     // sort_by_cell's scratch, per block and cell
  std::vector<std::size_t> cell_of_sorted_;  // the cell of sorted point k
  std::vector<Run> runs_;                    // cell c's runs: runs_[run_start_[c] ..
  std::vector<std::size_t> run_start_;       // ... run_start_[c+1]-1]
  std::vector<std::vector<Run>> block_runs_;  // build scratch, per block of cells
  std::optional<CellGrid<D>> runs_grid_;     // the grid runs_ hold whole cells' runs for
  bool runs_within_next_plane_ = false;      // ... and whether they keep the slab rule
  std::size_t examined_ = 0;                 // by all member queries, through the runs
  static constexpr std::size_t cells_per_block = 4096;
  SlabSchedule pair_slabs_;                  // the parallel schedule of for_each_pair
};

// Compiled once, in the runtime library (search_instances.hpp).
PARTC_SEARCH_INSTANCES(extern template, OrderedCellList);

}  // namespace partc
