// partc/vec.hpp: Vec<D>, a fixed-size vector of D doubles (positions, velocities,
// displacements) with the usual arithmetic.
//
// Surprises:
// - Vec is an aggregate so that it is trivially copyable and sits in SoA arrays
//   without padding; write Vec<2>{{1.0, 2.0}} (double braces). `Vec<D>{}` is all zero.
// - a / s divides every component (it does not multiply by 1/s), so results match
//   the scalar expressions a model author would write by hand, bit for bit.
// - == compares components with double ==, so a Vec holding a NaN never equals itself.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

namespace partc {

template <int D>
struct Vec {
  static_assert(D >= 1, "Vec needs at least one component");

  std::array<double, D> c;

  static Vec zero() { return filled(0.0); }
  static Vec filled(double value) {
    Vec v;
    v.c.fill(value);
    return v;
  }

  double& operator[](int k) { return c[static_cast<std::size_t>(k)]; }
  double operator[](int k) const { return c[static_cast<std::size_t>(k)]; }

  Vec& operator+=(const Vec& o) {
    for (int k = 0; k < D; ++k) (*this)[k] += o[k];
    return *this;
  }
  Vec& operator-=(const Vec& o) {
    for (int k = 0; k < D; ++k) (*this)[k] -= o[k];
    return *this;
  }
  Vec& operator*=(double s) {
    for (int k = 0; k < D; ++k) (*this)[k] *= s;
    return *this;
  }
  Vec& operator/=(double s) {
    for (int k = 0; k < D; ++k) (*this)[k] /= s;
    return *this;
  }
};

template <int D>
Vec<D> operator+(Vec<D> a, const Vec<D>& b) { return a += b; }
template <int D>
Vec<D> operator-(Vec<D> a, const Vec<D>& b) { return a -= b; }
template <int D>
Vec<D> operator-(Vec<D> a) { return a *= -1.0; }
template <int D>
Vec<D> operator*(Vec<D> a, double s) { return a *= s; }
template <int D>
Vec<D> operator*(double s, Vec<D> a) { return a *= s; }
template <int D>
Vec<D> operator/(Vec<D> a, double s) { return a /= s; }
template <int D>
bool operator==(const Vec<D>& a, const Vec<D>& b) { return a.c == b.c; }
template <int D>
bool operator!=(const Vec<D>& a, const Vec<D>& b) { return !(a == b); }

template <int D>
double dot(const Vec<D>& a, const Vec<D>& b) {
  double s = a[0] * b[0];  // not 0.0 + ...: an add the compiler may not drop (-0.0)
  for (int k = 1; k < D; ++k) s += a[k] * b[k];
  return s;
}
template <int D>
double squared_norm(const Vec<D>& a) { return dot(a, a); }
template <int D>
double norm(const Vec<D>& a) { return std::sqrt(squared_norm(a)); }

// The cross product in 3D; in 2D the z-component of the 3D cross product of
// (a, 0) and (b, 0), a scalar (a torque, a signed area).
inline Vec<3> cross(const Vec<3>& a, const Vec<3>& b) {
  return Vec<3>{{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}
inline double cross(const Vec<2>& a, const Vec<2>& b) { return a[0] * b[1] - a[1] * b[0]; }

// lo <= a <= hi componentwise (false if any of them is NaN).
template <int D>
bool inside(const Vec<D>& a, const Vec<D>& lo, const Vec<D>& hi) {
  for (int k = 0; k < D; ++k)
    if (!(a[k] >= lo[k] && a[k] <= hi[k])) return false;
  return true;
}

template <int D>
bool is_finite(const Vec<D>& a) {
  for (int k = 0; k < D; ++k)
    if (!std::isfinite(a[k])) return false;
  return true;
}

}  // namespace partc
