// partc/neighbour_search.hpp: NeighbourSearch<D>, the facade generated code uses.
// build picks brute force when a cell list would save a query too few pair
// tests to pay for itself (small sets, cutoffs near the box size, or a periodic
// dimension with < 3 cells) and the ordered cell list otherwise; for_each_near
// dispatches with one branch per query.
//
// Query contract: as BruteForce (brute_force.hpp).
//
// Surprises: on the cell-list path build REORDERS the particle set
// (set.permute(order)), so that j in f(j, dx) indexes the set's arrays; indices
// taken before build are stale afterwards (ids are not). cell_count() is 0 on the
// brute-force path.
#pragma once

#include <cstddef>

#include "partc/brute_force.hpp"
#include "partc/cell_grid.hpp"
#include "partc/domain.hpp"
#include "partc/ordered_cell_list.hpp"
#include "partc/vec.hpp"

namespace partc {

template <int D>
class NeighbourSearch {
 public:
  enum class Kind { brute_force, cell_list };

  // Brute force examines every point; the cell list examines the points of
  // the cells near the query (about n * visited_fraction() of them) but pays a
  // fixed cost per query to find those cells. Brute force wins when it would
  // examine fewer than `margin` more points than the cell list. The margin,
  // in pair tests, was measured (g++ 12 -O3, x86-64 Xeon, one thread) with
  // tests/bench (the seed's velocity update, 2D periodic, static points):
  //   rc = sqrt(3/500), N = 10: 0.7 candidates per query in cells, brute 3.0e-7 s,
  //     cells 2.3e-7 s (9.3 pairs saved); N = 20: 1.3 candidates, brute 1.1e-6 s,
  //     cells 5.1e-7 s (18.7 pairs saved)
  //   rc = sqrt(3/N), N = 27..40: 3 cells a side, every point examined either
  //     way (0 saved): brute force as fast or faster
  // and, with points jittered every step and builds included: rc = sqrt(3/N),
  // N = 40 (0 saved) brute 5.6 us, cells 5.1 us; N = 48 (21 saved) brute 8.2 us,
  // cells 6.0 us. The fixed query cost lies between 0 and 9.3 pair tests.
  static constexpr double default_margin = 8.0;

  explicit NeighbourSearch(double margin = default_margin) : margin_(margin) {}

  template <class Set>
  void build(const Domain<D>& domain, double radius, Set& set) {
    const std::size_t n = set.positions().size();
    const CellGrid<D> grid(domain, radius, n);
    const double saved = static_cast<double>(n) * (1.0 - grid.visited_fraction());
    // A periodic dimension with < 3 cells (radius > L/3) also means brute force:
    // the cell list would need a per-pair minimum_image there.
    if (saved < margin_ || !grid.shifts_suffice()) {
      kind_ = Kind::brute_force;
      brute_force_.build(domain, radius, set.positions());
    } else {
      kind_ = Kind::cell_list;
      cell_list_.build(domain, radius, set.positions());
      set.permute(cell_list_.order());
    }
  }

  template <class F>
  void for_each_near(const Vec<D>& q, F&& f) const {
    if (kind_ == Kind::cell_list)
      cell_list_.for_each_near(q, f);
    else
      brute_force_.for_each_near(q, f);
  }

  Kind kind() const { return kind_; }
  std::size_t cell_count() const { return kind_ == Kind::cell_list ? cell_list_.cell_count() : 0; }

 private:
  double margin_;
  Kind kind_ = Kind::brute_force;
  BruteForce<D> brute_force_;
  OrderedCellList<D> cell_list_;
};

}  // namespace partc
