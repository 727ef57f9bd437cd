// partc/fast_sum/m2l_operators.hpp: the multipole-to-local (M2L) operators
// between same-level boxes, and their product with many multipoles at once.
//
// The M2L operator from a source box to a well-separated target box of side
// h is the kernel between their Chebyshev nodes, K[m][n] = k(|y_n - x_m|),
// a p^D x p^D matrix that depends only on h (the level) and the integer
// offset o of the source box from the target box, each |o_d| <= 3. A signed
// permutation R of the axes (48 in 3D) that maps o to a canonical offset o'
// (components ascending and non-negative) maps the node grid onto itself, so
//   K_o[m][n] = K_o'[pi(m)][pi(n)],   pi the node permutation of R,
// and only the canonical offsets need a matrix: 16 per level in 3D instead of
// 316 (Messner, Schanz & Darve 2012). Applying K_o to a multipole W is then:
// permute W by pi, multiply by K_o', read the result through pi. Where it
// pays, K_o' is then compressed to two thin factors (low_rank.hpp), and the
// product is two multiply_panel calls through k coefficients.
//
// Surprises:
// - multiply_panel does the GEMM itself (register-blocked, 4 rows by 8
//   columns): Eigen's product chooses its blocking from its thread count, so
//   its sums are not bitwise the same for every thread count; here every
//   entry is summed over k in order, whatever runs it.
// - with FMA hardware (__FMA__) the products are fused, so results differ
//   (in the last bits) between builds with and without -march=native.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include "partc/fast_sum/chebyshev.hpp"

namespace partc::fast_sum {

// The signed permutations of D axes, and the node permutation of each.
template <int D>
class Symmetries {
 public:
  // Offsets with every |o_d| <= 3 are coded in base 4 after canonicalisation.
  static constexpr int codes = 1 << (2 * D);

  explicit Symmetries(const ChebyshevBasis& basis) {
    std::array<int, D> axes;
    std::iota(axes.begin(), axes.end(), 0);
    do perms_.push_back(axes);
    while (std::next_permutation(axes.begin(), axes.end()));
    const int p = basis.order();
    int n = 1;
    for (int d = 0; d < D; ++d) n *= p;
    for (const auto& perm : perms_)
      for (int flips = 0; flips < (1 << D); ++flips) {
        std::vector<int> map(static_cast<std::size_t>(n));
        for (int m = 0; m < n; ++m) {
          std::array<int, D> digit;
          for (int d = 0, rest = m; d < D; ++d, rest /= p)
            digit[static_cast<std::size_t>(d)] = rest % p;
          int image = 0;
          for (int k = D - 1; k >= 0; --k) {
            const int axis = perm[static_cast<std::size_t>(k)];
            const int i = digit[static_cast<std::size_t>(axis)];
            image = image * p + ((flips >> axis) & 1 ? p - 1 - i : i);
          }
          map[static_cast<std::size_t>(m)] = image;
        }
        node_maps_.push_back(std::move(map));
      }
  }

  struct Canonical {
    int code;      // the canonical offset o', sum_k o'_k 4^k
    int symmetry;  // which R maps o to o': node_map(symmetry) is its pi
  };
  Canonical canonicalize(const std::array<std::int64_t, D>& offset) const {
    int flips = 0;
    std::array<std::int64_t, D> size;
    for (int d = 0; d < D; ++d) {
      if (offset[static_cast<std::size_t>(d)] < 0) flips |= 1 << d;
      size[static_cast<std::size_t>(d)] = std::abs(offset[static_cast<std::size_t>(d)]);
    }
    std::array<int, D> perm;
    std::iota(perm.begin(), perm.end(), 0);
    for (int i = 1; i < D; ++i)  // insertion sort by size, stable: D is at most 3
      for (int j = i;
           j > 0 && size[static_cast<std::size_t>(perm[static_cast<std::size_t>(j)])] <
                        size[static_cast<std::size_t>(perm[static_cast<std::size_t>(j - 1)])];
           --j)
        std::swap(perm[static_cast<std::size_t>(j)], perm[static_cast<std::size_t>(j - 1)]);
    const int rank =
        static_cast<int>(std::find(perms_.begin(), perms_.end(), perm) - perms_.begin());
    int code = 0;
    for (int k = D - 1; k >= 0; --k)
      code = code * 4 + int(size[static_cast<std::size_t>(perm[static_cast<std::size_t>(k)])]);
    return {code, rank * (1 << D) + flips};
  }
  static std::array<int, D> decode(int code) {
    std::array<int, D> o;
    for (int d = 0; d < D; ++d, code /= 4) o[static_cast<std::size_t>(d)] = code % 4;
    return o;
  }

  const std::vector<int>& node_map(int symmetry) const {
    return node_maps_[static_cast<std::size_t>(symmetry)];
  }

 private:
  std::vector<std::array<int, D>> perms_;
  std::vector<std::vector<int>> node_maps_;
};

// The p^D x p^D operator, row-major, for boxes of side h at canonical offset
// `code`: row m (target node), column n (source node).
template <int D, class Kernel>
std::vector<double> m2l_matrix(const Kernel& kernel, const ChebyshevBasis& basis, double h,
                               int code) {
  const int p = basis.order();
  int n = 1;
  for (int d = 0; d < D; ++d) n *= p;
  const std::array<int, D> o = Symmetries<D>::decode(code);
  std::vector<std::array<double, D>> node(static_cast<std::size_t>(n));
  for (int m = 0; m < n; ++m)
    for (int d = 0, rest = m; d < D; ++d, rest /= p)
      node[static_cast<std::size_t>(m)][static_cast<std::size_t>(d)] = h / 2 * basis.node(rest % p);
  std::vector<double> k(static_cast<std::size_t>(n) * static_cast<std::size_t>(n));
  for (int m = 0; m < n; ++m)
    for (int j = 0; j < n; ++j) {
      double r2 = 0;
      for (std::size_t d = 0; d < D; ++d) {
        const double dx =
            h * o[d] + node[static_cast<std::size_t>(j)][d] - node[static_cast<std::size_t>(m)][d];
        r2 += dx * dx;
      }
      k[static_cast<std::size_t>(m) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)] =
          kernel(std::sqrt(r2));
    }
  return k;
}

constexpr int panel_width = 8;

inline double multiply_add(double a, double b, double c) {
#if defined(__FMA__)
  return std::fma(a, b, c);
#else
  return a * b + c;
#endif
}

// z = k x for one panel: k is rows x cols row-major, x is cols x
// panel_width and z rows x panel_width, row-major (the panel's 8 columns side
// by side). Four rows of k at a time keep 32 sums in registers; the column
// loop is what vectorises.
inline void multiply_panel(const double* k, int rows, int cols, const double* x, double* z) {
  constexpr int w = panel_width;
  const std::size_t n = std::size_t(cols);
  int row = 0;
  for (; row + 4 <= rows; row += 4) {
    double sum[4][w] = {};
    const double* k0 = k + std::size_t(row) * n;
    const double* k1 = k0 + n;
    const double* k2 = k1 + n;
    const double* k3 = k2 + n;
    for (int j = 0; j < cols; ++j) {
      const double* xj = x + std::size_t(j) * w;
      for (int c = 0; c < w; ++c) {
        sum[0][c] = multiply_add(k0[j], xj[c], sum[0][c]);
        sum[1][c] = multiply_add(k1[j], xj[c], sum[1][c]);
        sum[2][c] = multiply_add(k2[j], xj[c], sum[2][c]);
        sum[3][c] = multiply_add(k3[j], xj[c], sum[3][c]);
      }
    }
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < w; ++c) z[std::size_t(row + r) * w + std::size_t(c)] = sum[r][c];
  }
  for (; row < rows; ++row) {
    double sum[w] = {};
    const double* kr = k + std::size_t(row) * n;
    for (int j = 0; j < cols; ++j)
      for (int c = 0; c < w; ++c)
        sum[c] = multiply_add(kr[j], x[std::size_t(j) * w + std::size_t(c)], sum[c]);
    for (int c = 0; c < w; ++c) z[std::size_t(row) * w + std::size_t(c)] = sum[c];
  }
}

}  // namespace partc::fast_sum
