// partc/search/linked_cell_list.hpp: LinkedCellList<D>, a cell list as head/next linked
// lists (the classic serial-insert form). Points keep their indices: no
// reordering, so j in f(j, dx) indexes the caller's arrays directly.
//
// Query contract: as BruteForce (brute_force.hpp); geometry and periodic
// handling: cell_grid.hpp. Any radius works (a periodic dimension with < 3 cells
// uses exact mode).
//
// Surprises: build copies the points (wrapped into the periodic box). Within a
// cell, points are visited in increasing index order. Chasing next[] jumps
// through memory; OrderedCellList is the fast variant, this one is for callers
// that must not reorder.
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "partc/domain.hpp"
#include "partc/search/cell_grid.hpp"
#include "partc/vec.hpp"

namespace partc {

template <int D>
class LinkedCellList {
 public:
  template <class T>
  void build(const Domain<D>& domain, double radius, const std::vector<Vec<D, T>>& points) {
    grid_ = CellGrid<D>(domain, radius, points.size());
    points_.resize(points.size());
    next_.resize(points.size());
    head_.assign(grid_.cell_count(), none);
    // Inserting at the head in decreasing j leaves each list in increasing j.
    for (std::size_t j = points.size(); j-- > 0;) {
      points_[j] = domain.wrap(points[j]);
      const std::size_t cell = grid_.cell_of(points_[j]);
      next_[j] = head_[cell];
      head_[cell] = j;
    }
  }

  template <class F>
  void for_each_near(const Vec<D>& q, F&& f) const {
    grid_.for_each_run(q, [&](std::size_t first, std::size_t last, const Vec<D>& qs, auto exact) {
      for (std::size_t cell = first; cell <= last; ++cell)
        grid_.scan(exact, head_[cell], none, [this](std::size_t j) { return next_[j]; }, points_,
                   qs, f);
    });
  }

  // f(j, point) for every point with lo <= point <= hi componentwise (point as
  // stored: wrapped into the periodic box; the box itself does not wrap).
  template <class F>
  void for_each_in_box(const Vec<D>& lo, const Vec<D>& hi, F&& f) const {
    grid_.for_each_run_in_box(lo, hi, [&](std::size_t first, std::size_t last) {
      for (std::size_t cell = first; cell <= last; ++cell)
        for (std::size_t j = head_[cell]; j != none; j = next_[j])
          if (inside(points_[j], lo, hi)) f(j, points_[j]);
    });
  }

  std::size_t cell_count() const { return grid_.cell_count(); }

 private:
  static constexpr std::size_t none = std::numeric_limits<std::size_t>::max();

  CellGrid<D> grid_;
  std::vector<Vec<D>> points_;
  std::vector<std::size_t> head_;  // per cell: first point, or none
  std::vector<std::size_t> next_;  // per point: next point of its cell, or none
};

}  // namespace partc
