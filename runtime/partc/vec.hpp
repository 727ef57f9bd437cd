// partc/vec.hpp: Vec<D, T>, a fixed-size vector of D numbers of type T (double
// unless said: positions, velocities, displacements) with the usual arithmetic.
//
// Storage precision: a model whose schedule says `precision = float` stores
// its real and vec variables as float and Vec<D, float>, and computes with
// double and Vec<D> all the same. Generated code loads such a value with
// widen(), which is exact, and a store rounds once: the assignments and the
// compound ones (float += double) compute in double, then round.
//
// Surprises:
// - Vec is an aggregate so that it is trivially copyable and sits in SoA arrays
//   without padding; write Vec<2>{{1.0, 2.0}} (double braces). `Vec<D>{}` is all zero.
// - Vecs of different T convert implicitly both ways, as double and float do:
//   widening is exact, narrowing rounds each component to nearest. Arithmetic
//   takes operands of one T only, so float and double vecs never mix silently
//   in an expression: a Vec<D, float> + Vec<D> does not compile; widen first.
// - a / s divides every component (it does not multiply by 1/s), so results match
//   the scalar expressions a model author would write by hand, bit for bit.
// - == compares components with ==, so a Vec holding a NaN never equals itself.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

namespace partc {

template <int D, class T = double>
struct Vec {
  static_assert(D >= 1, "Vec needs at least one component");
  static constexpr int dim = D;
  using value_type = T;

  std::array<T, D> c;

  static Vec zero() { return filled(T(0)); }
  static Vec filled(T value) {
    Vec v;
    v.c.fill(value);
    return v;
  }

  T& operator[](int k) { return c[static_cast<std::size_t>(k)]; }
  T operator[](int k) const { return c[static_cast<std::size_t>(k)]; }

  // Componentwise conversion to another precision (see the top of the file).
  template <class U>
  operator Vec<D, U>() const {
    Vec<D, U> v;
    for (int k = 0; k < D; ++k) v[k] = static_cast<U>((*this)[k]);
    return v;
  }

  // o may be wider than T: a float component += a double computes in double
  // and rounds once, as a scalar float += double does.
  template <class U>
  Vec& operator+=(const Vec<D, U>& o) {
    for (int k = 0; k < D; ++k) (*this)[k] = static_cast<T>((*this)[k] + o[k]);
    return *this;
  }
  template <class U>
  Vec& operator-=(const Vec<D, U>& o) {
    for (int k = 0; k < D; ++k) (*this)[k] = static_cast<T>((*this)[k] - o[k]);
    return *this;
  }
  Vec& operator*=(double s) {
    for (int k = 0; k < D; ++k) (*this)[k] = static_cast<T>((*this)[k] * s);
    return *this;
  }
  Vec& operator/=(double s) {
    for (int k = 0; k < D; ++k) (*this)[k] = static_cast<T>((*this)[k] / s);
    return *this;
  }
};

template <int D, class T>
Vec<D, T> operator+(Vec<D, T> a, const Vec<D, T>& b) { return a += b; }
template <int D, class T>
Vec<D, T> operator-(Vec<D, T> a, const Vec<D, T>& b) { return a -= b; }
template <int D, class T>
Vec<D, T> operator-(Vec<D, T> a) {
  for (int k = 0; k < D; ++k) a[k] = -a[k];
  return a;
}
template <int D>
Vec<D> operator*(Vec<D> a, double s) { return a *= s; }
template <int D>
Vec<D> operator*(double s, Vec<D> a) { return a *= s; }
template <int D>
Vec<D> operator/(Vec<D> a, double s) { return a /= s; }
template <int D, class T>
bool operator==(const Vec<D, T>& a, const Vec<D, T>& b) { return a.c == b.c; }
template <int D, class T>
bool operator!=(const Vec<D, T>& a, const Vec<D, T>& b) { return !(a == b); }

// A stored value as kernels compute with it: float to double, Vec<D, float>
// to Vec<D>, exactly (doubles as they are). Generated code calls it on every
// load of a float variable; the runtime on positions of either precision.
inline double widen(double x) { return x; }
template <int D, class T>
Vec<D> widen(const Vec<D, T>& v) { return v; }

template <int D, class T>
T dot(const Vec<D, T>& a, const Vec<D, T>& b) {
  T s = a[0] * b[0];  // not 0.0 + ...: an add the compiler may not drop (-0.0)
  for (int k = 1; k < D; ++k) s += a[k] * b[k];
  return s;
}
template <int D, class T>
T squared_norm(const Vec<D, T>& a) { return dot(a, a); }
// sqrt(dot(a, a)), except where the squares underflow (|a| below about
// 1.5e-154, where particles 1e-162 apart would look coincident) or overflow
// (above 1.3e154): only there is each component scaled by the largest first.
template <int D, class T>
T norm(const Vec<D, T>& a) {
  const T s = squared_norm(a);
  if (s >= std::numeric_limits<T>::min() && s <= std::numeric_limits<T>::max()) return std::sqrt(s);
  if (std::isnan(s)) return s;
  T largest = 0;
  for (int k = 0; k < D; ++k) largest = std::max(largest, std::abs(a[k]));
  if (largest == 0 || std::isinf(largest)) return largest;
  T scaled = 0;
  for (int k = 0; k < D; ++k) scaled += (a[k] / largest) * (a[k] / largest);
  return largest * std::sqrt(scaled);
}

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

template <int D, class T>
bool is_finite(const Vec<D, T>& a) {
  for (int k = 0; k < D; ++k)
    if (!std::isfinite(a[k])) return false;
  return true;
}

}  // namespace partc
