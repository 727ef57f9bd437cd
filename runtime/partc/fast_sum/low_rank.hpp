// partc/fast_sum/low_rank.hpp: a square matrix as the product of two thin
// ones, K ~ left * right (n x k times k x n), dropping the singular values
// below eps times the largest: the SVD compression of the M2L operators
// (Fong & Darve 2009, section 3; one factorisation per canonical operator as
// in Messner, Schanz & Darve 2012). Between well-separated boxes the kernel
// has low numerical rank (k ~ 30 to 100 of n = 512 or 1000 nodes in 3D at
// eps 1e-8 to 1e-10, whatever the order), so an M2L product costs 4 n k
// flops instead of 2 n^2.
//
// The factorisation is randomised (Halko, Martinsson & Tropp 2011): the range
// of K Omega, Omega fixed pseudo-random columns added 16 at a time until K
// Omega adds nothing above eps times its largest column, orthonormalised to
// Q; then
// K ~ Q (Q^T K), and an SVD of the small factor, by QR and one-sided Jacobi,
// picks the kept directions.
//
// Surprises:
// - deterministic: the random columns come from a fixed sequence and every
//   sum runs in one order (multiply_panel, loops whose SIMD reductions are
//   fixed by the build; no Eigen, whose products block by thread count), so
//   a plan is the same on any threads.
// - it gives up (rank 0: keep K as it is) when the range reaches n / 2,
//   where the two thin products cost as much as K's.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "partc/fast_sum/m2l_operators.hpp"

namespace partc::fast_sum {

// Without OpenMP (or -fopenmp-simd) the simd pragmas are plain loops.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunknown-pragmas"

// The error the compression may add to the fast sum's, as a share of the
// interpolation's: an operator's dropped singular values, relative to its
// largest, are below compression_share times the interpolation's predicted
// error (error_model.hpp); fmm.hpp adds the share to the prediction.
constexpr double compression_share = 0.25;

struct LowRank {
  int rank = 0;               // 0: no compression paid
  std::vector<double> left;   // n x rank, row-major
  std::vector<double> right;  // rank x n, row-major
};

namespace detail {

// v (length n) made orthogonal to the `count` orthonormal columns u (each of
// length n, one after another), twice (once is not enough in floating point).
inline void project_out(const double* u, std::size_t count, std::size_t n, double* v) {
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t i = 0; i < count; ++i) {
      const double* ui = u + i * n;
      double dot = 0;
#pragma omp simd reduction(+ : dot)
      for (std::size_t m = 0; m < n; ++m) dot += ui[m] * v[m];
      for (std::size_t m = 0; m < n; ++m) v[m] -= dot * ui[m];
    }
}

inline double norm(const double* v, std::size_t n) {
  double sum = 0;
#pragma omp simd reduction(+ : sum)
  for (std::size_t m = 0; m < n; ++m) sum += v[m] * v[m];
  return std::sqrt(sum);
}

// z = k x for `count` columns x (each of length n, one after another),
// giving columns of length n: through multiply_panel, rows of k in chunks
// that stay in cache while every panel passes.
inline std::vector<double> multiply_columns(const std::vector<double>& k, std::size_t n,
                                            const double* x, std::size_t count) {
  constexpr std::size_t w = panel_width, chunk = 64;
  const std::size_t panels = (count + w - 1) / w;
  std::vector<double> in(panels * n * w, 0.0), out(panels * n * w), z(n * count);
  for (std::size_t j = 0; j < count; ++j)
    for (std::size_t m = 0; m < n; ++m) in[(j / w * n + m) * w + j % w] = x[j * n + m];
  for (std::size_t row = 0; row < n; row += chunk)
    for (std::size_t panel = 0; panel < panels; ++panel)
      multiply_panel(k.data() + row * n, int(std::min(chunk, n - row)), int(n),
                     in.data() + panel * n * w, out.data() + (panel * n + row) * w);
  for (std::size_t j = 0; j < count; ++j)
    for (std::size_t m = 0; m < n; ++m) z[j * n + m] = out[(j / w * n + m) * w + j % w];
  return z;
}

// One-sided Jacobi on the l columns (length l each) of g: rotations J with
// g J's columns orthogonal; g becomes g J, v (identity on entry) becomes J.
inline void jacobi_orthogonalise(std::vector<double>& g, std::vector<double>& v, std::size_t l) {
  for (int sweep = 0; sweep < 60; ++sweep) {
    bool rotated = false;
    for (std::size_t i = 0; i < l; ++i)
      for (std::size_t j = i + 1; j < l; ++j) {
        double* gi = g.data() + i * l;
        double* gj = g.data() + j * l;
        double a = 0, b = 0, c = 0;
#pragma omp simd reduction(+ : a, b, c)
        for (std::size_t m = 0; m < l; ++m) {
          a += gi[m] * gi[m];
          b += gj[m] * gj[m];
          c += gi[m] * gj[m];
        }
        if (std::abs(c) <= 1e-15 * std::sqrt(a * b) || c == 0) continue;
        rotated = true;
        const double zeta = (b - a) / (2 * c);
        const double t = (zeta >= 0 ? 1.0 : -1.0) / (std::abs(zeta) + std::sqrt(1 + zeta * zeta));
        const double cs = 1 / std::sqrt(1 + t * t), sn = cs * t;
        auto rotate = [&](double* x, double* y) {
          for (std::size_t m = 0; m < l; ++m) {
            const double xm = x[m], ym = y[m];
            x[m] = cs * xm - sn * ym;
            y[m] = sn * xm + cs * ym;
          }
        };
        rotate(gi, gj);
        rotate(v.data() + i * l, v.data() + j * l);
      }
    if (!rotated) break;
  }
}

}  // namespace detail

// k: n x n row-major. The kept singular values are those above eps times the largest.
inline LowRank compress(const std::vector<double>& k, int n, double eps) {
  constexpr std::size_t block = 16;
  const std::size_t size = std::size_t(n);
  std::uint64_t state = 0x9e3779b97f4a7c15ULL;
  auto random = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return double(state >> 11) * 0x1p-52 - 1.0;
  };
  // Q: an orthonormal basis of K's range, l columns of length n, grown a
  // block at a time until a whole block of samples K omega lies within eps
  // times the largest sample's norm of the range found so far (the adaptive
  // range finder of Halko et al., section 4.4).
  std::vector<double> q;
  std::size_t l = 0;
  double largest_sample = 0;
  for (bool found = false; !found;) {
    if (2 * (l + block) > size) return {};
    std::vector<double> omega(block * size);
    for (double& x : omega) x = random();
    std::vector<double> y = detail::multiply_columns(k, size, omega.data(), block);
    for (std::size_t j = 0; j < block; ++j)
      largest_sample = std::max(largest_sample, detail::norm(y.data() + j * size, size));
    double residual = 0;
    for (std::size_t j = 0; j < block; ++j) {
      double* v = y.data() + j * size;
      detail::project_out(q.data(), l, size, v);
      residual = std::max(residual, detail::norm(v, size));
    }
    found = residual <= eps * largest_sample;
    for (std::size_t j = 0; j < block; ++j) {
      double* v = y.data() + j * size;
      detail::project_out(y.data(), j, size, v);
      detail::project_out(q.data(), l, size, v);
      const double length = detail::norm(v, size);
      for (std::size_t m = 0; m < size; ++m) v[m] = length > 0 ? v[m] / length : 0.0;
    }
    q.insert(q.end(), y.begin(), y.end());
    l += block;
  }
  // K ~ Q B with B = Q^T K; B^T = K^T Q = Q2 R (Q2: n x l, orthonormal).
  std::vector<double> kt(size * size);
  for (std::size_t r = 0; r < size; ++r)
    for (std::size_t c = 0; c < size; ++c) kt[c * size + r] = k[r * size + c];
  const std::vector<double> bt = detail::multiply_columns(kt, size, q.data(), l);
  std::vector<double> q2 = bt;
  for (std::size_t j = 0; j < l; ++j) {
    double* v = q2.data() + j * size;
    detail::project_out(q2.data(), j, size, v);
    const double length = detail::norm(v, size);
    for (std::size_t m = 0; m < size; ++m) v[m] = length > 0 ? v[m] / length : 0.0;
  }
  // R = Q2^T B^T (l x l), so K ~ Q R^T Q2^T; g holds R^T's columns.
  std::vector<double> g(l * l, 0.0);
  for (std::size_t i = 0; i < l; ++i)
    for (std::size_t j = 0; j < l; ++j) {
      const double* row = q2.data() + j * size;
      const double* column = bt.data() + i * size;
      double dot = 0;
#pragma omp simd reduction(+ : dot)
      for (std::size_t m = 0; m < size; ++m) dot += row[m] * column[m];
      g[j * l + i] = dot;
    }
  std::vector<double> v(l * l, 0.0);
  for (std::size_t i = 0; i < l; ++i) v[i * l + i] = 1;
  detail::jacobi_orthogonalise(g, v, l);  // R^T J = G, so K ~ (Q G) (Q2 J)^T
  std::vector<double> sigma(l);
  for (std::size_t i = 0; i < l; ++i) sigma[i] = detail::norm(g.data() + i * l, l);
  const double largest = *std::max_element(sigma.begin(), sigma.end());
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < l; ++i)
    if (sigma[i] > eps * largest) kept.push_back(i);
  LowRank out;
  const std::size_t rank = kept.size();
  out.rank = int(rank);
  std::vector<double> left_columns(rank * size, 0.0);
  out.right.assign(rank * size, 0.0);
  for (std::size_t c = 0; c < rank; ++c) {
    const double* gc = g.data() + kept[c] * l;
    const double* vc = v.data() + kept[c] * l;
    double* left_c = left_columns.data() + c * size;
    double* right_c = out.right.data() + c * size;
    for (std::size_t j = 0; j < l; ++j)
      for (std::size_t m = 0; m < size; ++m) {
        left_c[m] += q[j * size + m] * gc[j];
        right_c[m] += q2[j * size + m] * vc[j];
      }
  }
  out.left.resize(size * rank);
  for (std::size_t c = 0; c < rank; ++c)
    for (std::size_t m = 0; m < size; ++m) out.left[m * rank + c] = left_columns[c * size + m];
  return out;
}

#pragma GCC diagnostic pop

}  // namespace partc::fast_sum
