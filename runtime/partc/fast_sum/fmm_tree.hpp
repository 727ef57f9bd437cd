// partc/fast_sum/fmm_tree.hpp: the adaptive 2^D-tree of the fast summation:
// boxes split while they hold more than a leaf's worth of points, so
// clustered points (a Plummer sphere) get deep trees where they are dense and
// shallow ones elsewhere.
//
//   const Cube<3> cube = bounding_cube(sources, targets);
//   const Tree<3> tree = build_tree(sources, cube, leaf_size);
//
// Sources and targets get a tree each over one common cube, so a box is
// named by its level and integer cell alone, in either tree, and two boxes'
// separation is integer arithmetic (gap_in_cells).
//
// Surprises:
// - boxes are breadth first (by level) and a box's children are contiguous;
//   only non-empty children exist, so a box has 1 to 2^D of them.
// - a box whose points all coincide is a leaf whatever its count (splitting
//   it would never separate them); so is a box at max_level.
// - a point's box is found from (x - origin) / side scaled by 2^level (an
//   exact scaling), so a point never changes its mind between levels.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "partc/vec.hpp"

namespace partc::fast_sum {

template <int D>
struct Cube {
  Vec<D> origin;
  double side;
};

// The smallest cube holding every point of a and b, widened a little so that
// the largest coordinate falls inside the last cell (side 1 if all coincide).
template <int D, class T>
Cube<D> bounding_cube(const std::vector<Vec<D, T>>& a, const std::vector<Vec<D, T>>& b) {
  Vec<D> lo = Vec<D>::filled(0), hi = Vec<D>::filled(0);
  bool any = false;
  for (const auto* set : {&a, &b})
    for (const Vec<D, T>& x : *set) {
      const Vec<D> y = x;
      if (!any) lo = hi = y;
      any = true;
      for (int d = 0; d < D; ++d) {
        lo[d] = std::min(lo[d], y[d]);
        hi[d] = std::max(hi[d], y[d]);
      }
    }
  double side = 0;
  for (int d = 0; d < D; ++d) side = std::max(side, hi[d] - lo[d]);
  side = side > 0 ? side * (1 + 1e-9) : 1.0;
  return {lo, side};
}

template <int D>
struct TreeBox {
  int level = 0;
  std::array<std::int64_t, D> cell{};  // the box is origin + side / 2^level * [cell, cell + 1)
  std::size_t first = 0, count = 0;    // its points are first .. first + count - 1 in tree order
  int parent = -1;
  int first_child = -1,
      children = 0;  // children are boxes first_child .. first_child + children - 1
  bool leaf() const { return children == 0; }
};

template <int D>
struct Tree {
  static constexpr int max_level = 40;
  Cube<D> cube;
  std::vector<TreeBox<D>> boxes;
  std::vector<std::size_t>
      level_begin;                 // level l's boxes: level_begin[l] .. level_begin[l + 1] - 1
  std::vector<int> leaves;         // ids of the leaf boxes, ascending
  std::vector<std::size_t> index;  // index[k]: the caller's index of the k-th point in tree order
  std::array<std::vector<double>, D> coords;  // positions in tree order, one array per dimension

  int levels() const { return static_cast<int>(level_begin.size()) - 1; }
  double box_side(int level) const { return std::ldexp(cube.side, -level); }
  double centre(const TreeBox<D>& b, int d) const {
    return cube.origin[d] + (double(b.cell[static_cast<std::size_t>(d)]) + 0.5) * box_side(b.level);
  }
};

template <int D, class T>
Tree<D> build_tree(const std::vector<Vec<D, T>>& points, const Cube<D>& cube,
                   std::size_t leaf_size) {
  Tree<D> tree;
  tree.cube = cube;
  const std::size_t n = points.size();
  // u: positions scaled to the unit cube, the only thing splitting looks at.
  std::vector<std::array<double, D>> u(n);
  for (std::size_t i = 0; i < n; ++i)
    for (int d = 0; d < D; ++d)
      u[i][static_cast<std::size_t>(d)] = (double(points[i][d]) - cube.origin[d]) / cube.side;
  tree.index.resize(n);
  for (std::size_t i = 0; i < n; ++i) tree.index[i] = i;
  std::vector<std::size_t> scratch(n);

  TreeBox<D> root;
  root.count = n;
  tree.boxes.push_back(root);
  constexpr int fan = 1 << D;
  for (std::size_t b = 0; b < tree.boxes.size(); ++b) {
    const TreeBox<D> box = tree.boxes[b];  // a copy: push_back below may move the boxes
    if (box.count <= leaf_size || box.level >= Tree<D>::max_level) continue;
    const std::size_t* ids = tree.index.data() + box.first;
    bool all_coincide = true;
    for (std::size_t k = 1; k < box.count && all_coincide; ++k)
      all_coincide = u[ids[k]] == u[ids[0]];
    if (all_coincide) continue;

    const double scale = std::ldexp(1.0, box.level + 1);
    const std::int64_t cells = std::int64_t(1) << (box.level + 1);
    auto child_of = [&](std::size_t i) {
      int code = 0;
      for (int d = 0; d < D; ++d) {
        const auto c = std::clamp<std::int64_t>(
            std::int64_t(std::floor(u[i][static_cast<std::size_t>(d)] * scale)), 0, cells - 1);
        code |= int(c - 2 * box.cell[static_cast<std::size_t>(d)]) << d;
      }
      return code;
    };
    // A stable counting sort of the box's points by child.
    std::array<std::size_t, fan + 1> start{};
    for (std::size_t k = 0; k < box.count; ++k)
      ++start[static_cast<std::size_t>(child_of(ids[k]) + 1)];
    for (int c = 0; c < fan; ++c)
      start[static_cast<std::size_t>(c + 1)] += start[static_cast<std::size_t>(c)];
    std::array<std::size_t, fan + 1> next = start;
    for (std::size_t k = 0; k < box.count; ++k)
      scratch[next[static_cast<std::size_t>(child_of(ids[k]))]++] = ids[k];
    std::copy(scratch.begin(), scratch.begin() + std::ptrdiff_t(box.count),
              tree.index.begin() + std::ptrdiff_t(box.first));

    tree.boxes[b].first_child = static_cast<int>(tree.boxes.size());
    for (int c = 0; c < fan; ++c) {
      const std::size_t count =
          start[static_cast<std::size_t>(c + 1)] - start[static_cast<std::size_t>(c)];
      if (count == 0) continue;
      TreeBox<D> child;
      child.level = box.level + 1;
      for (int d = 0; d < D; ++d)
        child.cell[static_cast<std::size_t>(d)] =
            2 * box.cell[static_cast<std::size_t>(d)] + ((c >> d) & 1);
      child.first = box.first + start[static_cast<std::size_t>(c)];
      child.count = count;
      child.parent = static_cast<int>(b);
      tree.boxes.push_back(child);
      ++tree.boxes[b].children;
    }
  }

  for (std::size_t b = 0; b < tree.boxes.size(); ++b) {
    while (tree.level_begin.size() <= static_cast<std::size_t>(tree.boxes[b].level))
      tree.level_begin.push_back(b);
    if (tree.boxes[b].leaf()) tree.leaves.push_back(static_cast<int>(b));
  }
  tree.level_begin.push_back(tree.boxes.size());
  for (int d = 0; d < D; ++d) {
    auto& c = tree.coords[static_cast<std::size_t>(d)];
    c.resize(n);
    for (std::size_t k = 0; k < n; ++k) c[k] = double(points[tree.index[k]][d]);
  }
  return tree;
}

// The gap between boxes a and b counted in cells of the finer one's level,
// in the max norm: 0 if they touch or overlap, 1 if one cell of the finer
// level fits between them along some dimension, and so on.
template <int D>
std::int64_t gap_in_cells(const TreeBox<D>& a, const TreeBox<D>& b) {
  const int level = std::max(a.level, b.level);
  std::int64_t gap = 0;
  for (std::size_t d = 0; d < D; ++d) {
    const std::int64_t a_lo = a.cell[d] << (level - a.level), a_hi = (a.cell[d] + 1)
                                                                     << (level - a.level);
    const std::int64_t b_lo = b.cell[d] << (level - b.level), b_hi = (b.cell[d] + 1)
                                                                     << (level - b.level);
    gap = std::max({gap, a_lo - b_hi, b_lo - a_hi});
  }
  return gap;
}

}  // namespace partc::fast_sum
