// Forward-mode derivatives: a value and its gradient with respect to N variables, over any scalar T
// (T = double for point derivatives, T = Interval for enclosures of derivatives over a box).
//
// Over intervals, Dual<Interval, N> evaluated on a box gives an enclosure of the value and of every partial
// derivative over the whole box (each elementary rule is the exact chain rule evaluated in interval arithmetic).
#pragma once

#include <array>
#include <cmath>
#include <type_traits>

#include "pkm_accuracy/core/interval/Functions.hpp"
#include "pkm_accuracy/core/interval/Interval.hpp"

namespace pkm_accuracy {
namespace interval {

template <typename T, int N>
class Dual {
 public:
  using Scalar = T;
  static constexpr int kSize = N;

  Dual() : v_(0.0) { d_.fill(T(0.0)); }
  Dual(const T& value) : v_(value) { d_.fill(T(0.0)); }  // NOLINT(runtime/explicit): constants mix in formulas
  template <typename U, typename = std::enable_if_t<std::is_arithmetic<U>::value && !std::is_same<U, T>::value>>
  Dual(U value) : v_(static_cast<double>(value)) {  // NOLINT(runtime/explicit)
    d_.fill(T(0.0));
  }
  /// The independent variable number i (0 <= i < N) with the given value.
  static Dual variable(const T& value, int i) {
    Dual r(value);
    r.d_[i] = T(1.0);
    return r;
  }

  const T& value() const { return v_; }
  const T& d(int i) const { return d_[i]; }
  T& d(int i) { return d_[i]; }
  const std::array<T, N>& gradient() const { return d_; }

  friend Dual operator+(const Dual& a, const Dual& b) {
    Dual r(a.v_ + b.v_);
    for (int i = 0; i < N; ++i) r.d_[i] = a.d_[i] + b.d_[i];
    return r;
  }
  friend Dual operator-(const Dual& a, const Dual& b) {
    Dual r(a.v_ - b.v_);
    for (int i = 0; i < N; ++i) r.d_[i] = a.d_[i] - b.d_[i];
    return r;
  }
  friend Dual operator-(const Dual& a) {
    Dual r(-a.v_);
    for (int i = 0; i < N; ++i) r.d_[i] = -a.d_[i];
    return r;
  }
  friend Dual operator+(const Dual& a) { return a; }
  friend Dual operator*(const Dual& a, const Dual& b) {
    Dual r(a.v_ * b.v_);
    for (int i = 0; i < N; ++i) r.d_[i] = a.d_[i] * b.v_ + a.v_ * b.d_[i];
    return r;
  }
  friend Dual operator/(const Dual& a, const Dual& b) {
    const T q = a.v_ / b.v_;
    Dual r(q);
    for (int i = 0; i < N; ++i) r.d_[i] = (a.d_[i] - q * b.d_[i]) / b.v_;
    return r;
  }
  // Mixed with the base scalar (cheaper than promoting it to a Dual).
  friend Dual operator*(const Dual& a, const T& s) {
    Dual r(a.v_ * s);
    for (int i = 0; i < N; ++i) r.d_[i] = a.d_[i] * s;
    return r;
  }
  friend Dual operator*(const T& s, const Dual& a) { return a * s; }
  friend Dual operator+(const Dual& a, const T& s) {
    Dual r(a);
    r.v_ = a.v_ + s;
    return r;
  }
  friend Dual operator+(const T& s, const Dual& a) { return a + s; }
  friend Dual operator-(const Dual& a, const T& s) {
    Dual r(a);
    r.v_ = a.v_ - s;
    return r;
  }
  friend Dual operator-(const T& s, const Dual& a) { return -(a - s); }
  friend Dual operator/(const Dual& a, const T& s) {
    Dual r(a.v_ / s);
    for (int i = 0; i < N; ++i) r.d_[i] = a.d_[i] / s;
    return r;
  }
  friend Dual operator/(const T& s, const Dual& a) { return Dual(s) / a; }
  // Mixed with built-in arithmetic constants (2.0 * x, x + 1, 1.0 / x). Without these, Dual<Interval, N> * double
  // would be ambiguous between the T and the Dual overloads (both need one user-defined conversion).
  template <typename U, typename = std::enable_if_t<std::is_arithmetic<U>::value && !std::is_same<U, T>::value>>
  friend Dual operator+(const Dual& a, U s) {
    return a + T(static_cast<double>(s));
  }
  template <typename U, typename = std::enable_if_t<std::is_arithmetic<U>::value && !std::is_same<U, T>::value>>
  friend Dual operator+(U s, const Dual& a) {
    return a + T(static_cast<double>(s));
  }
  template <typename U, typename = std::enable_if_t<std::is_arithmetic<U>::value && !std::is_same<U, T>::value>>
  friend Dual operator-(const Dual& a, U s) {
    return a - T(static_cast<double>(s));
  }
  template <typename U, typename = std::enable_if_t<std::is_arithmetic<U>::value && !std::is_same<U, T>::value>>
  friend Dual operator-(U s, const Dual& a) {
    return T(static_cast<double>(s)) - a;
  }
  template <typename U, typename = std::enable_if_t<std::is_arithmetic<U>::value && !std::is_same<U, T>::value>>
  friend Dual operator*(const Dual& a, U s) {
    return a * T(static_cast<double>(s));
  }
  template <typename U, typename = std::enable_if_t<std::is_arithmetic<U>::value && !std::is_same<U, T>::value>>
  friend Dual operator*(U s, const Dual& a) {
    return a * T(static_cast<double>(s));
  }
  template <typename U, typename = std::enable_if_t<std::is_arithmetic<U>::value && !std::is_same<U, T>::value>>
  friend Dual operator/(const Dual& a, U s) {
    return a / T(static_cast<double>(s));
  }
  template <typename U, typename = std::enable_if_t<std::is_arithmetic<U>::value && !std::is_same<U, T>::value>>
  friend Dual operator/(U s, const Dual& a) {
    return T(static_cast<double>(s)) / a;
  }
  Dual& operator+=(const Dual& o) { return *this = *this + o; }
  Dual& operator-=(const Dual& o) { return *this = *this - o; }
  Dual& operator*=(const Dual& o) { return *this = *this * o; }
  Dual& operator/=(const Dual& o) { return *this = *this / o; }

  friend Dual sqr(const Dual& a) {
    Dual r(sqrScalar(a.v_));
    const T twoV = T(2.0) * a.v_;
    for (int i = 0; i < N; ++i) r.d_[i] = twoV * a.d_[i];
    return r;
  }
  friend Dual sqrt(const Dual& a) {
    using std::sqrt;
    const T s = sqrt(a.v_);
    Dual r(s);
    const T twoS = T(2.0) * s;
    for (int i = 0; i < N; ++i) r.d_[i] = a.d_[i] / twoS;
    return r;
  }
  friend Dual sin(const Dual& a) {
    using std::cos;
    using std::sin;
    Dual r(sin(a.v_));
    const T c = cos(a.v_);
    for (int i = 0; i < N; ++i) r.d_[i] = c * a.d_[i];
    return r;
  }
  friend Dual cos(const Dual& a) {
    using std::cos;
    using std::sin;
    Dual r(cos(a.v_));
    const T ms = -sin(a.v_);
    for (int i = 0; i < N; ++i) r.d_[i] = ms * a.d_[i];
    return r;
  }

 private:
  static double sqrScalar(double x) { return x * x; }
  static Interval sqrScalar(const Interval& x) { return interval::sqr(x); }

  T v_;
  std::array<T, N> d_;
};

/// Generic square usable on double, Interval and Dual in templated model code.
inline double sqr(double x) { return x * x; }

}  // namespace interval
}  // namespace pkm_accuracy
