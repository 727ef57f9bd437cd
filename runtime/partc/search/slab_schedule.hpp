// partc/search/slab_schedule.hpp: SlabSchedule, the deterministic parallel order in
// which a structure walks each pair of points once (Newton's third law: a pair
// term given to both points, one of them += term, the other +-= term).
//
// The pair walk, for_each_pair(f), of every structure that has one: pairs are
// grouped by their lower point i, f(i, pairs) is called, and pairs(g) calls
// g(j, dx) for the group's pairs (i, j), j >= i - (i, 0) itself included -
// so that the caller can sum i's terms in a local and store them once, while
// j's go straight to j's total. f may be called twice for one i, the second
// time (without (i, 0)) for its pairs across a periodic edge.
//
// The points are sorted by cell, so the planes of cells along the first
// dimension are blocks of indices. Planes are grouped into an even number
// S >= 4 of slabs. A pair (i < j) must join a slab to itself, to the next
// slab, or (across a periodic edge) slab 0 to slab S - 1: the structure checks
// that (allows) before it uses the schedule, and keeps one slab otherwise.
// for_each_slab runs the even slabs concurrently, then the odd ones; the
// caller's slab a walks the pairs whose lower point is in slab a, and slab
// S - 1 also slab 0's pairs across the edge. Calls running at once never share
// a point, and every point receives its terms in one fixed order for any
// number of threads. One slab: everything in one serial call.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "partc/parallel.hpp"

namespace partc {

class SlabSchedule {
 public:
  SlabSchedule() = default;
  // One slab of n points.
  explicit SlabSchedule(std::size_t n) : start_{0, n} {}

  // Slabs for n points from the starts of planes (and the end, as
  // OrderedCellList::plane_starts gives them): one plane a slab, the last two
  // joined when the count is odd; one slab below 4 planes.
  static SlabSchedule of_planes(const std::vector<std::size_t>& planes, std::size_t n) {
    const std::size_t plane_count = planes.empty() ? 0 : planes.size() - 1;
    SlabSchedule schedule(n);
    if (plane_count < 4) return schedule;
    const std::size_t slabs = plane_count - plane_count % 2;
    schedule.start_.assign(planes.begin(), planes.begin() + static_cast<std::ptrdiff_t>(slabs) + 1);
    schedule.start_[slabs] = n;
    return schedule;
  }

  std::size_t count() const { return start_.size() - 1; }
  // Slab a holds points start(a) .. start(a + 1) - 1.
  std::size_t start(std::size_t a) const { return start_[a]; }
  std::size_t slab_of(std::size_t point) const {
    return static_cast<std::size_t>(std::upper_bound(start_.begin(), start_.end(), point) -
                                    start_.begin()) - 1;
  }
  // Whether a pair whose lower point is in slab a and upper in slab b obeys the rule.
  bool allows(std::size_t a, std::size_t b) const {
    return b == a || b == a + 1 || (a == 0 && b + 1 == count());
  }

  // f(a) for every slab: the even slabs concurrently, then the odd ones. Few
  // points take the same order on one thread: starting threads would cost
  // more than the walk (seed kernel, 10 points in 12 slabs: 3x the time).
  template <class F>
  void for_each_slab(F&& f) const {
    const std::size_t slabs = count();
    const bool parallel = start_.back() >= min_parallel(LoopWork::heavy);
    for (std::size_t phase = 0; phase < std::min<std::size_t>(2, slabs); ++phase) {
      const std::size_t tasks = (slabs - phase + 1) / 2;
      if (parallel)
        parallel_for(tasks, LoopWork::blocks, [&](std::size_t task) { f(phase + 2 * task); });
      else
        for (std::size_t task = 0; task < tasks; ++task) f(phase + 2 * task);
    }
  }

 private:
  std::vector<std::size_t> start_{0, 0};
};

}  // namespace partc
