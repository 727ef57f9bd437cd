// partc/neighbour_search.hpp: NeighbourSearch<D>, the facade generated code uses.
// build picks brute force for small sets (or when a periodic dimension would
// have < 3 cells) and the ordered cell list otherwise; for_each_near dispatches
// with one branch per query.
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

  // Measured (g++ 12 -O2, x86-64 Xeon, one thread) on the seed model's workload:
  // 2D periodic unit square, uniform points jittered every step, radius sqrt(3/N),
  // one step = build (+ permute for the cell list) + N queries, best of 5:
  //   N       27    32    36    40    48    64    128    256    512
  //   brute  2.8   3.9   4.6   5.6   8.2  14.4   55.1  199.5  681.8  us
  //   cells  3.4   4.3   4.4   5.1   6.0   8.4   16.5   32.0   59.0  us
  // (below N = 27 the radius leaves < 3 cells per dimension: brute force anyway).
  static constexpr std::size_t default_brute_force_below = 36;

  explicit NeighbourSearch(std::size_t brute_force_below = default_brute_force_below)
      : brute_force_below_(brute_force_below) {}

  template <class Set>
  void build(const Domain<D>& domain, double radius, Set& set) {
    const std::size_t n = set.positions().size();
    // The contract's rule: a periodic dimension with < 3 cells (radius > L/3) means
    // brute force; the cell list would need per-pair minimum_image there.
    if (n < brute_force_below_ || !CellGrid<D>(domain, radius, n).shifts_suffice()) {
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
  std::size_t brute_force_below_;
  Kind kind_ = Kind::brute_force;
  BruteForce<D> brute_force_;
  OrderedCellList<D> cell_list_;
};

}  // namespace partc
