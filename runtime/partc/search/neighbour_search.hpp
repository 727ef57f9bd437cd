// partc/search/neighbour_search.hpp: NeighbourSearch<D>, the facade generated code uses.
// build picks, from the data, brute force when a cell list would save a query
// too few pair tests to pay for itself (small sets, cutoffs near the box size,
// or a periodic dimension with < 3 cells), a k-d tree when the points are so
// clustered that a cell list's queries would examine hundreds of points, and
// the ordered cell list otherwise; a model's schedule can force one of them.
// for_each_near dispatches with one branch per query. for_each_pair walks
// each pair once (slab_schedule.hpp), for sums that obey Newton's third law;
// pairs_once says when that beats per-particle queries.
//
// Query contract: as BruteForce (brute_force.hpp), including its images: a
// radius over half a periodic length reports every image within the radius.
//
// Positions stored as float (a schedule's precision = float) are searched as
// doubles: every structure's build copies the points widened (exactly) to
// Vec<D>, so each dx is the difference of two doubles, as in a double model.
//
// A radius of 0 or less (a model's |dx| < r with r = 0) searches within the
// smallest positive double instead: the condition then holds for coincident
// particles at most, and those are what that finds; it is not an error.
//
// Surprises: on the cell-list and tree paths build REORDERS the particle set
// (set.permute(order)), so that j in f(j, dx) indexes the set's arrays; indices
// taken before build are stale afterwards (ids are not). cell_count() is 0 off
// the cell-list path. The clustered test builds the cell list first (cheap) to
// measure it, so a tree build costs one cell-list build more.
//
// Order::keep (for a set whose order something else owns: its Verlet lists,
// whose slots a reorder would scramble and so rebuild, or another search of
// the same set) builds without permuting the set and maps each reported j
// back to the set's index, and each index asked into the sorted order: the
// same neighbours, dx and order as Order::reorder, one index load more per
// neighbour; the set's arrays are then read out of spatial order.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "partc/domain.hpp"
#include "partc/function_ref.hpp"
#include "partc/parallel.hpp"
#include "partc/search/brute_force.hpp"
#include "partc/search/cell_grid.hpp"
#include "partc/search/kd_tree.hpp"
#include "partc/search/ordered_cell_list.hpp"
#include "partc/search/slab_schedule.hpp"
#include "partc/simd/pair_batches.hpp"
#include "partc/vec.hpp"

namespace partc {

template <int D>
class NeighbourSearch {
 public:
  enum class Kind { brute_force, cell_list, kd_tree };

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

  // A cell list costs ~120 ns per query plus ~1 ns per point it examines; a
  // k-d tree ~450-530 ns whatever the clustering (2D, ~20 neighbours, g++ -O2,
  // N = 1e4 and 1e5: uniform 59 examined, cells 128 ns vs tree 473 ns; blobs
  // sigma 0.01, 183-195 examined, 243-276 ns vs 444-514 ns; sigma 0.001,
  // 1345-6239 examined, 1436-6114 ns vs 435-499 ns). The tree wins beyond
  // about 400 examined points per query; its build costs ~8 cell-list builds,
  // which the margin below leaves room for.
  static constexpr double kd_tree_above_examined = 500.0;
  // ... and only for points clustered at least this much: a query examining
  // this many times the points it would examine if they were spread uniformly.
  // A large radius makes every query examine many points (LJ with a skin,
  // 3D: ~650), but then the tree examines many as well and was measured 2.2x
  // slower than the cell list (32000 uniform points, radius 2.8, 79 neighbours).
  static constexpr double kd_tree_clustering = 4.0;

  // Whether build may permute the set (reorder) or leaves it as it is (keep).
  enum class Order { reorder, keep };

  explicit NeighbourSearch(double margin = default_margin, Order order = Order::reorder)
      : margin_(margin), keep_order_(order == Order::keep) {}
  // Always this structure (a model's schedule said so), except that a radius
  // over half a periodic length takes brute force (see build). A forced cell
  // list also serves periodic sides of fewer than 3 cells, in its exact mode.
  explicit NeighbourSearch(Kind forced, Order order = Order::reorder)
      : forced_(forced), keep_order_(order == Order::keep) {}

  template <class Set>
  void build(const Domain<D>& domain, double requested_radius, Set& set) {
    if (const std::vector<std::size_t>* order =
            build_structure(domain, requested_radius, set.positions()))
      set.permute(*order);
  }

  template <class F>
  void for_each_near(const Vec<D>& q, F&& f) const {
    if (sorted_apart()) return sorted_near(q, in_set_order(f));
    sorted_near(q, f);
  }

  // f(j, point) for every particle whose position (wrapped into the periodic
  // box) lies in [lo, hi] componentwise; the box itself does not wrap.
  template <class F>
  void for_each_in_box(const Vec<D>& lo, const Vec<D>& hi, F&& f) const {
    if (sorted_apart()) return sorted_in_box(lo, hi, in_set_order(f));
    sorted_in_box(lo, hi, f);
  }

  // As for_each_near(p[i], f) for particle i of the set as of the last build
  // (after its reorder): the same neighbours, order and dx, found faster on the
  // cell-list path (OrderedCellList::for_each_near(k, f)).
  template <class F>
  void for_each_near(std::size_t i, F&& f) const {
    if (sorted_apart()) return sorted_near(rank_[i], in_set_order(f));
    sorted_near(i, f);
  }

  // The same for the neighbours j > i only: each pair once, from its first
  // particle (with Order::keep, "after" in the search's sorted order).
  template <class F>
  void for_each_near_after(std::size_t i, F&& f) const {
    if (sorted_apart()) return sorted_near_after(rank_[i], in_set_order(f));
    sorted_near_after(i, f);
  }

  // Each pair once (the pair walk of slab_schedule.hpp): f(i, pairs), pairs(g)
  // calling g(j, dx) for i itself (dx = 0) and every j > i that
  // for_each_near(i) reports, with the same dx (over half a periodic length,
  // every image, i's own included). A sum whose pair term is the same or its
  // negative seen from either particle (Newton's third law) gives it to both
  // and evaluates half as many terms. Nothing for a NaN point, which no query
  // reports. On the cell-list path in parallel slabs when the build allowed it
  // (OrderedCellList::for_each_pair), with results independent of the thread
  // count; else serially, i ascending. With Order::keep, i and j are mapped to
  // the set's indices (j > i in the sorted order); the mapping is one to one,
  // so two slabs still never touch one particle.
  template <class F>
  void for_each_pair(F&& f) const {
    if (kind_ != Kind::cell_list) return pairs_off_cells(f);
    if (!sorted_apart()) return cell_list_.for_each_pair(f);
    cell_list_.for_each_pair(set_order_pairs(f));
  }

  // for_each_pair's pairs packed for vector arithmetic (simd/pair_batches.hpp):
  // f(batch) for batches holding each particle's pairs together, the pair
  // (i, i) (dx 0) only with_self. On the cell-list path the candidates are
  // filtered by vectors, in the cell list's slabs (in parallel); on the others
  // the batches are filled from for_each_pair, serially. With Order::keep, i
  // and j are the set's indices, as for for_each_pair.
  //
  // Compiled once in the runtime library (searches.cpp), not with each
  // model: f is called through a FunctionRef once a batch (tens of pairs).
  void for_each_pair_batch(bool with_self,
                           FunctionRef<void(simd::PairBatch<D>&)> f) const;

  // for_each_near's neighbours packed the same way, for sums that take each
  // pair both ways, or that obey Newton's third law where the pair walk runs
  // serially (pairs_once false): f(batch) for batches of consecutive
  // particles i (the set's order), each i with every j that for_each_near(i)
  // reports, in its order and with its dx, the pair (i, i) at dx 0 only
  // with_self; batch.each_pair_once() is false. A particle's neighbours are
  // all in one batch, and the set's blocks run in parallel (f is called from
  // several threads at once, never for one i twice), so a sum into i alone
  // is as independent of the thread count as a per-particle query's.
  // Compiled in searches.cpp, as for_each_pair_batch.
  void for_each_near_batch(bool with_self,
                           FunctionRef<void(simd::PairBatch<D>&)> f) const;

  // Whether such sums should take for_each_pair over per-particle queries:
  // when its pairs run in parallel (cell list), and when the set is small
  // enough for a particle loop to run on one thread anyway (parallel_for below
  // min_parallel(LoopWork::heavy)). Half the pair terms: the seed kernel at
  // N = 10..50 took 0.63-0.68x the time. Otherwise per-particle queries run in
  // parallel, also with results that do not depend on the thread count.
  bool pairs_once() const {
    return size_ < min_parallel(LoopWork::heavy) || pair_slabs().count() > 1;
  }

  // The slabs of for_each_pair: the cell list's (OrderedCellList::pair_slabs),
  // whose pairs j > i all obey the slab rule; one slab on the other paths.
  SlabSchedule pair_slabs() const {
    return kind_ == Kind::cell_list ? cell_list_.pair_slabs() : SlabSchedule(size_);
  }

  Kind kind() const { return kind_; }
  bool keeps_order() const { return keep_order_; }
  std::size_t build_count() const { return build_count_; }
  // Pair walks: a kernel that sums over the neighbours of every particle (by
  // for_each_pair or by queries) counts one, so a model's report shows how
  // many passes over the pairs a step takes.
  void note_walk() { ++walk_count_; }
  std::size_t walk_count() const { return walk_count_; }
  // The structure of the last build, for people: "cell list", ...
  std::string describe() const {
    if (build_count_ == 0) return "not built yet";
    const std::string kept = keep_order_ ? ", set order kept" : "";
    switch (kind_) {
      case Kind::cell_list: {
        const std::size_t slabs = pair_slabs().count();
        return "cell list, " + std::to_string(cell_count()) + " cells" +
               (slabs > 1 ? ", pair walks in " + std::to_string(slabs) + " slabs" : "") + kept;
      }
      case Kind::kd_tree: return "k-d tree" + kept;
      case Kind::brute_force: break;
    }
    return brute_force_.all_images() ? "brute force, every periodic image" : "brute force";
  }
  std::size_t cell_count() const { return kind_ == Kind::cell_list ? cell_list_.cell_count() : 0; }

 private:
  // The structure's own order: the set's after a reordering build.
  template <class F>
  void sorted_near(const Vec<D>& q, F&& f) const {
    if (kind_ == Kind::cell_list)
      cell_list_.for_each_near(q, f);
    else if (kind_ == Kind::kd_tree)
      kd_tree_.for_each_near(q, f);
    else
      brute_force_.for_each_near(q, f);
  }

  template <class F>
  void sorted_in_box(const Vec<D>& lo, const Vec<D>& hi, F&& f) const {
    if (kind_ == Kind::cell_list)
      cell_list_.for_each_in_box(lo, hi, f);
    else if (kind_ == Kind::kd_tree)
      kd_tree_.for_each_in_box(lo, hi, f);
    else
      brute_force_.for_each_in_box(lo, hi, f);
  }

  template <class F>
  void sorted_near(std::size_t k, F&& f) const {
    if (kind_ == Kind::cell_list)
      cell_list_.for_each_near(k, f);
    else if (kind_ == Kind::kd_tree)
      kd_tree_.for_each_near(kd_tree_.point(k), f);
    else
      brute_force_.for_each_near(k, f);
  }

  template <class F>
  void sorted_near_after(std::size_t k, F&& f) const {
    if (kind_ == Kind::cell_list) return cell_list_.for_each_near_after(k, f);
    sorted_near(k, [&](std::size_t j, const Vec<D>& dx) {
      if (j > k) f(j, dx);
    });
  }

  // for_each_pair on the brute-force and k-d tree paths: a kernel walked only
  // there (for_each_pair_batch's serial batches) is compiled for those walks
  // alone, not also for the cell list's.
  template <class F>
  void pairs_off_cells(F&& f) const {
    if (kind_ == Kind::brute_force) return brute_force_.for_each_pair(f);
    if (!sorted_apart()) return kd_tree_pairs(f);
    kd_tree_pairs(set_order_pairs(f));
  }

  template <class F>
  void kd_tree_pairs(F&& f) const {
    for (std::size_t k = 0; k < size_; ++k)
      if (is_finite(kd_tree_.point(k)))
        f(k, [&](auto&& g) {
          g(k, Vec<D>::zero());
          kd_tree_.for_each_near(kd_tree_.point(k), [&](std::size_t j, const Vec<D>& dx) {
            if (j > k) g(j, dx);
          });
        });
  }

  // A pair walk's f(i, pairs), given the set's indices of i and of each j.
  template <class F>
  auto set_order_pairs(F& f) const {
    return [this, &f](std::size_t i, const auto& pairs) {
      f(order_[i], [&](auto&& g) { pairs(in_set_order(g)); });
    };
  }

  // g(j, dx) appending the pair (i, j) to batch; (i, i) at dx 0, the pair of
  // i with itself, only with_self (j == i elsewhere is another image).
  static auto pusher(simd::PairBatch<D>& batch, std::size_t i, bool with_self) {
    return [&batch, i, with_self](std::size_t j, const Vec<D>& dx) {
      if (with_self || j != i || dx != Vec<D>::zero()) batch.push(i, j, dx);
    };
  }

  // The cell list's sorted points as coordinate arrays for the packed walks, once per build.
  void batch_coordinates() const {
    if (batched_build_ == build_count_) return;
    batches_.build(cell_list_, size_);
    batched_build_ = build_count_;
  }

  // Order::keep on a path that sorts (brute force never does): indices differ.
  bool sorted_apart() const { return keep_order_ && kind_ != Kind::brute_force; }

  // f, called with the set's index of the sorted point j.
  template <class F>
  auto in_set_order(F& f) const {
    return [this, &f](std::size_t j, const Vec<D>& x) { f(order_[j], x); };
  }

  // Builds the structure the data calls for (see the top of the file), on
  // double or float positions. Returns the order the set must take (the
  // structure's), or null when it keeps its own: brute force, or Order::keep,
  // which remembers the map both ways instead. Compiled in searches.cpp.
  template <class T>
  const std::vector<std::size_t>* build_structure(const Domain<D>& domain, double requested_radius,
                                                  const std::vector<Vec<D, T>>& points);
  const std::vector<std::size_t>* adopt_order(const std::vector<std::size_t>& order);

 private:
  double margin_ = default_margin;
  std::optional<Kind> forced_;
  bool keep_order_ = false;
  std::vector<std::size_t> order_, rank_;  // Order::keep: sorted k -> set index, and back
  Kind kind_ = Kind::brute_force;
  std::size_t build_count_ = 0;
  std::size_t walk_count_ = 0;
  std::size_t size_ = 0;
  BruteForce<D> brute_force_;
  OrderedCellList<D> cell_list_;
  KdTree<D> kd_tree_;
  // for_each_pair_batch's scratch: coordinates and batches of the cell list
  // (rebuilt at its first walk after a build), one batch for the serial paths.
  mutable simd::PairBatches<D> batches_;
  mutable std::size_t batched_build_ = 0;
  mutable simd::PairBatch<D> serial_batch_;
  mutable std::vector<simd::PairBatch<D>> near_batches_;  // for_each_near_batch's, one per block
};

template <int D>
template <class T>
const std::vector<std::size_t>* NeighbourSearch<D>::build_structure(
    const Domain<D>& domain, double requested_radius, const std::vector<Vec<D, T>>& points) {
  const double radius = requested_radius > 0 || std::isnan(requested_radius)
                            ? requested_radius  // NaN: check_search_arguments refuses it
                            : std::numeric_limits<double>::min();
  const std::size_t n = points.size();
  size_ = n;
  const CellGrid<D> grid(domain, radius, n);
  const double saved = static_cast<double>(n) * (1.0 - grid.visited_fraction());
  // A periodic dimension with < 3 cells (radius > L/3) also means brute force:
  // the cell list would need a per-pair minimum_image there.
  // Only brute force reports every periodic image of a point, which a radius
  // over half a periodic length needs: there it is used whatever was forced.
  const bool brute = BruteForce<D>::needs_all_images(domain, radius) ||
                     (forced_ ? *forced_ == Kind::brute_force
                              : saved < margin_ || !grid.shifts_suffice());
  ++build_count_;
  if (brute) {
    kind_ = Kind::brute_force;
    brute_force_.build(domain, radius, points);
    return nullptr;
  }
  if (forced_ != Kind::kd_tree) {
    cell_list_.build(domain, radius, points);
    // Clustered points crowd a few cells: there the tree is cheaper.
    const double examined = cell_list_.mean_examined();
    if (forced_ == Kind::cell_list || examined <= kd_tree_above_examined ||
        examined <= kd_tree_clustering * static_cast<double>(n) * grid.visited_fraction()) {
      kind_ = Kind::cell_list;
      return adopt_order(cell_list_.order());
    }
  }
  kind_ = Kind::kd_tree;
  kd_tree_.build(domain, radius, points);
  return adopt_order(kd_tree_.order());
}

// The set takes the structure's order, or keeps its own and the map both ways.
template <int D>
const std::vector<std::size_t>* NeighbourSearch<D>::adopt_order(
    const std::vector<std::size_t>& order) {
  if (!keep_order_) return &order;
  order_ = order;
  rank_.resize(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) rank_[order[k]] = k;
  return nullptr;
}

template <int D>
void NeighbourSearch<D>::for_each_pair_batch(
    bool with_self, FunctionRef<void(simd::PairBatch<D>&)> f) const {
  if (kind_ == Kind::cell_list) {
    batch_coordinates();
    // One walk for both orders (the test is per batch, not per pair).
    return batches_.for_each_pair(cell_list_, with_self, [&](simd::PairBatch<D>& batch) {
      if (sorted_apart()) batch.renumber(order_);
      f(batch);
    });
  }
  simd::PairBatch<D>& batch = serial_batch_;
  batch.clear();
  pairs_off_cells([&](std::size_t i, const auto& pairs) {
    pairs(pusher(batch, i, with_self));
    batch.hand_over_if_full(f);
  });
  batch.hand_over_rest(f);
}

template <int D>
void NeighbourSearch<D>::for_each_near_batch(
    bool with_self, FunctionRef<void(simd::PairBatch<D>&)> f) const {
  // Blocks of consecutive particles, a few per thread (a loaded thread leaves
  // its share to the others); how many changes no result.
  const std::size_t blocks = std::clamp<std::size_t>(
      size_ / min_parallel(LoopWork::heavy), 1, 8 * static_cast<std::size_t>(max_threads()));
  near_batches_.resize(blocks);
  // On the cell list in the set's order, the candidates are filtered by
  // vectors (PairBatches::append_query), else pushed one by one.
  const bool by_runs = kind_ == Kind::cell_list && !sorted_apart() && cell_list_.shifts_suffice();
  if (by_runs) batch_coordinates();
  parallel_for(blocks, LoopWork::blocks, [&](std::size_t b) {
    simd::PairBatch<D>& batch = near_batches_[b];
    batch.clear();
    batch.set_slab(b);
    batch.set_each_pair_once(false);
    for (std::size_t i = b * size_ / blocks, stop = (b + 1) * size_ / blocks; i < stop; ++i) {
      if (by_runs)
        batches_.append_query(cell_list_, i, with_self, batch);
      else
        for_each_near(i, pusher(batch, i, with_self));
      batch.hand_over_if_full(f);
    }
    batch.hand_over_rest(f);
  });
}

#define PARTC_NEIGHBOUR_SEARCH_INSTANCE(prefix, D)                                        \
  prefix class NeighbourSearch<D>;                                                        \
  prefix const std::vector<std::size_t>* NeighbourSearch<D>::build_structure(             \
      const Domain<D>&, double, const std::vector<Vec<D, double>>&);                      \
  prefix const std::vector<std::size_t>* NeighbourSearch<D>::build_structure(             \
      const Domain<D>&, double, const std::vector<Vec<D, float>>&)

PARTC_NEIGHBOUR_SEARCH_INSTANCE(extern template, 1);
PARTC_NEIGHBOUR_SEARCH_INSTANCE(extern template, 2);
PARTC_NEIGHBOUR_SEARCH_INSTANCE(extern template, 3);
PARTC_NEIGHBOUR_SEARCH_INSTANCE(extern template, 4);

}  // namespace partc
