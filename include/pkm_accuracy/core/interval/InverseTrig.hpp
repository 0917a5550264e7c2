// Rigorous inverse trigonometric functions on intervals (atan2, asin) and their forward-mode derivative rules for
// Dual<T, N> (T = double for point derivatives, T = Interval for enclosures over a box).
//
// Method (as for sin / cos in Functions.hpp): glibc's atan2 / asin are evaluated in round-to-nearest (under
// rounding::ScopedRoundToNearest) at the points where the extremes are attained, and each value v is widened to
// rounding::widenByUlps(v, kInverseTrigUlpBound) (every real within that many ulps of v, in ulps of that real), then
// clamped to [-piUpper(), piUpper()] / [-halfPiUpper(), halfPiUpper()], which contain the function's range. The ulp
// bound is checked against MPFR on >= 10^5 random arguments per function, including edge cases (signed zeros,
// subnormals, huge ratios, the axes and the branch cut), by test/core/InverseTrigMpfrTest.cpp.
//
// Extremes:
//   * asin is increasing on [-1, 1]: asin(X) = [asin(lo), asin(hi)] after intersecting X with [-1, 1] (empty if X
//     lies outside [-1, 1]).
//   * atan2(Y, X) is the angle of (x, y) in (-pi, pi] (atan2(0, x) = pi for x < 0, as the principal argument).
//     Over a box that contains the origin, or that contains a point of the negative x axis together with points
//     below it (y < 0), the result is [-pi, pi] (the angle wraps around there). Otherwise the angle is continuous on
//     the box, which is convex and avoids the origin, so its range is spanned by the four corners: [min, max] of
//     atan2 at the corners, with a zero y bound taken as +0 (the angle pi on the negative x axis). Unbounded
//     operands give [-pi, pi].
#pragma once

#include <cmath>

#include "pkm_accuracy/core/interval/Dual.hpp"
#include "pkm_accuracy/core/interval/Interval.hpp"

namespace pkm_accuracy {
namespace interval {

/// Assumed bound of the error of a libm atan2 / asin result (round-to-nearest), in ulps of the exact value; the
/// results are widened by rounding::widenByUlps with it. glibc 2.36 measures below 0.52 ulp on the test's random and
/// hard cases (docs/soundness.md; the MPFR test fails if any case exceeds this bound).
constexpr int kInverseTrigUlpBound = 2;

/// Enclosure of { atan2(y, x) : y in Y, x in X, (x, y) != (0, 0) } in [-pi, pi] (principal value in (-pi, pi]).
Interval atan2(const Interval& y, const Interval& x) noexcept;
/// Enclosure of { asin(x) : x in X, -1 <= x <= 1 } (empty if X does not meet [-1, 1]).
Interval asin(const Interval& x) noexcept;

/// Upper bounds of pi and pi / 2 (the doubles just above them).
double piUpper() noexcept;
double halfPiUpper() noexcept;

namespace detail {
/// The point evaluations behind atan2 and asin (glibc, round-to-nearest must be in force). Exposed so that the tests
/// can measure their error against MPFR.
double libmAtan2(double y, double x) noexcept;
double libmAsin(double x) noexcept;

inline double square(double v) { return v * v; }
inline Interval square(const Interval& v) { return sqr(v); }
}  // namespace detail

// ---- derivative rules ---------------------------------------------------------------------------------------------
/// d atan2(y, x) = (x dy - y dx) / (x^2 + y^2): the same formula on both sides of the branch cut, so the derivative
/// enclosure stays valid where the value wraps around.
template <typename T, int N>
Dual<T, N> atan2(const Dual<T, N>& y, const Dual<T, N>& x) {
  using std::atan2;
  const T& yv = y.value();
  const T& xv = x.value();
  Dual<T, N> r(atan2(yv, xv));
  const T den = detail::square(xv) + detail::square(yv);
  for (int i = 0; i < N; ++i) r.d(i) = (xv * y.d(i) - yv * x.d(i)) / den;
  return r;
}

/// d asin(x) = dx / sqrt(1 - x^2) (unbounded enclosure where |x| may reach 1).
template <typename T, int N>
Dual<T, N> asin(const Dual<T, N>& x) {
  using std::asin;
  using std::sqrt;
  const T& xv = x.value();
  Dual<T, N> r(asin(xv));
  const T root = sqrt(T(1.0) - detail::square(xv));
  for (int i = 0; i < N; ++i) r.d(i) = x.d(i) / root;
  return r;
}

}  // namespace interval
}  // namespace pkm_accuracy
