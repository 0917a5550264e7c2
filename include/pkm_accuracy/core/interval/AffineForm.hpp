// First-order affine arithmetic in double over N noise symbols: a value
//   x = c + sum_m a_m tau_m + [-r, r],   tau_m in [-1, 1],
// for quantities that are smooth functions of N box variables (the pose over a pose box). Unlike an interval, the
// linear part keeps the correlations between quantities computed from the same variables, so a linear combination
// of them (a dot product with a fixed vector) is enclosed to first order exactly; everything of second order goes
// to r. Used for the geometry derivatives of the Gough platform over a pose box (GoughPlatform::
// geometryDerivatives), whose dot products d_e . v the geometry-aware enclosure needs.
//
// Rounding (the same policy as Rounding.hpp and MidRad.hpp: correct in any IEEE rounding mode, no mode switch):
// every coefficient is a sum of at most 3 floating-point products and sums, each off by at most 2^-52 of its
// magnitude, so its error is below kErr = 1e-15 times the sum of the magnitudes of the terms it is made of; r
// collects these bounds, and r itself is rounded up with up(). Non-finite values propagate: callers check finite().
// Nonlinear functions use the first-order Taylor form with the Lagrange remainder, the value and the derivative at c
// and the second derivative over the range enclosed in interval arithmetic (so libm's rounding is covered).
#pragma once

#include <cmath>

#include "pkm_accuracy/core/interval/AffineFunctions.hpp"
#include "pkm_accuracy/core/interval/Functions.hpp"
#include "pkm_accuracy/core/interval/Interval.hpp"
#include "pkm_accuracy/core/interval/Rounding.hpp"

namespace pkm_accuracy {
namespace interval {

template <int N>
class AffineForm {
 public:
  AffineForm() = default;
  /// The exact value x.
  explicit AffineForm(double x) : c_(x) {}
  /// An enclosure of the interval x, independent of the noise symbols (NaN if x is empty).
  explicit AffineForm(const Interval& x) {
    if (x.isEmpty()) {
      c_ = r_ = std::nan("");
      return;
    }
    c_ = x.mid();
    r_ = up(radiusAbout(x, c_));
  }
  /// The box variable x in [lower, upper] as symbol m: c + a tau_m with a >= the half-width (so tau in [-1, 1]
  /// covers x; it may cover a little more, which only widens the enclosures).
  static AffineForm variable(const Interval& x, int m) {
    AffineForm f;
    f.c_ = x.mid();
    f.a_[m] = up(radiusAbout(x, f.c_));
    return f;
  }

  /// The form c + sum_m a[m] tau_m + [-r, r] exactly as given (r >= 0; NaN r if it is not): the caller guarantees
  /// that it encloses what it stands for (e.g. the entries of another affine representation over the same symbols).
  static AffineForm fromParts(double c, const double* a, double r) {
    AffineForm f;
    f.c_ = c;
    for (int m = 0; m < N; ++m) f.a_[m] = a[m];
    f.r_ = r >= 0.0 ? r : std::nan("");
    return f;
  }
  double centre() const { return c_; }
  double coefficient(int m) const { return a_[m]; }
  double radius() const { return r_; }
  /// sum |a_m| + r (rounded up): the largest deviation from the centre.
  double deviation() const {
    double s = r_;
    for (int m = 0; m < N; ++m) s += std::abs(a_[m]);
    return up(s);
  }
  bool finite() const {
    bool ok = std::isfinite(c_) && std::isfinite(r_);
    for (int m = 0; m < N; ++m) ok = ok && std::isfinite(a_[m]);
    return ok;
  }
  /// The range [c - deviation, c + deviation] (rounded outward).
  Interval toInterval() const {
    const double d = deviation();
    return Interval(rounding::subDown(c_, d), rounding::addUp(c_, d));
  }

  friend AffineForm operator+(const AffineForm& x, const AffineForm& y) { return combine(x, y, 1.0); }
  friend AffineForm operator-(const AffineForm& x, const AffineForm& y) { return combine(x, y, -1.0); }
  friend AffineForm operator-(const AffineForm& x) {
    AffineForm f = x;
    f.c_ = -f.c_;
    for (int m = 0; m < N; ++m) f.a_[m] = -f.a_[m];
    return f;
  }
  /// x s for an exact double s.
  friend AffineForm operator*(const AffineForm& x, double s) {
    AffineForm f;
    const double as = std::abs(s);
    f.c_ = x.c_ * s;
    double err = std::abs(f.c_);
    for (int m = 0; m < N; ++m) {
      f.a_[m] = x.a_[m] * s;
      err += std::abs(f.a_[m]);
    }
    f.r_ = up(x.r_ * as + kErr * err);
    return f;
  }
  friend AffineForm operator*(const AffineForm& x, const AffineForm& y) {
    // (xc + X)(yc + Y) = xc yc + xc Y + yc X + X Y (X, Y: the parts around the centres). In X Y, the square terms
    // x_m y_m tau_m^2 lie in x_m y_m [0, 1] = x_m y_m / 2 + [-|x_m y_m| / 2, |x_m y_m| / 2]: their mean goes to the
    // centre, and |X Y - sum_m x_m y_m / 2| <= dev(x) dev(y) - sum_m |x_m y_m| / 2.
    AffineForm f;
    const double axc = std::abs(x.c_), ayc = std::abs(y.c_);
    double half = 0.0, halfMag = 0.0, xa = 0.0, ya = 0.0;
    for (int m = 0; m < N; ++m) {
      f.a_[m] = x.c_ * y.a_[m] + y.c_ * x.a_[m];
      const double d = x.a_[m] * y.a_[m];
      half += d;
      halfMag += std::abs(d);
      xa += std::abs(x.a_[m]);
      ya += std::abs(y.a_[m]);
    }
    // (The coefficients' terms' magnitudes sum_m (|xc| |y_m| + |yc| |x_m|) from the sums of the |x_m| and |y_m|: the
    // same sum but for rounding far below kErr's slack.)
    double err = axc * ya + ayc * xa;
    const double sx = x.r_ + xa, sy = y.r_ + ya;
    half *= 0.5;                     // exact but for underflow, which the floor in up() covers
    halfMag *= 0.5 * (1.0 - 1e-14);  // a lower bound of sum_m |x_m y_m| / 2 (it is subtracted below)
    f.c_ = x.c_ * y.c_ + half;
    err += std::abs(x.c_ * y.c_) + std::abs(f.c_) + 4.0 * halfMag;
    // sx sy - halfMag >= sx sy / 2 (halfMag <= sum_m |x_m| |y_m| / 2), so every term of the radius below is >= 0 and
    // computed with a relative error of a few 2^-53 (sums of non-negative terms, one product, one well-conditioned
    // subtraction): up()'s relative 1e-12 covers them.
    f.r_ = up(axc * y.r_ + ayc * x.r_ + (sx * sy - halfMag) + kErr * err);
    return f;
  }
  AffineForm& operator+=(const AffineForm& o) { return *this = *this + o; }
  AffineForm& operator-=(const AffineForm& o) { return *this = *this - o; }

  /// f(x) = f(c) + f'(c) (x - c) + f''(xi) (x - c)^2 / 2: value0 and slope0 enclose f(c) and f'(c), curvature encloses
  /// f'' over the range of x. Where f'' keeps its sign over the range (f convex or concave there: 1 / x, sqrt, cos near
  /// 0), the remainder lies in [0, M dev^2 / 2] (or its mirror), M = |f''| max: its midpoint goes to the centre and the
  /// radius is M dev^2 / 4, half the symmetric one.
  static AffineForm taylor(const AffineForm& x, const Interval& value0, const Interval& slope0,
                           const Interval& curvature) {
    AffineForm f;
    const double dev = x.deviation();
    const double s = slope0.mid();
    const double sRad = radiusAbout(slope0, s);
    const double quarter = 0.25 * curvature.mag() * up(dev * dev);  // (exact scaling but for underflow)
    const double shift = curvature.lower() >= 0.0 ? quarter : (curvature.upper() <= 0.0 ? -quarter : 0.0);
    f.c_ = value0.mid() + shift;
    const double cRad = radiusAbout(value0, value0.mid());
    double err = std::abs(value0.mid()) + std::abs(shift) + std::abs(f.c_);
    for (int m = 0; m < N; ++m) {
      f.a_[m] = s * x.a_[m];
      err += std::abs(f.a_[m]);
    }
    const double remainder = shift != 0.0 ? quarter : 2.0 * quarter;
    f.r_ = up(cRad + std::abs(s) * x.r_ + sRad * dev + remainder + kErr * err);
    return f;
  }

 private:
  static constexpr double kErr = 1e-15;
  static_assert(kErr >= rounding::gamma(3), "kErr covers sums of at most 3 products and sums");
  static double up(double x) { return rounding::up(x); }
  static AffineForm combine(const AffineForm& x, const AffineForm& y, double sign) {
    AffineForm f;
    f.c_ = x.c_ + sign * y.c_;
    double err = std::abs(x.c_) + std::abs(y.c_);
    for (int m = 0; m < N; ++m) {
      f.a_[m] = x.a_[m] + sign * y.a_[m];
      err += std::abs(x.a_[m]) + std::abs(y.a_[m]);
    }
    f.r_ = up(x.r_ + y.r_ + kErr * err);
    return f;
  }

  double c_ = 0.0;
  double a_[N] = {};
  double r_ = 0.0;
};

/// sqrt, 1 / x, sin and cos (AffineFunctions.hpp: first-order Taylor forms, remainders over the range).
template <int N>
AffineForm<N> sqrt(const AffineForm<N>& x) {
  return taylorSqrt(x);
}
template <int N>
AffineForm<N> reciprocal(const AffineForm<N>& x) {
  return taylorReciprocal(x);
}
/// x / y as x * (1 / y) (non-finite where the range of y reaches 0, or where x or y is not finite).
template <int N>
AffineForm<N> operator/(const AffineForm<N>& x, const AffineForm<N>& y) {
  if (!x.finite() || !y.finite()) return AffineForm<N>(std::nan(""));
  return x * reciprocal(y);
}
template <int N>
AffineForm<N> sin(const AffineForm<N>& x) {
  return taylorSin(x);
}
template <int N>
AffineForm<N> cos(const AffineForm<N>& x) {
  return taylorCos(x);
}

}  // namespace interval
}  // namespace pkm_accuracy
