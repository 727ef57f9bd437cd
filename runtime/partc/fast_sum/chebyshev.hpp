// partc/fast_sum/chebyshev.hpp: Chebyshev nodes of the first kind and the
// tensor-product Lagrange interpolation through them, the basis of the
// black-box fast multipole method (Fong & Darve 2009): a box's expansion is
// the values of a sum at p^D nodes, and the sum anywhere in the box is their
// interpolant.
//
// Node multi-indices: node m of a box in D dimensions has the 1D node index
// (m / p^d) % p along dimension d (dimension 0 varies fastest).
//
// Surprises:
// - the nodes decrease (node 0 is the largest); node p-1-k is minus node k,
//   which is what lets mirrored box pairs share one M2L operator.
// - weights() is exact at a node (1 there, 0 elsewhere), not 0/0.
#pragma once

#include <cmath>
#include <vector>

namespace partc::fast_sum {

class ChebyshevBasis {
 public:
  explicit ChebyshevBasis(int p)
      : p_(p), nodes_(static_cast<std::size_t>(p)), bary_(nodes_.size()) {
    const double pi = std::acos(-1.0);
    for (int k = 0; k < p; ++k) {
      const double angle = (2 * k + 1) * pi / (2 * p);
      nodes_[static_cast<std::size_t>(k)] = std::cos(angle);
      // Barycentric weights of first-kind nodes (Berrut & Trefethen 2004, eq. 5.3).
      bary_[static_cast<std::size_t>(k)] = (k % 2 == 0 ? 1.0 : -1.0) * std::sin(angle);
    }
  }

  int order() const { return p_; }
  double node(int k) const { return nodes_[static_cast<std::size_t>(k)]; }

  // w[k] = l_k(t), the Lagrange polynomial of node k at t (t in [-1, 1]).
  void weights(double t, double* w) const {
    double total = 0;
    for (int k = 0; k < p_; ++k) {
      const double gap = t - node(k);
      if (gap == 0) {
        for (int j = 0; j < p_; ++j) w[j] = j == k ? 1.0 : 0.0;
        return;
      }
      w[k] = bary_[static_cast<std::size_t>(k)] / gap;
      total += w[k];
    }
    for (int k = 0; k < p_; ++k) w[k] /= total;
  }

  // The p x p matrix (row m, column n) l_m(child node n), with the child the
  // lower (side 0) or upper (side 1) half of [-1, 1]: the 1D factor of M2M
  // (parent += transfer * child) and of L2L (child += transfer^T * parent).
  std::vector<double> child_transfer(int side) const {
    std::vector<double> t(static_cast<std::size_t>(p_ * p_));
    std::vector<double> w(static_cast<std::size_t>(p_));
    for (int n = 0; n < p_; ++n) {
      weights((node(n) + (side == 0 ? -1.0 : 1.0)) / 2, w.data());
      for (int m = 0; m < p_; ++m)
        t[static_cast<std::size_t>(m * p_ + n)] = w[static_cast<std::size_t>(m)];
    }
    return t;
  }

 private:
  int p_;
  std::vector<double> nodes_, bary_;
};

// The p^D tensor-product weights s[m] = prod_d l_{m_d}(t[d]) of a point with
// box coordinates t (each in [-1, 1]); scratch holds p doubles.
template <int D>
void tensor_weights(const ChebyshevBasis& basis, const double* t, double* s, double* scratch) {
  const int p = basis.order();
  basis.weights(t[0], s);
  int size = p;
  for (int d = 1; d < D; ++d) {
    basis.weights(t[d], scratch);
    // Outer product in place, from the back so that s[j] is read before written.
    for (int k = p - 1; k >= 0; --k)
      for (int j = size - 1; j >= 0; --j) s[k * size + j] = s[j] * scratch[k];
    size *= p;
  }
}

// out += (M_{D-1} x ... x M_0) in (or the transposes, for L2L), one dimension
// at a time: D p^(D+1) multiplications rather than p^(2D). Each M_d is p x p,
// row-major; a and b are scratch of p^D doubles each.
template <int D>
void tensor_apply_add(int p, const double* const* mats, bool transpose, const double* in,
                      double* out, double* a, double* b) {
  int total = 1;
  for (int d = 0; d < D; ++d) total *= p;
  const double* src = in;
  int stride = 1;
  for (int d = 0; d < D; ++d) {
    const double* m = mats[d];
    double* dst = d % 2 == 0 ? a : b;
    const int block = stride * p;
    for (int outer = 0; outer < total; outer += block)
      for (int row = 0; row < p; ++row)
        for (int inner = 0; inner < stride; ++inner) {
          double sum = 0;
          for (int k = 0; k < p; ++k)
            sum += (transpose ? m[k * p + row] : m[row * p + k]) * src[outer + k * stride + inner];
          dst[outer + row * stride + inner] = sum;
        }
    src = dst;
    stride = block;
  }
  for (int m = 0; m < total; ++m) out[m] += src[m];
}

}  // namespace partc::fast_sum
