#include "pkm_accuracy/core/interval/Functions.hpp"

#include <cmath>
#include <limits>

namespace pkm_accuracy {
namespace interval {
namespace {

// Enclosure of the exact value y of sin / cos whose libm value (round-to-nearest) is v: y is within kLibmUlpBound
// ulps of v, in ulps of y, so y lies in rounding::widenByUlps(v, kLibmUlpBound) (proof there; near a power of two it
// steps 2k ulps on the side away from zero); y also lies in [-1, 1], so clamping keeps it. NaN (no trustworthy
// evaluation available) gives [-1, 1].
Interval widenLibm(double v) noexcept {
  if (v != v) return Interval::fromBoundsUnchecked(-1.0, 1.0);
  const rounding::Bounds b = rounding::widenByUlps(v, kLibmUlpBound);
  return Interval::fromBoundsUnchecked(std::max(b.lower, -1.0), std::min(b.upper, 1.0));
}

// ---- extremum detection by long-double reduction (|x| <= kReductionLimit) ----------------------------------------
//
// The extrema of sin are pi/2 + k pi and those of cos are k pi: maxima for even k, minima for odd k.
// mayContainExtrema(a, b, phase) returns kMax / kMin bits that must be set whenever [a, b] contains a point
// c = phase + k pi with even / odd k; a spurious bit only widens the result by adding the extremum value +-1.
//
// Rigour of the margin. Let u be the unit roundoff of long double in the worst case: u <= 2^-52 (53-bit significand,
// e.g. an x87 precision control set to double or a platform where long double is double, in a directed rounding
// mode; with the usual 64-bit x87 significand u = 2^-63). For |a|, |b| <= 2^30 the candidate k satisfy |k| < 2^29,
// so k, its parity and k0 + j are exact. The computed c = fl(P + fl(k T)), with P = fl(phase) and T = fl(pi), obeys
//   |P - phase| <= u pi/2,  |T - pi| <= pi u,  |fl(k T) - k pi| <= 2.01 u |k pi|,  |c - fl(P + fl(kT))| <= u |c|
// and |k pi| <= |c_exact| + pi/2, so |c - c_exact| <= 3.1 u (|c| + pi) < 2^-50 (|c| + 4). The margin used below,
// 2^-40 (|c| + 4), is 1024 times larger, which also absorbs the rounding of a - margin and b + margin
// (<= u (|c| + 2 pi + 1)). Hence c_exact in [a, b] implies that the test finds c. The margin costs nothing in
// practice: an extremum is only added spuriously when an endpoint lies within the margin of it, where the function
// differs from +-1 by at most margin^2 / 2 (< 2^-21 even at |x| = 2^30, < 1e-24 for |x| < 10).
//
// Which k are tried: t = (a - P) / T has an absolute error far below 1, so the computed floor(t) is within 1 of the
// exact one; every k with c_k in [a - margin, b + margin] lies in [floor(t) - 1, floor(t) + 2] because
// b - a < 6.2832 < 2 pi (the caller handles wider intervals); trying floor(t) - 2 ... floor(t) + 3 in increasing
// order, and stopping once c_k exceeds b + margin, covers both.
constexpr double kReductionLimit = 0x1p30;
constexpr long double kMarginRelative = 0x1p-40L;
constexpr long double kHalfPi = 1.570796326794896619231321691639751442L;
constexpr long double kPi = 3.141592653589793238462643383279502884L;
static_assert(std::numeric_limits<long double>::digits >= 53, "the margin analysis assumes at least double precision");
constexpr int kMaxBit = 1, kMinBit = 2;

int mayContainExtrema(double a, double b, long double phase) noexcept {
  const long double la = a, lb = b;
  const long double k0 = std::floor((la - phase) / kPi) - 2.0L;
  int found = 0;
  for (int j = 0; j <= 5; ++j) {
    const long double k = k0 + j;
    const long double c = phase + k * kPi;
    const long double margin = kMarginRelative * (std::fabs(c) + 4.0L);
    if (c > lb + margin) break;
    if (c >= la - margin) found |= (static_cast<long long>(k) & 1) ? kMinBit : kMaxBit;  // NOLINT(runtime/int)
  }
  return found;
}

// ---- extremum detection by the derivative (any magnitude, narrow intervals) --------------------------------------
//
// For f = sin (g = cos) or f = cos (g = sin), the extrema of f are the zeros of g, and |g| is 1-Lipschitz. If a zero
// c of g lies in [a, b] then |g(a)| = |g(a) - g(c)| <= |a - c| <= w for any upper bound w of b - a; so a certified
// lower bound of |g(a)| or |g(b)| above w proves f monotone on [a, b]. Otherwise, for w < 1 < pi there is at most
// one such c, and f(a) = f(c) cos(a - c) with cos(a - c) >= cos(1) > 0: the sign of f(a) (|f(a)| >= cos 1, far from
// 0 compared with its few-ulp enclosure) tells whether c is a maximum (+1) or a minimum (-1). Only point values are
// used (detail::libmSin / libmCos, accurate for every double; checked against MPFR up to DBL_MAX by the tests).
constexpr double kNarrowWidth = 1.0;

enum class Kind { kSin, kCos };

double libm(Kind kind, double x) noexcept { return kind == Kind::kSin ? detail::libmSin(x) : detail::libmCos(x); }
double libmCompanion(Kind kind, double x) noexcept {
  return kind == Kind::kSin ? detail::libmCos(x) : detail::libmSin(x);
}

Interval periodicEnclosure(const Interval& a, Kind kind) noexcept {
  if (a.isEmpty()) return a;
  const Interval unit = Interval::fromBoundsUnchecked(-1.0, 1.0);
  if (!a.isBounded()) return unit;
  // libm error bounds hold in round-to-nearest. The guard comes before any arithmetic, so that under a directed
  // mode the caller's environment, flags included, is restored exactly on every return path.
  rounding::ScopedRoundToNearest rn;
  const double lo = a.lower(), hi = a.upper();
  const double w = rounding::subUp(hi, lo);  // >= hi - lo
  if (w >= 6.2831) return unit;              // may contain a full period (2 pi = 6.28318...)
  const Interval fa = widenLibm(libm(kind, lo));
  if (lo == hi) return fa;
  const Interval fb = widenLibm(libm(kind, hi));
  Interval r = hull(fa, fb);
  bool addMax, addMin;
  if (std::max(-lo, hi) <= kReductionLimit) {
    const int found = mayContainExtrema(lo, hi, kind == Kind::kSin ? kHalfPi : 0.0L);
    addMax = (found & kMaxBit) != 0;
    addMin = (found & kMinBit) != 0;
  } else if (w < kNarrowWidth) {
    const Interval ga = widenLibm(libmCompanion(kind, lo)), gb = widenLibm(libmCompanion(kind, hi));
    if (ga.mig() > w || gb.mig() > w) return r;  // monotone
    addMax = !(fa.upper() < 0.0);
    addMin = !(fa.lower() > 0.0);
  } else {
    return unit;  // |x| > 2^30 and width >= 1: not worth a reduction of our own
  }
  return Interval::fromBoundsUnchecked(addMin ? -1.0 : r.lower(), addMax ? 1.0 : r.upper());
}

Interval pointEnclosure(double x, Kind kind) noexcept {
  if (!std::isfinite(x)) return x != x ? Interval::empty() : Interval::fromBoundsUnchecked(-1.0, 1.0);
  rounding::ScopedRoundToNearest rn;
  return widenLibm(libm(kind, x));
}

}  // namespace

namespace detail {

// glibc's double sin/cos reduce |x| < 105414350 (about 2^26.65) with a multi-part pi/2 and are within 0.52 ulp there
// (measured, docs/interval-arithmetic.md). Above, their reduction (__branred) has an absolute error up to about
// 2^-93, i.e. up to 1e5 ulps of results near 0 (measured at the doubles closest to multiples of pi/2). The long
// double sinl/cosl use a Payne-Hanek reduction with enough bits; their result rounded to double is within 0.5 ulp
// on the same hard cases (about 175 ns instead of 45 ns, only for |x| >= 2^26). Without an extended long double
// no trustworthy evaluation is available there: NaN, which widenLibm turns into [-1, 1].
constexpr double kLibmDoubleLimit = 0x1p26;
constexpr bool kExtendedLongDouble = std::numeric_limits<long double>::digits >= 64;

double libmSin(double x) noexcept {
  if (std::fabs(x) < kLibmDoubleLimit) return std::sin(x);
  if (!kExtendedLongDouble) return std::numeric_limits<double>::quiet_NaN();
  return static_cast<double>(std::sin(static_cast<long double>(x)));
}

double libmCos(double x) noexcept {
  if (std::fabs(x) < kLibmDoubleLimit) return std::cos(x);
  if (!kExtendedLongDouble) return std::numeric_limits<double>::quiet_NaN();
  return static_cast<double>(std::cos(static_cast<long double>(x)));
}

}  // namespace detail

Interval sin(const Interval& a) noexcept { return periodicEnclosure(a, Kind::kSin); }
Interval cos(const Interval& a) noexcept { return periodicEnclosure(a, Kind::kCos); }
Interval sinPoint(double x) noexcept { return pointEnclosure(x, Kind::kSin); }
Interval cosPoint(double x) noexcept { return pointEnclosure(x, Kind::kCos); }

}  // namespace interval
}  // namespace pkm_accuracy
