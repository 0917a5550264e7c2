// Rigorous transcendental functions on intervals.
//
// libm's sin/cos are not correctly rounded and are only specified for round-to-nearest, so they are evaluated in
// round-to-nearest (under rounding::ScopedRoundToNearest, which restores the caller's environment; for |x| >= 2^26
// through the long double sinl/cosl, see detail::libmSin) and each endpoint value v is widened to
// rounding::widenByUlps(v, kLibmUlpBound), which contains every real within kLibmUlpBound ulps of v in ulps of that
// real (then clamped to [-1, 1]). Extrema inside the interval are added when they may be there, never dropped:
//   * |x| <= 2^30: the extrema phase + k pi are located by a long-double reduction with a proven error margin
//     (Functions.cpp explains the bound);
//   * larger |x|, width < 1: a derivative test on point values (sinl/cosl reduce every double accurately);
//   * larger |x|, width >= 1, width >= 6.2831 or an unbounded interval: [-1, 1].
// A degenerate interval [x, x] gives the widened libm value for every finite x. The ulp bound is checked against
// MPFR on millions of arguments (including huge ones and the nearest doubles to k pi / 2) by the test suite; the
// measured figures are in docs/interval-arithmetic.md.
#pragma once

#include "pkm_accuracy/core/interval/Interval.hpp"

namespace pkm_accuracy {
namespace interval {

/// Assumed bound of the error of a libm sin/cos result (detail::libmSin / libmCos in round-to-nearest), in ulps of the
/// exact value; the results are widened by rounding::widenByUlps with it. The measured maximum error is about
/// 0.56 ulp (docs/soundness.md; the MPFR test fails if any case exceeds this bound); 2 leaves a margin of
/// more than three.
constexpr int kLibmUlpBound = 2;

/// Enclosure of { sin(x) : x in a }.
Interval sin(const Interval& a) noexcept;
/// Enclosure of { cos(x) : x in a }.
Interval cos(const Interval& a) noexcept;

/// Enclosure of sin(x) and cos(x) for a point x (one libm call each), used by point evaluations that need a
/// certified bound. NaN gives the empty interval, +-inf gives [-1, 1].
Interval sinPoint(double x) noexcept;
Interval cosPoint(double x) noexcept;

namespace detail {
/// The unwidened point evaluations behind sin, cos, sinPoint and cosPoint: glibc sin/cos for |x| < 2^26, the long
/// double sinl/cosl rounded to double above (glibc's double sin/cos lose up to ~1e5 ulps on hard huge arguments).
/// Round-to-nearest must be in force. Exposed so that the tests can measure their error against MPFR; within
/// kLibmUlpBound ulps of the exact value (NaN for |x| >= 2^26 where long double is not extended precision).
double libmSin(double x) noexcept;
double libmCos(double x) noexcept;
}  // namespace detail

}  // namespace interval
}  // namespace pkm_accuracy
