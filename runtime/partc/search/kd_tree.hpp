// partc/search/kd_tree.hpp: KdTree<D>, a k-d tree for clustered or very non-uniform
// particle sets, where a cell list degrades (a few cells hold most points and
// every query scans them). A query costs about log N plus its neighbours
// whatever the distribution; build is O(N log N). Measured (2D, ~20 neighbours
// per query, g++ -O2): ~470 ns per query at any clustering; OrderedCellList
// ~120 ns on uniform points, ~1 ns per point it examines beyond that, so the
// tree wins once the cell list examines more than ~400 points per query.
//
// Query contract: as BruteForce (brute_force.hpp). Also for_each_in_box (the
// points in an axis-aligned box) and nearest (the k nearest points, for any k;
// it does not use the build radius).
//
// Structure: build copies the points, wrapped into the periodic box, and sorts
// them so that every node is a contiguous range; a node keeps the tight
// bounding box of its points. A node of more than leaf_size points is split at
// the median along its box's widest extent (std::nth_element), so its halves
// differ in size by at most one and the depth stays below 64 whatever the data;
// a box of zero extent (identical points) is not split: it is one leaf, of any
// size. Nodes are stored breadth-first with children adjacent; nothing recurses.
//
// Periodic dimensions, per dimension at build:
// - Images (L >= 3 * reach, reach = radius * (1 + 1e-12)): the tree is walked
//   once per image q + s*L (s = -1, 0, 1) whose reach overlaps the root's box,
//   with plain box pruning and dx = p - (q + s*L), no per-pair minimum_image.
//   Images of q are L >= 3 * reach apart, so a point is within reach of at most
//   one of them (with a margin no rounding of q + s*L can eat), and that one is
//   its minimum image (reach < L/2). CellGrid's ">= 3 cells" rule, in effect.
// - Exact (3 * reach > L): one walk, dx = minimum_image(p - q) per pair, and the
//   box distance taken the shorter way round the torus. Here two images of q
//   may both reach a point (radius > L/2) and only the shorter vector may be
//   reported. Measured 1.7x slower per query than images, hence two modes.
//   nearest always works this way: it has no radius.
// Pruning (squared_gap) uses the pair test's own roundings, so it never drops
// a point the pair test would accept, even one exactly at the radius.
//
// Surprises:
// - j in f(j, ...) and in nearest's result indexes the SORTED order, not the
//   caller's: order() maps it back (sorted[k] = points[order()[k]]); a caller
//   wanting j to index its particle arrays permutes them with order() right
//   after build (ParticleSet::permute(order())), as for OrderedCellList.
//   Equal points do not keep their relative order (nth_element is not stable),
//   but the order is deterministic.
// - Points with a non-finite coordinate (NaN; also +-inf, which could never be
//   within reach) are placed last in order(), outside the tree: no query
//   reports them. A query point with a non-finite coordinate finds nothing.
// - for_each_in_box's box is not periodic: it is compared with the stored,
//   wrapped coordinates, so a box reaching past a periodic face does not wrap
//   round (split it there), and f receives the wrapped point.
// - nearest ranks by the distance |dx| (ties by j), computed as
//   sqrt(|dx|^2): distances that round to the same double are ties.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

#include "partc/domain.hpp"
#include "partc/search/search_instances.hpp"
#include "partc/vec.hpp"

namespace partc {

template <int D>
class KdTree {
 public:
  // Leaves of 6 to 12 points (any number if identical). Measured (2D, uniform and
  // clustered, N = 10^4 and 10^5): a limit of 8 makes queries ~10% slower, 16 and
  // 24 are within noise.
  static constexpr std::size_t leaf_size = 12;

  template <class T>
  void build(const Domain<D>& domain, double radius, const std::vector<Vec<D, T>>& points) {
    check_search_arguments(domain, radius);
    domain_ = domain;
    squared_reach_ = radius * radius * (1 + 1e-12);
    const double reach = radius * (1 + 1e-12);
    exact_domain_ = domain;
    exact_ = false;
    for (int k = 0; k < D; ++k) {
      exact_domain_.periodic[k] = domain.periodic[k] && !(3 * reach <= domain.hi[k] - domain.lo[k]);
      exact_ = exact_ || exact_domain_.periodic[k];
    }
    entries_.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) entries_[i] = {domain.wrap(points[i]), i};
    const auto finite_end = std::partition(entries_.begin(), entries_.end(),
                                           [](const Entry& e) { return is_finite(e.p); });
    nodes_.clear();
    if (finite_end != entries_.begin())
      nodes_.push_back({{}, {}, 0, static_cast<std::size_t>(finite_end - entries_.begin()), 0});
    for (std::size_t i = 0; i < nodes_.size(); ++i) split(i);  // appends children: breadth-first
    points_.resize(entries_.size());
    order_.resize(entries_.size());
    for (std::size_t k = 0; k < entries_.size(); ++k) {
      points_[k] = entries_[k].p;
      order_[k] = entries_[k].index;
    }
  }

  template <class F>
  void for_each_near(const Vec<D>& q, F&& f) const {
    const Vec<D> qw = domain_.wrap(q);
    if (nodes_.empty() || !is_finite(qw)) return;
    // Per dimension, the query coordinates to walk with: qw itself, or in a periodic
    // dimension in image mode, those of qw - L, qw, qw + L whose reach meets the root's
    // box (the walk would prune the others at the root, but there are 3^D combinations).
    std::array<std::array<double, 3>, D> images;
    std::array<int, D> count{};
    const Node& root = nodes_[0];
    for (int k = 0; k < D; ++k) {
      if (!domain_.periodic[k] || exact_domain_.periodic[k]) {
        images[k][count[k]++] = qw[k];
        continue;
      }
      const double L = domain_.hi[k] - domain_.lo[k];
      for (const double qs : {qw[k] - L, qw[k], qw[k] + L}) {
        const double gap = std::max({0.0, root.lo[k] - qs, qs - root.hi[k]});  // as squared_gap
        if (gap * gap <= squared_reach_) images[k][count[k]++] = qs;
      }
      if (count[k] == 0) return;
    }
    std::array<int, D> m{};  // odometer over the combinations of images
    Vec<D> qs;
    while (true) {
      for (int k = 0; k < D; ++k) qs[k] = images[k][m[k]];
      if (exact_)
        walk_near<true>(qs, f);
      else
        walk_near<false>(qs, f);
      int k = 0;
      while (k < D && ++m[k] == count[k]) m[k++] = 0;
      if (k == D) return;
    }
  }

  // Point k of the last build (sorted order), wrapped into the periodic box.
  const Vec<D>& point(std::size_t k) const { return points_[k]; }

  // f(j, point) for every point with lo <= point <= hi componentwise (point as
  // stored: wrapped into the periodic box).
  template <class F>
  void for_each_in_box(const Vec<D>& lo, const Vec<D>& hi, F&& f) const {
    const auto meets = [&](const Vec<D>& a, const Vec<D>& b) {  // [a, b] meets [lo, hi]
      for (int k = 0; k < D; ++k)
        if (!(b[k] >= lo[k] && a[k] <= hi[k])) return false;  // false for NaN bounds too
      return true;
    };
    walk([&](const Node& node) { return meets(node.lo, node.hi); },
         [&](const Node& node) {
           for (std::size_t j = node.begin; j < node.end; ++j)
             if (inside(points_[j], lo, hi)) f(j, points_[j]);
         },
         [](const Node&) { return false; });
  }

  // The min(k, number of finite points) nearest points to q as (j, distance),
  // sorted by distance, then j; distances are minimum-image in periodic dimensions.
  std::vector<std::pair<std::size_t, double>> nearest(const Vec<D>& q, std::size_t k) const {
    const Vec<D> qw = domain_.wrap(q);
    if (k == 0 || !is_finite(qw)) return {};
    std::vector<std::pair<double, std::size_t>> best;  // max-heap: the k-th nearest so far on top
    best.reserve(std::min(k, points_.size()));
    // sqrt is monotone, so sqrt(squared_gap) bounds the distances in a node from below.
    const auto gap = [&](const Node& node) { return std::sqrt(squared_gap(node, qw, domain_)); };
    walk([&](const Node& node) {  // <=: a node at the k-th distance may hold a smaller j
           return best.size() < k || gap(node) <= best.front().first;
         },
         [&](const Node& node) {
           for (std::size_t j = node.begin; j < node.end; ++j) {
             const std::pair<double, std::size_t> candidate(
                 norm(domain_.minimum_image(points_[j] - qw)), j);
             if (best.size() == k) {
               if (!(candidate < best.front())) continue;
               std::pop_heap(best.begin(), best.end());
               best.pop_back();
             }
             best.push_back(candidate);
             std::push_heap(best.begin(), best.end());
           }
         },
         // The nearer child first, so that the heap fills with near points early.
         [&](const Node& node) { return gap(nodes_[node.child + 1]) < gap(nodes_[node.child]); });
    std::sort_heap(best.begin(), best.end());
    std::vector<std::pair<std::size_t, double>> result(best.size());
    for (std::size_t i = 0; i < best.size(); ++i) result[i] = {best[i].second, best[i].first};
    return result;
  }

  // The permutation of the last build: sorted[k] = points[order()[k]].
  const std::vector<std::size_t>& order() const { return order_; }
  std::size_t node_count() const { return nodes_.size(); }

 private:
  struct Node {
    Vec<D> lo, hi;           // bounding box of the node's points
    std::size_t begin, end;  // its points: points_[begin .. end-1]
    std::size_t child;       // children at child, child + 1; 0 (the root) for a leaf
  };
  struct Entry {
    Vec<D> p;
    std::size_t index;
  };

  // Sets node i's box and, unless it is a leaf, partitions its points around the
  // median of the widest extent and appends its two children.
  void split(std::size_t i) {
    Node& node = nodes_[i];
    node.lo = node.hi = entries_[node.begin].p;
    for (std::size_t j = node.begin + 1; j < node.end; ++j) {
      for (int k = 0; k < D; ++k) {
        node.lo[k] = std::min(node.lo[k], entries_[j].p[k]);
        node.hi[k] = std::max(node.hi[k], entries_[j].p[k]);
      }
    }
    int widest = 0;
    for (int k = 1; k < D; ++k)
      if (node.hi[k] - node.lo[k] > node.hi[widest] - node.lo[widest]) widest = k;
    if (node.end - node.begin <= leaf_size || !(node.hi[widest] > node.lo[widest])) return;
    const std::size_t begin = node.begin, middle = begin + (node.end - begin) / 2, end = node.end;
    const auto by_widest = [widest](const Entry& a, const Entry& b) {
      return a.p[widest] < b.p[widest];
    };
    Entry* const e = entries_.data();
    std::nth_element(e + begin, e + middle, e + end, by_widest);
    node.child = nodes_.size();
    nodes_.push_back({{}, {}, begin, middle, 0});  // invalidates node
    nodes_.push_back({{}, {}, middle, end, 0});
  }

  // A lower bound of |dx|^2 over the points p of node seen from q: per dimension,
  // the distance from q to the box's interval; in the dimensions periodic in
  // `exact`, also the way round the torus. Built from the pair test's own
  // operations (p - q, then minimum_image's single shift by L), each monotone in p,
  // so it never exceeds a point's computed |dx|^2 (points and q wrapped there).
  static double squared_gap(const Node& node, const Vec<D>& q, const Domain<D>& exact) {
    Vec<D> gap;
    for (int k = 0; k < D; ++k) {
      const double below = node.lo[k] - q[k], above = node.hi[k] - q[k];  // p - q in [below, above]
      gap[k] = std::max({0.0, below, -above});
      if (!exact.periodic[k]) continue;
      const double L = exact.hi[k] - exact.lo[k], half = 0.5 * L;
      if (above > half) gap[k] = std::min(gap[k], L - above);   // p - q - L
      if (below < -half) gap[k] = std::min(gap[k], below + L);  // p - q + L
    }
    return squared_norm(gap);
  }

  // Depth-first: leaf(node) for every leaf that passes keep(node) with all of its
  // ancestors; keep is asked when a node is reached, so it may tighten as the walk
  // goes. second_first(node) visits node's second child before its first. The
  // stack holds one pending sibling per level: depth < 64, as a split halves a
  // size_t count of points.
  template <class Keep, class Leaf, class SecondFirst>
  void walk(Keep&& keep, Leaf&& leaf, SecondFirst&& second_first) const {
    if (nodes_.empty()) return;
    std::size_t stack[std::numeric_limits<std::size_t>::digits + 1];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (!keep(node)) continue;
      if (node.child == 0) {
        leaf(node);
        continue;
      }
      const std::size_t second = second_first(node) ? 1 : 0;
      stack[top++] = node.child + 1 - second;  // popped last
      stack[top++] = node.child + second;
    }
  }

  // for_each_near for one image qs of the query. The leaf scan is the hot loop.
  template <bool Exact, class F>
  void walk_near(const Vec<D>& qs, F& f) const {
    walk([&](const Node& node) { return squared_gap(node, qs, exact_domain_) <= squared_reach_; },
         [&](const Node& node) {
           for (std::size_t j = node.begin; j < node.end; ++j) {
             Vec<D> dx = points_[j] - qs;
             if constexpr (Exact) dx = exact_domain_.minimum_image(dx);
             if (squared_norm(dx) <= squared_reach_) f(j, dx);
           }
         },
         [](const Node&) { return false; });
  }

  Domain<D> domain_{};
  Domain<D> exact_domain_{};  // periodic only in the dimensions in exact mode
  bool exact_ = false;        // some dimension is
  double squared_reach_ = 0.0;
  std::vector<Node> nodes_;     // nodes_[0] is the root; empty without finite points
  std::vector<Vec<D>> points_;  // wrapped, in tree order
  std::vector<std::size_t> order_;
  std::vector<Entry> entries_;  // build scratch, kept to reuse its memory
};

// Compiled once, in the runtime library (search_instances.hpp).
PARTC_SEARCH_INSTANCES(extern template, KdTree);

}  // namespace partc
