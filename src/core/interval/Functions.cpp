#include "pkm_accuracy/core/interval/Functions.hpp"

#include <cmath>

namespace pkm_accuracy {
namespace interval {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Interval widenLibm(double v) noexcept {
  double lo = v, hi = v;
  for (int i = 0; i < kLibmUlpBound; ++i) {
    lo = rounding::nextDown(lo);
    hi = rounding::nextUp(hi);
  }
  return Interval::fromBoundsUnchecked(std::max(lo, -1.0), std::min(hi, 1.0));
}

// Does [a, b] (possibly) contain a point phase + 2 k pi for an integer k? Errs on the side of "yes".
bool mayContainPeriodicPoint(double a, double b, long double phase) noexcept {
  constexpr long double kTwoPi = 6.283185307179586476925286766559005768L;
  const long double ka = std::floor((static_cast<long double>(a) - phase) / kTwoPi);
  for (long double k = ka - 1; k <= ka + 2; k += 1) {
    const long double c = phase + k * kTwoPi;
    // Error of c in long double is a few ulps of |c| (2^-63 relative each); 1e-15 relative is ample.
    const long double margin = 1e-15L * (1.0L + std::fabs(c));
    if (c >= static_cast<long double>(a) - margin && c <= static_cast<long double>(b) + margin) return true;
  }
  return false;
}

template <typename F>
Interval periodicEnclosure(const Interval& a, F f, long double maxPhase, long double minPhase) noexcept {
  if (a.isEmpty()) return a;
  if (!a.isBounded() || a.upper() - a.lower() >= 6.28) return Interval::fromBoundsUnchecked(-1.0, 1.0);
  Interval r;
  {
    rounding::ScopedRoundToNearest rn;
    r = hull(widenLibm(f(a.lower())), widenLibm(f(a.upper())));
  }
  double lo = r.lower(), hi = r.upper();
  if (mayContainPeriodicPoint(a.lower(), a.upper(), maxPhase)) hi = 1.0;
  if (mayContainPeriodicPoint(a.lower(), a.upper(), minPhase)) lo = -1.0;
  return Interval::fromBoundsUnchecked(lo, hi);
}

constexpr long double kHalfPi = 1.570796326794896619231321691639751442L;
constexpr long double kPi = 3.141592653589793238462643383279502884L;

}  // namespace

Interval sin(const Interval& a) noexcept {
  return periodicEnclosure(a, [](double x) { return std::sin(x); }, kHalfPi, -kHalfPi);
}

Interval cos(const Interval& a) noexcept {
  return periodicEnclosure(a, [](double x) { return std::cos(x); }, 0.0L, kPi);
}

Interval sinPoint(double x) noexcept {
  if (!std::isfinite(x)) return x != x ? Interval::empty() : Interval::fromBoundsUnchecked(-1.0, 1.0);
  rounding::ScopedRoundToNearest rn;
  return widenLibm(std::sin(x));
}

Interval cosPoint(double x) noexcept {
  if (!std::isfinite(x)) return x != x ? Interval::empty() : Interval::fromBoundsUnchecked(-1.0, 1.0);
  rounding::ScopedRoundToNearest rn;
  return widenLibm(std::cos(x));
}

}  // namespace interval
}  // namespace pkm_accuracy
