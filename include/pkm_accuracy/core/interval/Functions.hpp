// Rigorous transcendental functions on intervals.
//
// libm's sin/cos are not correctly rounded and ignore the rounding mode, so they are evaluated in round-to-nearest
// (under rounding::ScopedRoundToNearest) and each endpoint value is widened by kLibmUlpBound ulps; extrema inside
// the interval are detected with a long-double reduction and a safety margin that only ever adds an extremum
// (never drops one). The ulp bound is checked against MPFR on millions of arguments by the test suite.
#pragma once

#include "pkm_accuracy/core/interval/Interval.hpp"

namespace pkm_accuracy {
namespace interval {

/// Number of ulps by which a libm sin/cos result (round-to-nearest) is widened on each side. glibc documents
/// errors below 1 ulp for these functions on x86_64; 2 leaves a factor-two margin.
constexpr int kLibmUlpBound = 2;

/// Enclosure of { sin(x) : x in a }.
Interval sin(const Interval& a) noexcept;
/// Enclosure of { cos(x) : x in a }.
Interval cos(const Interval& a) noexcept;

/// Enclosure of sin(x) and cos(x) for a point x (one libm call each), used by point evaluations that need a
/// certified bound.
Interval sinPoint(double x) noexcept;
Interval cosPoint(double x) noexcept;

}  // namespace interval
}  // namespace pkm_accuracy
