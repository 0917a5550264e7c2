#include "pkm_accuracy/core/interval/InverseTrig.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "pkm_accuracy/core/interval/Rounding.hpp"

namespace pkm_accuracy {
namespace interval {
namespace {

// M_PI and M_PI_2 as doubles are below pi and pi / 2 (0x1.921fb54442d18p+1 < pi < 0x1.921fb54442d19p+1), so the
// next doubles are upper bounds.
constexpr double kPiDouble = 3.141592653589793116;      // 0x1.921fb54442d18p+1 < pi
constexpr double kHalfPiDouble = 1.570796326794896558;  // 0x1.921fb54442d18p+0 < pi / 2

/// Enclosure of the exact value whose libm value (round-to-nearest) is v: within kInverseTrigUlpBound ulps of v, in
/// ulps of the exact value (rounding::widenByUlps proves the bounds).
rounding::Bounds widen(double v) noexcept { return rounding::widenByUlps(v, kInverseTrigUlpBound); }

/// +0 for either zero (the angle of a point on the negative x axis is +pi).
double positiveZero(double v) noexcept { return v == 0.0 ? 0.0 : v; }

}  // namespace

double piUpper() noexcept { return rounding::nextUp(kPiDouble); }
double halfPiUpper() noexcept { return rounding::nextUp(kHalfPiDouble); }

namespace detail {
double libmAtan2(double y, double x) noexcept { return std::atan2(y, x); }
double libmAsin(double x) noexcept { return std::asin(x); }
}  // namespace detail

Interval atan2(const Interval& y, const Interval& x) noexcept {
  if (y.isEmpty() || x.isEmpty()) return Interval::empty();
  const double pi = piUpper();
  const Interval full = Interval::fromBoundsUnchecked(-pi, pi);
  if (!y.isBounded() || !x.isBounded()) return full;
  // The origin, or the negative x axis with points below it: the angle wraps from -pi to pi inside the box.
  if (y.containsZero() && x.containsZero()) return full;
  if (x.lower() < 0.0 && y.lower() < 0.0 && y.upper() >= 0.0) return full;
  rounding::ScopedRoundToNearest rn;
  const double ys[2] = {positiveZero(y.lower()), positiveZero(y.upper())};
  const double xs[2] = {x.lower(), x.upper()};
  // The exact angle at each corner lies in its widened libm value; the hull of the four encloses the range. (Each
  // corner is widened: the widened bounds are not monotone in the libm value near powers of two.)
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (double yc : ys) {
    for (double xc : xs) {
      const rounding::Bounds b = widen(detail::libmAtan2(yc, xc));
      lo = std::min(lo, b.lower);
      hi = std::max(hi, b.upper);
    }
  }
  return Interval::fromBoundsUnchecked(std::max(lo, -pi), std::min(hi, pi));
}

Interval asin(const Interval& x) noexcept {
  const Interval d = intersect(x, Interval::fromBoundsUnchecked(-1.0, 1.0));
  if (d.isEmpty()) return d;
  rounding::ScopedRoundToNearest rn;
  const double half = halfPiUpper();
  // asin is increasing: its range is [asin(lo), asin(hi)], each exact value in its widened libm value.
  const double l = widen(detail::libmAsin(d.lower())).lower, h = widen(detail::libmAsin(d.upper())).upper;
  return Interval::fromBoundsUnchecked(std::max(l, -half), std::min(h, half));
}

}  // namespace interval
}  // namespace pkm_accuracy
