// Midpoint-radius arithmetic in double: a value [m - r, m + r] with r >= 0, for long formulas whose operands are
// narrow (the pose Hessian of the Gough platform), at a fraction of the cost of endpoint intervals.
//
// Rounding (the same policy as Rounding.hpp: correct in any IEEE rounding mode, no mode switch): for a sum or product
// s = fl(a op b) of doubles, |s - (a op b)| <= 2^-52 |s| in every rounding mode (the error is below one ulp of s, and
// ulp(s) <= 2^-52 |s| for normal s), and subnormal results are off by less than 2^-1074. So
//   a + b: m = fl(am + bm),  r = up(ar + br + 2^-52 |m|)
//   a * b: m = fl(am bm),    r = up(|am| br + ar |bm| + ar br + 2^-52 |m|), or, when neither contains 0, the exact
//          hull: m = fl(am bm) +- fl(ar br) (the sign of am bm), r = up(|am| br + ar |bm| + 2^-52 (|am bm| + ar br +
//          |m|))
// where up(x) = x (1 + 1e-12) + 1e-300 (rounding::up) bounds the rounding of the radius expression itself (a few
// operations, each off by at most a relative 2^-52, and the absolute floor covers subnormals). The exact results of the
// operations on every pair of points of the operands lie in the computed [m - r, m + r]. Non-finite values propagate (m
// or r infinite or NaN): callers check finite() before use.
#pragma once

#include <cmath>

#include "pkm_accuracy/core/interval/Interval.hpp"
#include "pkm_accuracy/core/interval/Rounding.hpp"

namespace pkm_accuracy {
namespace interval {

class MidRad {
 public:
  MidRad() = default;
  MidRad(double m, double r) : m_(m), r_(r) {}
  /// The exact value x.
  explicit MidRad(double x) : m_(x), r_(0.0) {}
  /// An enclosure of the interval x (NaN if x is empty).
  explicit MidRad(const Interval& x) {
    if (x.isEmpty()) {
      m_ = r_ = std::nan("");
      return;
    }
    m_ = x.mid();
    r_ = up(radiusAbout(x, m_));
  }

  double mid() const { return m_; }
  double rad() const { return r_; }
  bool finite() const { return std::isfinite(m_) && std::isfinite(r_); }
  /// The endpoint interval [m - r, m + r] (rounded outward).
  Interval toInterval() const { return Interval(rounding::subDown(m_, r_), rounding::addUp(m_, r_)); }

  friend MidRad operator+(const MidRad& a, const MidRad& b) {
    const double m = a.m_ + b.m_;
    return MidRad(m, up(a.r_ + b.r_ + kUlp * std::abs(m)));
  }
  friend MidRad operator-(const MidRad& a, const MidRad& b) {
    const double m = a.m_ - b.m_;
    return MidRad(m, up(a.r_ + b.r_ + kUlp * std::abs(m)));
  }
  friend MidRad operator-(const MidRad& a) { return MidRad(-a.m_, a.r_); }
  friend MidRad operator*(const MidRad& a, const MidRad& b) {
    const double p = a.m_ * b.m_, q = a.r_ * b.r_;
    const double cross = std::abs(a.m_) * b.r_ + a.r_ * std::abs(b.m_);
    if (std::abs(a.m_) > a.r_ && std::abs(b.m_) > b.r_) {
      // Neither contains 0: the exact hull is |a||b| +- its extremes, i.e. midpoint p + sign(p) q, radius `cross`.
      const double m = p >= 0.0 ? p + q : p - q;
      return MidRad(m, up(cross + kUlp * (std::abs(p) + q + std::abs(m))));
    }
    return MidRad(p, up(cross + q + kUlp * std::abs(p)));
  }
  MidRad& operator+=(const MidRad& o) { return *this = *this + o; }
  MidRad& operator-=(const MidRad& o) { return *this = *this - o; }

 private:
  static constexpr double kUlp = rounding::kUnitRoundoff;
  static double up(double x) { return rounding::up(x); }
  double m_ = 0.0, r_ = 0.0;
};

}  // namespace interval
}  // namespace pkm_accuracy
