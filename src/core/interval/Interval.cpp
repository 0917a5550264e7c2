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
  auto powPoint = [](double x, int k) {
    Interval r(1.0), b(x);
    while (k > 0) {
      if (k & 1) r = r * b;
      k >>= 1;
      if (k > 0) b = sqr(b);
    }
    return r;
  };
  if (n % 2 == 0) {
    const Interval lo = powPoint(a.mig(), n), hi = powPoint(a.mag(), n);
    return Interval::fromBoundsUnchecked(std::max(0.0, lo.lower()), hi.upper());
  }
  const Interval lo = powPoint(a.lower(), n), hi = powPoint(a.upper(), n);
  return Interval::fromBoundsUnchecked(lo.lower(), hi.upper());
}

std::ostream& operator<<(std::ostream& os, const Interval& a) {
  if (a.isEmpty()) return os << "[empty]";
  return os << '[' << a.lower() << ", " << a.upper() << ']';
}

}  // namespace interval
}  // namespace pkm_accuracy
