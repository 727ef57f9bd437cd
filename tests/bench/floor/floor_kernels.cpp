// The floor's kernels (see floor_kernels.hpp): shared/floor/floor.cpp's
// CellGrid, eval_compact_simd, build_nlist, build_sell4 and eval_sell4, with
// the arithmetic as there. Trimmed: only the exact-sqrt weight (floor.cpp's
// RS = false), the CSR list only as the step to SELL-4 (dx, dy, no j), and
// c passed in where floor.cpp has its constant kC = 1e-3.
#include "floor_kernels.hpp"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace floor_ref {

bool CellGrid::build(int n_, const double* x, const double* y, double rc_) {
  n = n_;
  rc = rc_;
  nc = int(std::floor(1.0 / rc));
  if (nc < 3) return false;  // 3x3 stencil would visit a cell twice
  np = nc + 2;
  const int ncell = nc * nc;
  std::vector<int> cell(n);
  cstart.assign(ncell + 1, 0);
  for (int i = 0; i < n; ++i) {
    int cx = std::min(int(x[i] * nc), nc - 1);
    int cy = std::min(int(y[i] * nc), nc - 1);
    cell[i] = cy * nc + cx;
    cstart[cell[i] + 1]++;
  }
  for (int c = 0; c < ncell; ++c) cstart[c + 1] += cstart[c];
  std::vector<int> fill(cstart.begin(), cstart.end() - 1);
  perm.resize(n);
  sx.resize(n);
  sy.resize(n);
  for (int i = 0; i < n; ++i) {
    int k = fill[cell[i]]++;
    perm[k] = i;
    sx[k] = x[i];
    sy[k] = y[i];
  }
  // Halo ring: padded cell (qx,qy), qx,qy in [0,np), holds the image of
  // interior cell ((qx-1) mod nc, (qy-1) mod nc) shifted by the box.
  pstart.assign(np * np + 1, 0);
  px.clear();
  py.clear();
  px.reserve(size_t(n) * np * np / ncell + kPad + 16);
  py.reserve(px.capacity());
  for (int qy = 0; qy < np; ++qy) {
    int syc = (qy - 1 + nc) % nc;
    double shy = qy == 0 ? -1.0 : (qy == np - 1 ? 1.0 : 0.0);
    for (int qx = 0; qx < np; ++qx) {
      int sxc = (qx - 1 + nc) % nc;
      double shx = qx == 0 ? -1.0 : (qx == np - 1 ? 1.0 : 0.0);
      pstart[qy * np + qx] = int(px.size());
      int c = syc * nc + sxc;
      for (int k = cstart[c]; k < cstart[c + 1]; ++k) {
        px.push_back(sx[k] + shx);
        py.push_back(sy[k] + shy);
      }
    }
  }
  pstart[np * np] = int(px.size());
  for (int k = 0; k < kPad; ++k) {
    px.push_back(1e3);
    py.push_back(1e3);
  }
  return true;
}

void CompactScratch::fit(const CellGrid& g) {
  size_t maxrow = 0;
  for (int cy = 0; cy < g.nc; ++cy)
    for (int cx = 0; cx < g.nc; ++cx) {
      size_t row = 0;
      for (int d = 0; d < 3; ++d)
        row += g.pstart[(cy + d) * g.np + cx + 3] - g.pstart[(cy + d) * g.np + cx];
      maxrow = std::max(maxrow, row);
    }
  if (bx.size() < maxrow + 8) {
    bx.resize(maxrow + 8);
    by.resize(maxrow + 8);
    br2.resize(maxrow + 8);
  }
}

namespace {

// Iterate i-particles cell by cell: f(i_padded, i_sorted, js[3], je[3]).
template <class F>
inline void for_each_i(const CellGrid& g, F&& f) {
  const int nc = g.nc, np = g.np;
  const int* ps = g.pstart.data();
  for (int cy = 0; cy < nc; ++cy) {
    for (int cx = 0; cx < nc; ++cx) {
      const int pc = (cy + 1) * np + cx + 1;
      int js[3], je[3];
      for (int d = 0; d < 3; ++d) {
        js[d] = ps[(cy + d) * np + cx];
        je[d] = ps[(cy + d) * np + cx + 3];
      }
      int ii = g.cstart[cy * nc + cx];
      for (int i = ps[pc]; i < ps[pc + 1]; ++i, ++ii) f(i, ii, js, je);
    }
  }
}

// exp(a) for a in [-708, 708]: Cody-Waite reduction by ln2, degree-13 Taylor
// polynomial on |r| <= ln2/2 evaluated with Estrin's scheme (a shorter
// dependency chain than Horner; the pair loop is latency bound), scaled by
// 2^k through the exponent bits. About 1 ulp; glibc's vector exp would need
// -ffast-math.
inline __m256d vexp4(__m256d a) {
  const __m256d L2E = _mm256_set1_pd(1.4426950408889634074);
  const __m256d SH = _mm256_set1_pd(6755399441055744.0);
  const __m256d LN2HI = _mm256_set1_pd(6.93147180369123816490e-01);
  const __m256d LN2LO = _mm256_set1_pd(1.90821492927058770002e-10);
  __m256d t = _mm256_fmadd_pd(a, L2E, SH);
  __m256d k = _mm256_sub_pd(t, SH);
  __m256d r = _mm256_fnmadd_pd(k, LN2HI, a);
  r = _mm256_fnmadd_pd(k, LN2LO, r);
  const auto C = [](double x) { return _mm256_set1_pd(x); };
  __m256d r2 = _mm256_mul_pd(r, r);
  __m256d r4 = _mm256_mul_pd(r2, r2);
  __m256d r8 = _mm256_mul_pd(r4, r4);
  __m256d q0 = _mm256_fmadd_pd(C(1.0), r, C(1.0));
  __m256d q1 = _mm256_fmadd_pd(C(1.0 / 6.0), r, C(0.5));
  __m256d q2 = _mm256_fmadd_pd(C(1.0 / 120.0), r, C(1.0 / 24.0));
  __m256d q3 = _mm256_fmadd_pd(C(1.0 / 5040.0), r, C(1.0 / 720.0));
  __m256d q4 = _mm256_fmadd_pd(C(1.0 / 362880.0), r, C(1.0 / 40320.0));
  __m256d q5 = _mm256_fmadd_pd(C(1.0 / 39916800.0), r, C(1.0 / 3628800.0));
  __m256d q6 = _mm256_fmadd_pd(C(1.0 / 6227020800.0), r, C(1.0 / 479001600.0));
  __m256d s0 = _mm256_fmadd_pd(q1, r2, q0);
  __m256d s1 = _mm256_fmadd_pd(q3, r2, q2);
  __m256d s2 = _mm256_fmadd_pd(q5, r2, q4);
  __m256d u0 = _mm256_fmadd_pd(s1, r4, s0);
  __m256d u1 = _mm256_fmadd_pd(q6, r4, s2);
  __m256d p = _mm256_fmadd_pd(u1, r8, u0);
  __m256i ti = _mm256_castpd_si256(t);
  __m256i sb = _mm256_sub_epi64(ti, _mm256_castpd_si256(SH));
  sb = _mm256_slli_epi64(_mm256_add_epi64(sb, _mm256_set1_epi64x(1023)), 52);
  return _mm256_mul_pd(p, _mm256_castsi256_pd(sb));
}

inline double hsum4(__m256d v) {
  __m128d lo = _mm256_castpd256_pd128(v), hi = _mm256_extractf128_pd(v, 1);
  lo = _mm_add_pd(lo, hi);
  return _mm_cvtsd_f64(_mm_add_sd(lo, _mm_unpackhi_pd(lo, lo)));
}

// exp(-r)/r from r2 > 0 (all lanes valid): r = sqrt(r2) (vsqrtpd), w = exp(-r) / r (vdivpd).
inline __m256d weight4_valid(__m256d r2) {
  __m256d r = _mm256_sqrt_pd(r2);
  __m256d e = vexp4(_mm256_sub_pd(_mm256_setzero_pd(), r));
  return _mm256_div_pd(e, r);
}

// w = exp(-r)/r for lanes in mask (0 elsewhere), r2 assumed valid where mask.
inline __m256d weight4(__m256d r2, __m256d m) {
  const __m256d one = _mm256_set1_pd(1.0);
  __m256d r2s = _mm256_blendv_pd(one, r2, m);
  return _mm256_and_pd(weight4_valid(r2s), m);
}

// Per 4-lane mask, the permutation that packs the chosen lanes to the front,
// and how many there are.
struct CompactLUT {
  __m256i perm[16];
  int cnt[16];
  CompactLUT() {
    for (int m = 0; m < 16; ++m) {
      int idx[8], k = 0;
      for (int l = 0; l < 4; ++l)
        if (m >> l & 1) {
          idx[2 * k] = 2 * l;
          idx[2 * k + 1] = 2 * l + 1;
          ++k;
        }
      cnt[m] = k;
      for (int l = k; l < 4; ++l) idx[2 * l] = 0, idx[2 * l + 1] = 1;
      perm[m] = _mm256_setr_epi32(idx[0], idx[1], idx[2], idx[3], idx[4], idx[5], idx[6], idx[7]);
    }
  }
};
const CompactLUT kLUT;

inline __m256d compress4(__m256d v, __m256i p) {
  return _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(v), p));
}

// The CSR list SELL-4 is packed from: (dx, dy) of each pair, sorted order.
struct NList {
  std::vector<int64_t> off;  // CSR offsets, size n+1 (sorted order)
  std::vector<double> dx, dy;
};

void build_nlist(const CellGrid& g, NList& L) {
  const double rc2 = g.rc * g.rc;
  L.off.assign(g.n + 1, 0);
  L.dx.clear();
  L.dy.clear();
  const size_t est = size_t(1.02 * g.n * (g.n - 1) * M_PI * g.rc * g.rc) + 1024;
  L.dx.reserve(est);
  L.dy.reserve(est);
  const double* px = g.px.data();
  const double* py = g.py.data();
  for_each_i(g, [&](int i, int ii, const int* js, const int* je) {
    for (int d = 0; d < 3; ++d)
      for (int jj = js[d]; jj < je[d]; ++jj) {
        double dx = px[jj] - px[i], dy = py[jj] - py[i];
        double r2 = dx * dx + dy * dy;
        if (r2 < rc2 && r2 > 0.0) {
          L.dx.push_back(dx);
          L.dy.push_back(dy);
        }
      }
    L.off[ii + 1] = int64_t(L.dx.size());
  });
}

}  // namespace

// The buffer is padded with (dx,dy,r2) = (0,0,1) so the last partial vector
// adds exact zeros. Not inlined, as in floor.cpp: the kernel is compiled, and
// measured, on its own.
__attribute__((noinline)) void eval_compact_simd(const CellGrid& g, CompactScratch& s, double c,
                                                 double* __restrict vx, double* __restrict vy) {
  const __m256d rc2 = _mm256_set1_pd(g.rc * g.rc);
  const __m256d zero = _mm256_setzero_pd();
  const __m256d one = _mm256_set1_pd(1.0);
  const __m256i iota = _mm256_setr_epi64x(0, 1, 2, 3);
  const double* px = g.px.data();
  const double* py = g.py.data();
  double* bx = s.bx.data();
  double* by = s.by.data();
  double* br2 = s.br2.data();
  for_each_i(g, [&](int i, int ii, const int* js, const int* je) {
    const __m256d xi = _mm256_set1_pd(px[i]), yi = _mm256_set1_pd(py[i]);
    int nb = 0;
    for (int d = 0; d < 3; ++d) {
      const int e = je[d];
      const __m256i ev = _mm256_set1_epi64x(e);
      for (int j = js[d]; j < e; j += 4) {
        __m256d dx = _mm256_sub_pd(_mm256_loadu_pd(px + j), xi);
        __m256d dy = _mm256_sub_pd(_mm256_loadu_pd(py + j), yi);
        __m256d r2 = _mm256_fmadd_pd(dy, dy, _mm256_mul_pd(dx, dx));
        __m256d m = _mm256_and_pd(_mm256_cmp_pd(r2, rc2, _CMP_LT_OQ),
                                  _mm256_cmp_pd(r2, zero, _CMP_GT_OQ));
        if (j + 4 > e) {
          __m256i lane = _mm256_add_epi64(_mm256_set1_epi64x(j), iota);
          m = _mm256_and_pd(m, _mm256_castsi256_pd(_mm256_cmpgt_epi64(ev, lane)));
        }
        const int mm = _mm256_movemask_pd(m);
        const __m256i p = kLUT.perm[mm];
        _mm256_storeu_pd(bx + nb, compress4(dx, p));
        _mm256_storeu_pd(by + nb, compress4(dy, p));
        _mm256_storeu_pd(br2 + nb, compress4(r2, p));
        nb += kLUT.cnt[mm];
      }
    }
    _mm256_storeu_pd(bx + nb, zero);
    _mm256_storeu_pd(by + nb, zero);
    _mm256_storeu_pd(br2 + nb, one);
    __m256d ax = zero, ay = zero;
    for (int k = 0; k < nb; k += 4) {
      __m256d w = weight4_valid(_mm256_loadu_pd(br2 + k));
      ax = _mm256_fmadd_pd(w, _mm256_loadu_pd(bx + k), ax);
      ay = _mm256_fmadd_pd(w, _mm256_loadu_pd(by + k), ay);
    }
    vx[ii] -= c * hsum4(ax);
    vy[ii] -= c * hsum4(ay);
  });
}

void build_sell4(const CellGrid& grid, Sell4& S) {
  NList L;
  build_nlist(grid, L);
  const int n = grid.n;
  const int ng = (n + 3) / 4;
  S.n = n;
  S.pairs = L.off[n];
  S.base.assign(ng + 1, 0);
  for (int g = 0; g < ng; ++g) {
    int64_t mx = 0;
    for (int l = 0; l < 4; ++l) {
      int i = 4 * g + l;
      if (i < n) mx = std::max(mx, L.off[i + 1] - L.off[i]);
    }
    S.base[g + 1] = S.base[g] + 4 * mx;
  }
  S.dx.assign(S.base[ng], 0.0);
  S.dy.assign(S.base[ng], 0.0);
  for (int g = 0; g < ng; ++g)
    for (int l = 0; l < 4; ++l) {
      int i = 4 * g + l;
      if (i >= n) continue;
      for (int64_t k = L.off[i]; k < L.off[i + 1]; ++k) {
        int64_t s = k - L.off[i];
        S.dx[S.base[g] + 4 * s + l] = L.dx[k];
        S.dy[S.base[g] + 4 * s + l] = L.dy[k];
      }
    }
}

// Streams 16 B per slot: no gathers, no horizontal sums.
__attribute__((noinline)) void eval_sell4(const Sell4& S, double c, double* __restrict vx,
                                          double* __restrict vy) {
  const __m256d zero = _mm256_setzero_pd();
  const __m256d mc = _mm256_set1_pd(-c);
  const int n = S.n, ng = (n + 3) / 4;
  const double* dxp = S.dx.data();
  const double* dyp = S.dy.data();
  for (int g = 0; g < ng; ++g) {
    __m256d ax = zero, ay = zero;
    for (int64_t k = S.base[g]; k < S.base[g + 1]; k += 4) {
      __m256d dx = _mm256_loadu_pd(dxp + k), dy = _mm256_loadu_pd(dyp + k);
      __m256d r2 = _mm256_fmadd_pd(dy, dy, _mm256_mul_pd(dx, dx));
      __m256d m = _mm256_cmp_pd(r2, zero, _CMP_GT_OQ);
      __m256d w = weight4(r2, m);
      ax = _mm256_fmadd_pd(w, dx, ax);
      ay = _mm256_fmadd_pd(w, dy, ay);
    }
    if (4 * g + 4 <= n) {
      _mm256_storeu_pd(vx + 4 * g, _mm256_fmadd_pd(mc, ax, _mm256_loadu_pd(vx + 4 * g)));
      _mm256_storeu_pd(vy + 4 * g, _mm256_fmadd_pd(mc, ay, _mm256_loadu_pd(vy + 4 * g)));
    } else {
      alignas(32) double tx[4], ty[4];
      _mm256_store_pd(tx, ax);
      _mm256_store_pd(ty, ay);
      for (int l = 0; 4 * g + l < n; ++l) {
        vx[4 * g + l] -= c * tx[l];
        vy[4 * g + l] -= c * ty[l];
      }
    }
  }
}

bool VelocityUpdate::applicable(double rc) { return int(std::floor(1.0 / rc)) >= 3; }

// floor.cpp's estimate: pairs of uniform points, n^2 pi rc^2.
bool VelocityUpdate::sell4_fits(int n, double rc) {
  return double(n) * n * M_PI * rc * rc <= sell4_max_pairs;
}

VelocityUpdate::VelocityUpdate(const double* x, const double* y, int n, double rc, double c,
                               bool with_sell4)
    : c_(c), compact_vx_(n, 0.0), compact_vy_(n, 0.0) {
  grid_.build(n, x, y, rc);
  scratch_.fit(grid_);
  if (with_sell4) {
    build_sell4(grid_, sell4_);
    sell4_vx_.assign(n, 0.0);
    sell4_vy_.assign(n, 0.0);
  }
}

void VelocityUpdate::update_compact() {
  eval_compact_simd(grid_, scratch_, c_, compact_vx_.data(), compact_vy_.data());
}

void VelocityUpdate::update_sell4() { eval_sell4(sell4_, c_, sell4_vx_.data(), sell4_vy_.data()); }

std::vector<std::array<double, 2>> VelocityUpdate::velocities_compact() const {
  return in_input_order(compact_vx_, compact_vy_);
}

std::vector<std::array<double, 2>> VelocityUpdate::velocities_sell4() const {
  return in_input_order(sell4_vx_, sell4_vy_);
}

std::vector<std::array<double, 2>> VelocityUpdate::in_input_order(
    const std::vector<double>& vx, const std::vector<double>& vy) const {
  std::vector<std::array<double, 2>> v(vx.size());
  for (std::size_t k = 0; k < v.size(); ++k) v[grid_.perm[k]] = {vx[k], vy[k]};
  return v;
}

}  // namespace floor_ref
