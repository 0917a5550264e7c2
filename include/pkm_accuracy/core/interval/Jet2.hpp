// Second-order forward-mode derivatives: a value, its gradient and its Hessian (upper triangle) with respect to N
// variables, over any scalar T (Interval for enclosures over a box, AffineForm / SegmentAffineForm for affine forms of
// the derivatives over a box). The same derivatives as Dual<Dual<T, N>, N> with fewer products: a product costs
// 1 + 2N + 4 N(N+1)/2 products of T against (1 + 2N)(1 + N) for the nested duals, and nothing is computed twice.
//
// Every rule is the exact chain rule evaluated in T's arithmetic (f(x): value f(v), gradient f'(v) g, Hessian
// f'(v) H + f''(v) g g^T), so over intervals every component encloses the true derivative over the box.
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
    return r;
  }

  const T& value() const { return v_; }
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
    return r;
  }
  /// f(x) from f(v), f'(v), f''(v).
  static Jet2 chain(const Jet2& x, const T& f0, const T& f1, const T& f2) {
    Jet2 r(f0);
    for (int i = 0; i < N; ++i) r.g_[i] = f1 * x.g_[i];
    for (int a = 0; a < N; ++a)
      for (int b = a; b < N; ++b) r.h_[pair(a, b)] = f1 * x.h_[pair(a, b)] + f2 * (x.g_[a] * x.g_[b]);
    return r;
  }

  friend Jet2 operator+(const Jet2& a, const Jet2& b) {
    Jet2 r(a.v_ + b.v_);
    for (int i = 0; i < N; ++i) r.g_[i] = a.g_[i] + b.g_[i];
    for (int p = 0; p < kPairs; ++p) r.h_[p] = a.h_[p] + b.h_[p];
    return r;
  }
  friend Jet2 operator-(const Jet2& a, const Jet2& b) {
    Jet2 r(a.v_ - b.v_);
    for (int i = 0; i < N; ++i) r.g_[i] = a.g_[i] - b.g_[i];
    for (int p = 0; p < kPairs; ++p) r.h_[p] = a.h_[p] - b.h_[p];
    return r;
  }
  friend Jet2 operator-(const Jet2& a) {
    Jet2 r(-a.v_);
    for (int i = 0; i < N; ++i) r.g_[i] = -a.g_[i];
    for (int p = 0; p < kPairs; ++p) r.h_[p] = -a.h_[p];
    return r;
  }
  friend Jet2 operator+(const Jet2& a) { return a; }
  friend Jet2 operator*(const Jet2& a, const Jet2& b) {
    Jet2 r(a.v_ * b.v_);
    for (int i = 0; i < N; ++i) r.g_[i] = a.g_[i] * b.v_ + a.v_ * b.g_[i];
    for (int x = 0; x < N; ++x)
      for (int y = x; y < N; ++y) {
        const int p = pair(x, y);
        r.h_[p] = a.h_[p] * b.v_ + a.v_ * b.h_[p] + (a.g_[x] * b.g_[y] + a.g_[y] * b.g_[x]);
      }
    return r;
  }
  /// q = a / b from a = q b: q' = (a' - q b') / b, q''_xy = (a''_xy - q'_x b'_y - q'_y b'_x - q b''_xy) / b.
  friend Jet2 operator/(const Jet2& a, const Jet2& b) {
    const T inv = T(1.0) / b.v_;
    Jet2 q(a.v_ * inv);
    for (int i = 0; i < N; ++i) q.g_[i] = (a.g_[i] - q.v_ * b.g_[i]) * inv;
    for (int x = 0; x < N; ++x)
      for (int y = x; y < N; ++y) {
        const int p = pair(x, y);
        q.h_[p] = (a.h_[p] - (q.g_[x] * b.g_[y] + q.g_[y] * b.g_[x]) - q.v_ * b.h_[p]) * inv;
      }
    return q;
  }
  // Mixed with the base scalar and with constants.
  friend Jet2 operator*(const Jet2& a, const T& s) {
    Jet2 r(a.v_ * s);
    for (int i = 0; i < N; ++i) r.g_[i] = a.g_[i] * s;
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
};

}  // namespace interval
}  // namespace pkm_accuracy
