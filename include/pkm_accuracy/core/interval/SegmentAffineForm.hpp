// First-order affine arithmetic over N noise symbols whose remainder is split by how it scales towards the centre of
// the box: for every point tau = s tau^ of the segments from the centre (tau^ in [-1, 1]^N, s in [0, 1]),
//   x(tau) in c + sum_m a_m tau_m + [-(r0 + s^2 r2), r0 + s^2 r2].
// r2 collects the nonlinearity (the products of the linear parts, the Taylor remainders), which vanishes
// quadratically at the centre, and r0 what does not (roundings, the radii of interval constants). Used where a bound
// is integrated along those segments, in mean-value and Taylor forms about the box centre (the weights of s^2 there
// are 1/3 and 1/6): GoughPlatform::preconditionedHessianMagnitude. Unlike AffineForm, no mean of the square terms or
// of a one-signed Taylor remainder goes to the centre (such a shift would not vanish at the centre), so over the
// whole box (s = 1) the form is a little wider than AffineForm's.
//
// Derivation of the operations, with X = sum_m x_m tau_m (|X| <= s dx, dx = sum_m |x_m|) and Ex the remainder of x
// (|Ex| <= x.r0 + s^2 x.r2), and s^3, s^4 <= s^2, s <= 1:
//   x y - (xc yc + xc Y + yc X) = xc Ey + yc Ex + X Y + X Ey + Ex Y + Ex Ey,
//   f(x) - (f(c) + f'(c) X) = f'(c) Ex + f''(xi) (X + Ex)^2 / 2 with (X + Ex)^2 <= s^2 (dx + x.r2)^2 +
//   2 (dx + x.r2) x.r0 + x.r0^2.
// Rounding: the same policy as AffineForm (every coefficient within kErr = 1e-15 of the magnitudes of its terms, into
// r0; the radii rounded up with a relative 1e-12); correct in any IEEE rounding mode. Non-finite values propagate:
// callers check finite().
#pragma once

#include <cmath>

#include "pkm_accuracy/core/interval/AffineFunctions.hpp"
#include "pkm_accuracy/core/interval/Functions.hpp"
#include "pkm_accuracy/core/interval/Interval.hpp"
#include "pkm_accuracy/core/interval/Rounding.hpp"

namespace pkm_accuracy {
namespace interval {

template <int N>
class SegmentAffineForm {
 public:
  SegmentAffineForm() = default;
  /// The exact value x.
  explicit SegmentAffineForm(double x) : c_(x) {}
  /// An enclosure of the interval x (its radius in r0), independent of the noise symbols (NaN if x is empty).
  explicit SegmentAffineForm(const Interval& x) {
    if (x.isEmpty()) {
      c_ = r0_ = std::nan("");
      return;
    }
    c_ = x.mid();
    r0_ = up(radiusAbout(x, c_));
  }
  /// The box variable x in [lower, upper] as symbol m: its midpoint + a tau_m, a >= the half-width (the centre of
  /// the box is the midpoint of every variable).
  static SegmentAffineForm variable(const Interval& x, int m) {
    SegmentAffineForm f;
    f.c_ = x.mid();
    f.a_[m] = up(radiusAbout(x, f.c_));
    return f;
  }

  double centre() const { return c_; }
  double coefficient(int m) const { return a_[m]; }
  /// The remainder's parts: r0 (constant) and r2 (times s^2 on the segment at s).
  double constantRadius() const { return r0_; }
  double quadraticRadius() const { return r2_; }
  /// The remainder over the whole box (s = 1), rounded up.
  double radius() const { return up(r0_ + r2_); }
  /// sum |a_m| + r0 + r2 (rounded up): the largest deviation from the centre over the box.
  double deviation() const {
    double s = r0_ + r2_;
    for (int m = 0; m < N; ++m) s += std::abs(a_[m]);
    return up(s);
  }
  bool finite() const {
    bool ok = std::isfinite(c_) && std::isfinite(r0_) && std::isfinite(r2_);
    for (int m = 0; m < N; ++m) ok = ok && std::isfinite(a_[m]);
    return ok;
  }
  /// The range over the box (rounded outward).
  Interval toInterval() const {
    const double d = deviation();
    return Interval(rounding::subDown(c_, d), rounding::addUp(c_, d));
  }

  friend SegmentAffineForm operator+(const SegmentAffineForm& x, const SegmentAffineForm& y) {
    return combine(x, y, 1.0);
  }
  friend SegmentAffineForm operator-(const SegmentAffineForm& x, const SegmentAffineForm& y) {
    return combine(x, y, -1.0);
  }
  friend SegmentAffineForm operator-(const SegmentAffineForm& x) {
    SegmentAffineForm f = x;
    f.c_ = -f.c_;
    for (int m = 0; m < N; ++m) f.a_[m] = -f.a_[m];
    return f;
  }
  /// x s for an exact double s.
  friend SegmentAffineForm operator*(const SegmentAffineForm& x, double s) {
    SegmentAffineForm f;
    const double as = std::abs(s);
    f.c_ = x.c_ * s;
    double err = std::abs(f.c_);
    for (int m = 0; m < N; ++m) {
      f.a_[m] = x.a_[m] * s;
      err += std::abs(f.a_[m]);
    }
    f.r0_ = up(x.r0_ * as + kErr * err);
    f.r2_ = up(x.r2_ * as);
    return f;
  }
  friend SegmentAffineForm operator*(const SegmentAffineForm& x, const SegmentAffineForm& y) {
    SegmentAffineForm f;
    const double axc = std::abs(x.c_), ayc = std::abs(y.c_);
    double dx = 0.0, dy = 0.0;
    for (int m = 0; m < N; ++m) {
      f.a_[m] = x.c_ * y.a_[m] + y.c_ * x.a_[m];
      dx += std::abs(x.a_[m]);
      dy += std::abs(y.a_[m]);
    }
    f.c_ = x.c_ * y.c_;
    // (The coefficients' terms' magnitudes from the sums of |x_m| and |y_m|: the same but for rounding far below
    // kErr's slack.)
    const double err = axc * dy + ayc * dx + std::abs(f.c_);
    f.r0_ = up(axc * y.r0_ + ayc * x.r0_ + dx * y.r0_ + x.r0_ * dy + x.r0_ * y.r0_ + kErr * err);
    f.r2_ = up(axc * y.r2_ + ayc * x.r2_ + dx * dy + dx * y.r2_ + x.r2_ * dy + x.r0_ * y.r2_ + x.r2_ * y.r0_ +
               x.r2_ * y.r2_);
    return f;
  }
  SegmentAffineForm& operator+=(const SegmentAffineForm& o) { return *this = *this + o; }
  SegmentAffineForm& operator-=(const SegmentAffineForm& o) { return *this = *this - o; }

  /// f(x) = f(c) + f'(c) (x - c) + f''(xi) (x - c)^2 / 2: value0 and slope0 enclose f(c) and f'(c), curvature encloses
  /// f'' over the range of x (over the whole box).
  static SegmentAffineForm taylor(const SegmentAffineForm& x, const Interval& value0, const Interval& slope0,
                                  const Interval& curvature) {
    SegmentAffineForm f;
    double dx = 0.0;
    for (int m = 0; m < N; ++m) dx += std::abs(x.a_[m]);
    f.c_ = value0.mid();
    const double s = slope0.mid();
    const double sRad = radiusAbout(slope0, s);
    const double cRad = radiusAbout(value0, f.c_);
    double err = std::abs(f.c_);
    for (int m = 0; m < N; ++m) {
      f.a_[m] = s * x.a_[m];
      err += std::abs(f.a_[m]);
    }
    const double mm = curvature.mag(), e2 = dx + x.r2_;
    f.r0_ = up(cRad + std::abs(s) * x.r0_ + sRad * (dx + x.r0_ + x.r2_) +
               0.5 * mm * (2.0 * e2 * x.r0_ + x.r0_ * x.r0_) + kErr * err);
    f.r2_ = up(std::abs(s) * x.r2_ + 0.5 * mm * e2 * e2);
    return f;
  }

 private:
  static constexpr double kErr = 1e-15;
  static_assert(kErr >= rounding::gamma(3), "kErr covers sums of at most 3 products and sums");
  static double up(double x) { return rounding::up(x); }
  static SegmentAffineForm combine(const SegmentAffineForm& x, const SegmentAffineForm& y, double sign) {
    SegmentAffineForm f;
    f.c_ = x.c_ + sign * y.c_;
    double err = std::abs(x.c_) + std::abs(y.c_);
    for (int m = 0; m < N; ++m) {
      f.a_[m] = x.a_[m] + sign * y.a_[m];
      err += std::abs(x.a_[m]) + std::abs(y.a_[m]);
    }
    f.r0_ = up(x.r0_ + y.r0_ + kErr * err);
    f.r2_ = up(x.r2_ + y.r2_);
    return f;
  }

  double c_ = 0.0;
  double a_[N] = {};
  double r0_ = 0.0, r2_ = 0.0;
};

/// sqrt, 1 / x, sin and cos (AffineFunctions.hpp: first-order Taylor forms, remainders over the range).
template <int N>
SegmentAffineForm<N> sqrt(const SegmentAffineForm<N>& x) {
  return taylorSqrt(x);
}
template <int N>
SegmentAffineForm<N> reciprocal(const SegmentAffineForm<N>& x) {
  return taylorReciprocal(x);
}
/// x / y as x * (1 / y) (non-finite where the range of y reaches 0, or where x or y is not finite).
template <int N>
SegmentAffineForm<N> operator/(const SegmentAffineForm<N>& x, const SegmentAffineForm<N>& y) {
  if (!x.finite() || !y.finite()) return SegmentAffineForm<N>(std::nan(""));
  return x * reciprocal(y);
}
template <int N>
SegmentAffineForm<N> sin(const SegmentAffineForm<N>& x) {
  return taylorSin(x);
}
template <int N>
SegmentAffineForm<N> cos(const SegmentAffineForm<N>& x) {
  return taylorCos(x);
}

}  // namespace interval
}  // namespace pkm_accuracy
