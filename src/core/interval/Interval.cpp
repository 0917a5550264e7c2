#include "pkm_accuracy/core/interval/Interval.hpp"

#include <ostream>
#include <sstream>

namespace pkm_accuracy {
namespace interval {

void Interval::throwInvalid(double lo, double hi) {
  std::ostringstream os;
  os.precision(17);
  os << "Interval(lo, hi): expected lo <= hi, neither NaN, lo != +inf and hi != -inf; got lo = " << lo
     << ", hi = " << hi;
  throw InvalidArgument(os.str());
}

Interval pow(const Interval& a, int n) noexcept {
  if (a.isEmpty()) return a;
  if (n == 0) return Interval(1.0);
  if (n < 0) {
    // n = INT_MIN cannot be negated; a^INT_MIN is 1 / a^(2^31), and 1/(a^(INT_MAX) * a) has the same set value.
    if (n == std::numeric_limits<int>::min()) return Interval(1.0) / (pow(a, std::numeric_limits<int>::max()) * a);
    return Interval(1.0) / pow(a, -n);
  }
  // Repeated squaring on the point intervals [mig, mig] (even) or the endpoints (odd, monotone).
  // k >= 1; the first factor is taken as is (no multiplication by 1, which would widen by one more ulp).
  auto powPoint = [](double x, int k) {
    // An infinite bound (+inf, or -inf for odd n) stays infinite; only the bound on that side is used.
    if (std::isinf(x)) return Interval::fromBoundsUnchecked(x, x);
    Interval r, b(x);
    bool first = true;
    for (;;) {
      if (k & 1) {
        r = first ? b : r * b;
        first = false;
      }
      k >>= 1;
      if (k == 0) return r;
      b = sqr(b);
    }
  };
  if (n % 2 == 0) {
    const Interval lo = powPoint(a.mig(), n), hi = powPoint(a.mag(), n);
    return Interval::fromBoundsUnchecked(std::max(0.0, lo.lower()), hi.upper());
  }
  const Interval lo = powPoint(a.lower(), n), hi = powPoint(a.upper(), n);
  return Interval::fromBoundsUnchecked(lo.lower(), hi.upper());
}

void checkFloatingPointEnvironment() {
  if (!rounding::subnormalsHonoured()) {
    throw Error(
        "floating-point environment: flush-to-zero (FTZ) is enabled; interval enclosures need IEEE 754 "
        "subnormal results");
  }
  if (!rounding::subnormalOperandsHonoured()) {
    throw Error(
        "floating-point environment: denormals-are-zero (DAZ) is enabled; interval enclosures need IEEE 754 "
        "subnormal operands");
  }
  if (!rounding::longDoublePrecisionHonoured()) {
    throw Error(
        "floating-point environment: the x87 precision control is below the long double precision; the "
        "sin/cos enclosures need full long double precision");
  }
}

std::ostream& operator<<(std::ostream& os, const Interval& a) {
  if (a.isEmpty()) return os << "[empty]";
  return os << '[' << a.lower() << ", " << a.upper() << ']';
}

}  // namespace interval
}  // namespace pkm_accuracy
