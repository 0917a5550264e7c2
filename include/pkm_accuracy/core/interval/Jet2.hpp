// Second-order forward-mode derivatives: a value, its gradient and its Hessian (upper triangle) with respect to N
// variables, over any scalar T (Interval for enclosures over a box, AffineForm / SegmentAffineForm for affine forms of
// the derivatives over a box). The same derivatives as Dual<Dual<T, N>, N> with fewer products: a product costs
// 1 + 2N + 4 N(N+1)/2 products of T against (1 + 2N)(1 + N) for the nested duals, and nothing is computed twice.
//
// Every rule is the exact chain rule evaluated in T's arithmetic (f(x): value f(v), gradient f'(v) g, Hessian
// f'(v) H + f''(v) g g^T), so over intervals every component encloses the true derivative over the box.
//
// Each jet knows its order (order()): 0 for a constant (zero gradient and Hessian), 1 for a jet whose Hessian is zero
// (an independent variable, or a sum of them), 2 otherwise. The rules skip the terms that are products with those
// exact zeros (a model's geometry constants and its pose variables enter most products), which changes no enclosure:
// an omitted term is exactly zero.
#pragma once

#include <array>
#include <type_traits>

namespace pkm_accuracy {
namespace interval {

template <typename T, int N>
class Jet2 {
 public:
  using Scalar = T;
  static constexpr int kSize = N;
  static constexpr int kPairs = N * (N + 1) / 2;
  /// Index of the pair (a, b), a <= b.
  static constexpr int pair(int a, int b) { return a * N - a * (a - 1) / 2 + (b - a); }

  Jet2() : v_(0.0) { clear(); }
  Jet2(const T& value) : v_(value) { clear(); }  // NOLINT(runtime/explicit): constants mix in formulas
  template <typename U, typename = std::enable_if_t<std::is_arithmetic<U>::value && !std::is_same<U, T>::value>>
  Jet2(U value) : v_(static_cast<double>(value)) {  // NOLINT(runtime/explicit)
    clear();
  }
  /// The independent variable number i (0 <= i < N) with the given value.
  static Jet2 variable(const T& value, int i) {
    Jet2 r(value);
    r.g_[i] = T(1.0);
    r.order_ = 1;
    return r;
  }

  const T& value() const { return v_; }
  /// 0: a constant; 1: the Hessian is zero; 2: general.
  int order() const { return order_; }
  const T& d(int i) const { return g_[i]; }
  /// d^2 / dx_a dx_b (either order).
  const T& d2(int a, int b) const { return a <= b ? h_[pair(a, b)] : h_[pair(b, a)]; }

  /// The same value with the gradient g and the Hessian entries hessian(a, b) (a <= b) given (for rules of two
  /// arguments, such as atan2).
  template <typename F>
  Jet2 withDerivatives(const std::array<T, N>& g, F hessian) const {
    Jet2 r(v_);
    r.g_ = g;
    for (int a = 0; a < N; ++a)
      for (int b = a; b < N; ++b) r.h_[pair(a, b)] = hessian(a, b);
    r.order_ = 2;
    return r;
  }
  /// f(x) from f(v), f'(v), f''(v).
  static Jet2 chain(const Jet2& x, const T& f0, const T& f1, const T& f2) {
    Jet2 r(f0);
    if (x.order_ == 0) return r;
    r.order_ = 2;
    for (int i = 0; i < N; ++i) r.g_[i] = f1 * x.g_[i];
    for (int a = 0; a < N; ++a)
      for (int b = a; b < N; ++b) {
        const int p = pair(a, b);
        r.h_[p] = x.order_ == 2 ? f1 * x.h_[p] + f2 * (x.g_[a] * x.g_[b]) : f2 * (x.g_[a] * x.g_[b]);
      }
    return r;
  }

  friend Jet2 operator+(const Jet2& a, const Jet2& b) {
    Jet2 r(a.v_ + b.v_);
    r.order_ = a.order_ > b.order_ ? a.order_ : b.order_;
    if (r.order_ >= 1)
      for (int i = 0; i < N; ++i) r.g_[i] = a.g_[i] + b.g_[i];
    if (r.order_ == 2)
      for (int p = 0; p < kPairs; ++p) r.h_[p] = a.h_[p] + b.h_[p];
    return r;
  }
  friend Jet2 operator-(const Jet2& a, const Jet2& b) {
    Jet2 r(a.v_ - b.v_);
    r.order_ = a.order_ > b.order_ ? a.order_ : b.order_;
    if (r.order_ >= 1)
      for (int i = 0; i < N; ++i) r.g_[i] = a.g_[i] - b.g_[i];
    if (r.order_ == 2)
      for (int p = 0; p < kPairs; ++p) r.h_[p] = a.h_[p] - b.h_[p];
    return r;
  }
  friend Jet2 operator-(const Jet2& a) {
    Jet2 r(-a.v_);
    r.order_ = a.order_;
    if (r.order_ >= 1)
      for (int i = 0; i < N; ++i) r.g_[i] = -a.g_[i];
    if (r.order_ == 2)
      for (int p = 0; p < kPairs; ++p) r.h_[p] = -a.h_[p];
    return r;
  }
  friend Jet2 operator+(const Jet2& a) { return a; }
  friend Jet2 operator*(const Jet2& a, const Jet2& b) {
    if (a.order_ == 0) return b * a.v_;
    if (b.order_ == 0) return a * b.v_;
    Jet2 r(a.v_ * b.v_);
    r.order_ = 2;
    for (int i = 0; i < N; ++i) r.g_[i] = a.g_[i] * b.v_ + a.v_ * b.g_[i];
    for (int x = 0; x < N; ++x)
      for (int y = x; y < N; ++y) {
        const int p = pair(x, y);
        const T cross = a.g_[x] * b.g_[y] + a.g_[y] * b.g_[x];
        if (a.order_ == 2 && b.order_ == 2) {
          r.h_[p] = a.h_[p] * b.v_ + a.v_ * b.h_[p] + cross;
        } else if (a.order_ == 2) {
          r.h_[p] = a.h_[p] * b.v_ + cross;
        } else if (b.order_ == 2) {
          r.h_[p] = a.v_ * b.h_[p] + cross;
        } else {
          r.h_[p] = cross;
        }
      }
    return r;
  }
  /// q = a / b from a = q b: q' = (a' - q b') / b, q''_xy = (a''_xy - q'_x b'_y - q'_y b'_x - q b''_xy) / b.
  friend Jet2 operator/(const Jet2& a, const Jet2& b) {
    if (b.order_ == 0) return a * (T(1.0) / b.v_);
    const T inv = T(1.0) / b.v_;
    Jet2 q(a.v_ * inv);
    q.order_ = 2;
    for (int i = 0; i < N; ++i) q.g_[i] = (a.order_ >= 1 ? a.g_[i] - q.v_ * b.g_[i] : -(q.v_ * b.g_[i])) * inv;
    for (int x = 0; x < N; ++x)
      for (int y = x; y < N; ++y) {
        const int p = pair(x, y);
        const T cross = q.g_[x] * b.g_[y] + q.g_[y] * b.g_[x];
        T num = a.order_ == 2 ? a.h_[p] - cross : -cross;
        if (b.order_ == 2) num = num - q.v_ * b.h_[p];
        q.h_[p] = num * inv;
      }
    return q;
  }
  // Mixed with the base scalar and with constants.
  friend Jet2 operator*(const Jet2& a, const T& s) {
    Jet2 r(a.v_ * s);
    r.order_ = a.order_;
    if (r.order_ >= 1)
      for (int i = 0; i < N; ++i) r.g_[i] = a.g_[i] * s;
    if (r.order_ == 2)
      for (int p = 0; p < kPairs; ++p) r.h_[p] = a.h_[p] * s;
    return r;
  }
  friend Jet2 operator*(const T& s, const Jet2& a) { return a * s; }
  friend Jet2 operator+(const Jet2& a, const T& s) {
    Jet2 r(a);
    r.v_ = a.v_ + s;
    return r;
  }
  friend Jet2 operator+(const T& s, const Jet2& a) { return a + s; }
  friend Jet2 operator-(const Jet2& a, const T& s) {
    Jet2 r(a);
    r.v_ = a.v_ - s;
    return r;
  }
  friend Jet2 operator-(const T& s, const Jet2& a) { return -(a - s); }
  friend Jet2 operator/(const Jet2& a, const T& s) { return a * (T(1.0) / s); }
  friend Jet2 operator/(const T& s, const Jet2& a) { return Jet2(s) / a; }
  template <typename U, typename = std::enable_if_t<std::is_arithmetic<U>::value && !std::is_same<U, T>::value>>
  friend Jet2 operator+(const Jet2& a, U s) {
    return a + T(static_cast<double>(s));
  }
  template <typename U, typename = std::enable_if_t<std::is_arithmetic<U>::value && !std::is_same<U, T>::value>>
  friend Jet2 operator+(U s, const Jet2& a) {
    return a + T(static_cast<double>(s));
  }
  template <typename U, typename = std::enable_if_t<std::is_arithmetic<U>::value && !std::is_same<U, T>::value>>
  friend Jet2 operator-(const Jet2& a, U s) {
    return a - T(static_cast<double>(s));
  }
  template <typename U, typename = std::enable_if_t<std::is_arithmetic<U>::value && !std::is_same<U, T>::value>>
  friend Jet2 operator-(U s, const Jet2& a) {
    return T(static_cast<double>(s)) - a;
  }
  template <typename U, typename = std::enable_if_t<std::is_arithmetic<U>::value && !std::is_same<U, T>::value>>
  friend Jet2 operator*(const Jet2& a, U s) {
    return a * T(static_cast<double>(s));
  }
  template <typename U, typename = std::enable_if_t<std::is_arithmetic<U>::value && !std::is_same<U, T>::value>>
  friend Jet2 operator*(U s, const Jet2& a) {
    return a * T(static_cast<double>(s));
  }
  template <typename U, typename = std::enable_if_t<std::is_arithmetic<U>::value && !std::is_same<U, T>::value>>
  friend Jet2 operator/(const Jet2& a, U s) {
    return a / T(static_cast<double>(s));
  }
  template <typename U, typename = std::enable_if_t<std::is_arithmetic<U>::value && !std::is_same<U, T>::value>>
  friend Jet2 operator/(U s, const Jet2& a) {
    return T(static_cast<double>(s)) / a;
  }
  Jet2& operator+=(const Jet2& o) { return *this = *this + o; }
  Jet2& operator-=(const Jet2& o) { return *this = *this - o; }
  Jet2& operator*=(const Jet2& o) { return *this = *this * o; }
  Jet2& operator/=(const Jet2& o) { return *this = *this / o; }

 private:
  void clear() {
    g_.fill(T(0.0));
    h_.fill(T(0.0));
  }

  T v_;
  std::array<T, N> g_;
  std::array<T, kPairs> h_;
  int order_ = 0;
};

}  // namespace interval
}  // namespace pkm_accuracy
