// partc/fast_sum/interactions.hpp: which box pairs of the target and source
// trees interact how, found by a dual tree traversal from the two roots.
//
// A pair of boxes is well separated when a cell of the finer one's level fits
// between them (gap_in_cells >= 1); the expansion then lives in the smaller
// box, whose interpolation error is set by the ratio of its size to the gap,
// the same as for two same-level boxes that are not neighbours. Then:
// - same level: M2L, through the operator of the pair's canonical offset
//   (m2l_operators.hpp), unless the target is a leaf and the two boxes hold
//   so few points that summing them directly is cheaper;
// - a target leaf and a smaller source box: the source's multipole evaluated
//   at the target's points (M2P), or their direct sum if the source holds no
//   more points than it has nodes;
// - a source leaf and a smaller target box: the source's points summed at
//   the target's nodes into its local expansion (P2L); a target with no more
//   points than nodes is split down to its leaves, which sum them directly.
// Pairs that are not separated are split, the larger box (both if of one
// level) until both are leaves, which sum directly (P2P). So of two boxes of
// different levels the larger is always a leaf.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <map>
#include <vector>

#include "partc/fast_sum/cost_model.hpp"
#include "partc/fast_sum/fmm_tree.hpp"
#include "partc/fast_sum/m2l_operators.hpp"

namespace partc::fast_sum {

struct M2lPair {
  int target, source, symmetry;
};

// The M2L pairs that share one operator: one level, one canonical offset.
struct M2lGroup {
  int level = 0, code = 0;
  std::vector<M2lPair> pairs;  // by target box (for the scatter), then in traversal order
};

// Consecutive source points (in the source tree's order).
struct PointRange {
  std::size_t first, count;
};

struct Interactions {
  std::vector<M2lGroup> m2l;  // by level, then canonical offset
  std::vector<std::vector<PointRange>>
      near;  // per target leaf: sources summed directly at its points
  std::vector<std::vector<int>>
      m2p;  // per target leaf: source boxes whose multipole is evaluated at its points
  std::vector<std::vector<int>> p2l;  // per target box: source leaves summed at its nodes
  std::size_t m2l_pairs = 0, m2p_pairs = 0, p2l_pairs = 0;
  double near_point_pairs = 0;  // point pairs summed directly
};

template <int D>
Interactions find_interactions(const Tree<D>& targets, const Tree<D>& sources,
                               const Symmetries<D>& symmetries, std::size_t nodes) {
  Interactions found;
  found.near.resize(targets.boxes.size());
  found.m2p.resize(targets.boxes.size());
  found.p2l.resize(targets.boxes.size());
  std::map<int, M2lGroup> groups;  // by level * codes + code
  auto near = [&](int t, int s) {
    const TreeBox<D>& sb = sources.boxes[static_cast<std::size_t>(s)];
    found.near[static_cast<std::size_t>(t)].push_back({sb.first, sb.count});
    found.near_point_pairs += double(targets.boxes[static_cast<std::size_t>(t)].count) *
                              double(sources.boxes[static_cast<std::size_t>(s)].count);
  };
  auto visit = [&](auto&& self, int t, int s) -> void {
    const TreeBox<D>& tb = targets.boxes[static_cast<std::size_t>(t)];
    const TreeBox<D>& sb = sources.boxes[static_cast<std::size_t>(s)];
    auto each_target_child = [&](auto&& f) {
      for (int c = tb.first_child; c < tb.first_child + tb.children; ++c) f(c);
    };
    auto each_source_child = [&](auto&& f) {
      for (int c = sb.first_child; c < sb.first_child + sb.children; ++c) f(c);
    };
    if (gap_in_cells(tb, sb) >= 1) {
      if (tb.level == sb.level) {
        if (tb.leaf() && direct_is_cheaper(D, tb.count, sb.count, nodes)) return near(t, s);
        std::array<std::int64_t, D> offset;
        for (std::size_t d = 0; d < D; ++d) offset[d] = sb.cell[d] - tb.cell[d];
        const auto canonical = symmetries.canonicalize(offset);
        M2lGroup& group = groups[tb.level * Symmetries<D>::codes + canonical.code];
        group.level = tb.level;
        group.code = canonical.code;
        group.pairs.push_back({t, s, canonical.symmetry});
        ++found.m2l_pairs;
      } else if (tb.level < sb.level) {
        if (sb.count <= nodes) return near(t, s);
        found.m2p[static_cast<std::size_t>(t)].push_back(s);
        ++found.m2p_pairs;
      } else if (tb.count > nodes) {
        found.p2l[static_cast<std::size_t>(t)].push_back(s);
        ++found.p2l_pairs;
      } else if (tb.leaf()) {
        near(t, s);
      } else {
        each_target_child([&](int c) { self(self, c, s); });
      }
      return;
    }
    if (tb.leaf() && sb.leaf()) return near(t, s);
    const bool split_target = !tb.leaf() && (sb.leaf() || tb.level <= sb.level);
    const bool split_source = !sb.leaf() && (tb.leaf() || sb.level <= tb.level);
    if (split_target && split_source)
      each_target_child([&](int ct) { each_source_child([&](int cs) { self(self, ct, cs); }); });
    else if (split_target)
      each_target_child([&](int ct) { self(self, ct, s); });
    else
      each_source_child([&](int cs) { self(self, t, cs); });
  };
  if (!targets.boxes.empty() && !sources.boxes.empty() && targets.boxes[0].count > 0 &&
      sources.boxes[0].count > 0)
    visit(visit, 0, 0);
  // Source boxes next to each other in the tree's order become one range:
  // fewer, longer direct loops.
  for (auto& ranges : found.near) {
    std::sort(ranges.begin(), ranges.end(),
              [](const PointRange& a, const PointRange& b) { return a.first < b.first; });
    std::vector<PointRange> merged;
    for (const PointRange& r : ranges)
      if (!merged.empty() && merged.back().first + merged.back().count == r.first)
        merged.back().count += r.count;
      else
        merged.push_back(r);
    ranges = std::move(merged);
  }
  for (auto& entry : groups) {
    std::stable_sort(entry.second.pairs.begin(), entry.second.pairs.end(),
                     [](const M2lPair& a, const M2lPair& b) { return a.target < b.target; });
    found.m2l.push_back(std::move(entry.second));
  }
  return found;
}

}  // namespace partc::fast_sum
