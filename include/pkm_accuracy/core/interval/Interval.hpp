// Closed real interval [lo, hi] of doubles with guaranteed outward rounding (policy: Rounding.hpp).
//
// Semantics (set-based, as in IEEE 1788 where it matters here):
//   * the empty set is a valid value (Interval::empty()); every operation on it returns it;
//   * unbounded intervals are allowed: [-inf, x], [x, +inf], Interval::entire(); endpoints are never NaN except in
//     the empty interval, and never lo = +inf or hi = -inf;
//   * 0 * inf inside a product of intervals counts as 0 (the product set of [0,1] and [1,inf] is [0,inf]);
//   * division by an interval that contains zero (including [0, 0], [-0, +0], [0, x], [x, 0] and entire()) returns
//     Interval::entire(), a valid, if loose, enclosure of the quotient set { x / y : x in a, y in b, y != 0 } (no
//     exception, no NaN, no division by zero is executed); an empty operand gives the empty interval. Division by
//     an interval that does not contain zero is tight to one ulp per bound;
//   * +inf and -inf are not real numbers: Interval(+inf) is [DBL_MAX, +inf] and Interval(-inf) is [-inf, -DBL_MAX]
//     (enclosures of a value that overflowed), never the invalid [inf, inf];
//   * every bound is rounded outward by at least one ulp (Rounding.hpp), so results of exact operations such as
//     [1, 1] + [2, 2] are [3 - ulp, 3 + ulp] rather than [3, 3]; abs, min, max, hull, intersect and unary minus are
//     exact;
//   * comparisons are explicit: certainlyLess(a, b) means every element of a is below every element of b (false if
//     either is empty).
// Nothing in this header changes the floating-point environment; see Rounding.hpp for the exact contract (control
// state untouched, flags never cleared, never raises FE_INVALID / FE_DIVBYZERO).
#pragma once

#include <algorithm>
#include <cmath>
#include <iosfwd>
#include <limits>
#include <utility>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/interval/Rounding.hpp"

namespace pkm_accuracy {
namespace interval {

class Interval {
 public:
  /// The degenerate interval [0, 0] (default-constructible for Eigen).
  constexpr Interval() noexcept : lo_(0.0), hi_(0.0) {}
  /// The degenerate interval [x, x]; exact. Implicit so that doubles mix with intervals in formulas.
  /// A NaN x gives the empty interval; +inf gives [DBL_MAX, +inf] and -inf gives [-inf, -DBL_MAX].
  constexpr Interval(double x) noexcept  // NOLINT(runtime/explicit)
      : lo_(x == kInf ? kMax : x), hi_(x == -kInf ? -kMax : x) {}
  /// [lo, hi]. @throws InvalidArgument if lo > hi, either is NaN, lo = +inf or hi = -inf.
  Interval(double lo, double hi) : lo_(lo), hi_(hi) {
    if (!(lo <= hi) || lo == kInf || hi == -kInf) throwInvalid(lo, hi);
  }

  static constexpr Interval empty() noexcept { return Interval(kNaN, kNaN, Unchecked{}); }
  static constexpr Interval entire() noexcept { return Interval(-kInf, kInf, Unchecked{}); }
  /// [lo, hi] without validation, for code that has already established lo <= hi (internal fast path).
  static constexpr Interval fromBoundsUnchecked(double lo, double hi) noexcept { return Interval(lo, hi, Unchecked{}); }
  /// Smallest interval containing both values (in any order; NaN gives empty).
  static Interval hullOf(double a, double b) noexcept {
    if (a != a || b != b) return empty();
    return a <= b ? Interval(a, b, Unchecked{}) : Interval(b, a, Unchecked{});
  }

  constexpr double lower() const noexcept { return lo_; }
  constexpr double upper() const noexcept { return hi_; }
  constexpr bool isEmpty() const noexcept { return lo_ != lo_; }
  constexpr bool isPoint() const noexcept { return lo_ == hi_; }
  // The predicates test isEmpty() (a quiet comparison) before any ordered comparison, so that they never raise
  // FE_INVALID on the NaN bounds of the empty interval.
  /// Not empty and both bounds finite.
  constexpr bool isBounded() const noexcept { return !isEmpty() && lo_ > -kInf && hi_ < kInf; }
  /// The real number x is an element (false for NaN and +-inf, which are not real numbers, and for the empty set).
  constexpr bool contains(double x) const noexcept {
    return !isEmpty() && x == x && x != kInf && x != -kInf && lo_ <= x && x <= hi_;
  }
  constexpr bool containsZero() const noexcept { return !isEmpty() && lo_ <= 0.0 && 0.0 <= hi_; }
  /// Every element of *this is in other (the empty set is a subset of everything).
  constexpr bool isSubsetOf(const Interval& o) const noexcept {
    return isEmpty() || (!o.isEmpty() && o.lo_ <= lo_ && hi_ <= o.hi_);
  }
  /// Same set.
  constexpr bool operator==(const Interval& o) const noexcept {
    return (isEmpty() && o.isEmpty()) || (lo_ == o.lo_ && hi_ == o.hi_);
  }
  constexpr bool operator!=(const Interval& o) const noexcept { return !(*this == o); }

  /// A point of the interval, close to its centre (0 for entire, +-DBL_MAX for half-unbounded; NaN if empty).
  double mid() const noexcept {
    if (isEmpty()) return kNaN;
    if (lo_ == -kInf) return hi_ == kInf ? 0.0 : -std::numeric_limits<double>::max();
    if (hi_ == kInf) return std::numeric_limits<double>::max();
    const double m = 0.5 * lo_ + 0.5 * hi_;
    return std::min(std::max(m, lo_), hi_);
  }
  /// Upper bound of the width hi - lo (+inf if unbounded, NaN if empty).
  double width() const noexcept { return isEmpty() ? kNaN : rounding::subUp(hi_, lo_); }
  /// Upper bound of the radius (half-width).
  double rad() const noexcept { return isEmpty() ? kNaN : rounding::nextUp(0.5 * rounding::subUp(hi_, lo_)); }
  /// Magnitude max |x| (exact).
  double mag() const noexcept { return isEmpty() ? kNaN : std::max(-lo_, hi_); }
  /// Mignitude min |x| (exact).
  double mig() const noexcept {
    if (isEmpty()) return kNaN;
    if (lo_ > 0.0) return lo_;
    if (hi_ < 0.0) return -hi_;
    return 0.0;
  }
  /// Splits at the midpoint into two halves that share it. Precondition: not empty.
  std::pair<Interval, Interval> bisect() const noexcept { return bisectAt(mid()); }
  /// Splits at x (clamped into the interval; a NaN x splits at mid()). Precondition: not empty.
  std::pair<Interval, Interval> bisectAt(double x) const noexcept {
    const double m = x != x ? mid() : std::min(std::max(x, lo_), hi_);
    return {Interval(lo_, m, Unchecked{}), Interval(m, hi_, Unchecked{})};
  }

  Interval& operator+=(const Interval& o) noexcept { return *this = *this + o; }
  Interval& operator-=(const Interval& o) noexcept { return *this = *this - o; }
  Interval& operator*=(const Interval& o) noexcept { return *this = *this * o; }
  Interval& operator/=(const Interval& o) noexcept { return *this = *this / o; }
  Interval& operator*=(double s) noexcept { return *this = *this * s; }
  Interval& operator/=(double s) noexcept { return *this = *this / s; }

  friend Interval operator+(const Interval& a) noexcept { return a; }
  friend Interval operator-(const Interval& a) noexcept { return Interval(-a.hi_, -a.lo_, Unchecked{}); }

  // Sums: lo + lo and hi + hi never meet inf - inf (lo is never +inf, hi never -inf), so only the empty interval
  // needs a test (without it, NaN bounds would leak out as a NaN-bounded non-empty value).
  friend Interval operator+(const Interval& a, const Interval& b) noexcept {
    if (a.isEmpty() || b.isEmpty()) return empty();
    return Interval(rounding::addDown(a.lo_, b.lo_), rounding::addUp(a.hi_, b.hi_), Unchecked{});
  }
  friend Interval operator-(const Interval& a, const Interval& b) noexcept {
    if (a.isEmpty() || b.isEmpty()) return empty();
    return Interval(rounding::subDown(a.lo_, b.hi_), rounding::subUp(a.hi_, b.lo_), Unchecked{});
  }
  friend Interval operator*(const Interval& a, const Interval& b) noexcept {
    // Fast path for bounded operands (std::isfinite is a quiet test: false for NaN, i.e. the empty interval).
    if (!(std::isfinite(a.lo_) && std::isfinite(a.hi_) && std::isfinite(b.lo_) && std::isfinite(b.hi_))) {
      return multiplySlow(a, b);  // empty operand or an infinite bound (0 * inf must count as 0)
    }
    const double p1 = a.lo_ * b.lo_, p2 = a.lo_ * b.hi_, p3 = a.hi_ * b.lo_, p4 = a.hi_ * b.hi_;
    return Interval(rounding::nextDown(std::min(std::min(p1, p2), std::min(p3, p4))),
                    rounding::nextUp(std::max(std::max(p1, p2), std::max(p3, p4))), Unchecked{});
  }
  // Mixed with a double (e.g. a point preconditioner times an interval matrix): two products instead of four; the
  // results are bit-identical to a * Interval(s) and a / Interval(s).
  friend Interval operator*(const Interval& a, double s) noexcept {
    if (!(std::isfinite(a.lo_) && std::isfinite(a.hi_) && std::isfinite(s))) return a * Interval(s);
    const double p = a.lo_ * s, q = a.hi_ * s;
    return s >= 0.0 ? Interval(rounding::nextDown(p), rounding::nextUp(q), Unchecked{})
                    : Interval(rounding::nextDown(q), rounding::nextUp(p), Unchecked{});
  }
  friend Interval operator*(double s, const Interval& a) noexcept { return a * s; }
  friend Interval operator/(const Interval& a, double s) noexcept {
    if (!(std::isfinite(a.lo_) && std::isfinite(a.hi_) && std::isfinite(s)) || s == 0.0) return a / Interval(s);
    const double p = a.lo_ / s, q = a.hi_ / s;
    return s > 0.0 ? Interval(rounding::nextDown(p), rounding::nextUp(q), Unchecked{})
                   : Interval(rounding::nextDown(q), rounding::nextUp(p), Unchecked{});
  }
  friend Interval operator/(const Interval& a, const Interval& b) noexcept {
    if (a.isEmpty() || b.isEmpty()) return empty();
    if (b.containsZero()) return entire();
    // b is strictly positive or strictly negative: a / b = a * (1/b) as sets; use the endpoint quotients.
    double lo, hi;
    if (b.lo_ > 0.0) {
      lo = a.lo_ >= 0.0 ? quot(a.lo_, b.hi_) : quot(a.lo_, b.lo_);
      hi = a.hi_ >= 0.0 ? quot(a.hi_, b.lo_) : quot(a.hi_, b.hi_);
    } else {
      lo = a.hi_ >= 0.0 ? quot(a.hi_, b.hi_) : quot(a.hi_, b.lo_);
      hi = a.lo_ >= 0.0 ? quot(a.lo_, b.lo_) : quot(a.lo_, b.hi_);
    }
    return Interval(rounding::nextDown(lo), rounding::nextUp(hi), Unchecked{}).normalized();
  }

 private:
  struct Unchecked {};
  constexpr Interval(double lo, double hi, Unchecked) noexcept : lo_(lo), hi_(hi) {}
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  static constexpr double kMax = std::numeric_limits<double>::max();
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

  [[noreturn]] static void throwInvalid(double lo, double hi);

  // Safety net for the quotient bounds: quot() never returns NaN for non-empty operands and a divisor without zero,
  // but should a NaN bound ever appear, the corresponding infinity is a valid bound.
  Interval normalized() const noexcept {
    if (lo_ != lo_ || hi_ != hi_) return Interval(lo_ != lo_ ? -kInf : lo_, hi_ != hi_ ? kInf : hi_, Unchecked{});
    return *this;
  }
  // Endpoint quotient with inf / inf treated by sign only (the exact set bound is then 0 or inf, covered by the
  // caller's outward step and normalization).
  static double quot(double x, double y) noexcept {
    const double q = x / y;
    if (q != q) return (x > 0) == (y > 0) ? kInf : -kInf;  // inf / inf: the supremum of such quotients
    return q;
  }
  static double prod(double x, double y) noexcept { return (x == 0.0 || y == 0.0) ? 0.0 : x * y; }
  static Interval multiplySlow(const Interval& a, const Interval& b) noexcept {
    if (a.isEmpty() || b.isEmpty()) return empty();
    const double p1 = prod(a.lo_, b.lo_), p2 = prod(a.lo_, b.hi_), p3 = prod(a.hi_, b.lo_), p4 = prod(a.hi_, b.hi_);
    return Interval(rounding::nextDown(std::min(std::min(p1, p2), std::min(p3, p4))),
                    rounding::nextUp(std::max(std::max(p1, p2), std::max(p3, p4))), Unchecked{});
  }

  double lo_;
  double hi_;
};

// ---- set operations -------------------------------------------------------------------------------------------
inline Interval hull(const Interval& a, const Interval& b) noexcept {
  if (a.isEmpty()) return b;
  if (b.isEmpty()) return a;
  return Interval::fromBoundsUnchecked(std::min(a.lower(), b.lower()), std::max(a.upper(), b.upper()));
}
inline Interval intersect(const Interval& a, const Interval& b) noexcept {
  if (a.isEmpty() || b.isEmpty()) return Interval::empty();
  const double lo = std::max(a.lower(), b.lower()), hi = std::min(a.upper(), b.upper());
  return lo <= hi ? Interval::fromBoundsUnchecked(lo, hi) : Interval::empty();
}

/// The smallest radius about m (rounded up) that covers x: x lies in [m - r, m + r] for r = radiusAbout(x, m).
inline double radiusAbout(const Interval& x, double m) noexcept {
  return std::max(rounding::subUp(m, x.lower()), rounding::subUp(x.upper(), m));
}

// ---- certain / possible comparisons ----------------------------------------------------------------------------
// All false when an operand is empty (conservative: nothing is certified about an empty enclosure).
inline bool certainlyLess(const Interval& a, const Interval& b) noexcept {
  return !a.isEmpty() && !b.isEmpty() && a.upper() < b.lower();
}
inline bool certainlyLessEqual(const Interval& a, const Interval& b) noexcept {
  return !a.isEmpty() && !b.isEmpty() && a.upper() <= b.lower();
}
inline bool certainlyPositive(const Interval& a) noexcept { return !a.isEmpty() && a.lower() > 0.0; }
inline bool certainlyNegative(const Interval& a) noexcept { return !a.isEmpty() && a.upper() < 0.0; }

// ---- elementary functions (exact or one-ulp outward) -----------------------------------------------------------
inline double mid(const Interval& a) noexcept { return a.mid(); }
inline double rad(const Interval& a) noexcept { return a.rad(); }
inline double mag(const Interval& a) noexcept { return a.mag(); }
inline double mig(const Interval& a) noexcept { return a.mig(); }

inline Interval abs(const Interval& a) noexcept {
  if (a.isEmpty()) return a;
  return Interval::fromBoundsUnchecked(a.mig(), a.mag());
}

/// A linear upper bound of |x| e over x in a (e >= 0 finite): |x| e <= weight x + offset for every x in a, exactly
/// (not only up to rounding). `weight` (in [-e, e]) is the secant slope of |x| e over a, rounded to nearest; `offset`
/// is the largest value of the convex |x| e - weight x over a, at one of its ends, rounded up. So for a of one sign
/// weight = +-e and offset = 0 (exactly: |x| e = +-e x there), and for a = [-r, r] weight = 0 and offset = r e (the
/// magnitude); in between, offset is below mag(a) e (up to the rounding). Unbounded or empty a: weight 0, offset
/// mag(a) e.
struct AbsSecant {
  double weight;
  double offset;
};
inline AbsSecant absSecant(const Interval& a, double e) noexcept {
  if (!a.isBounded()) return {0.0, a.isEmpty() ? a.lower() : rounding::mulUp(a.mag(), e)};
  const double lo = a.lower(), hi = a.upper();
  if (lo >= 0.0) return {e, 0.0};
  if (hi <= 0.0) return {-e, 0.0};
  const double slope = hi > lo ? std::max(-1.0, std::min(1.0, (hi + lo) / (hi - lo))) : (lo >= 0.0 ? 1.0 : -1.0);
  const double weight = slope * e;  // |weight| <= e: rounding is monotone
  const double atLo = (Interval(std::abs(lo)) * e - Interval(weight) * lo).upper();
  const double atHi = (Interval(std::abs(hi)) * e - Interval(weight) * hi).upper();
  return {weight, std::max(0.0, std::max(atLo, atHi))};
}

/// x^2 (tighter than x * x: [-1, 2]^2 = [0, 4]).
inline Interval sqr(const Interval& a) noexcept {
  if (a.isEmpty()) return a;
  const double lo = a.mig(), hi = a.mag();
  return Interval::fromBoundsUnchecked(lo == 0.0 ? 0.0 : std::max(0.0, rounding::nextDown(lo * lo)),
                                       rounding::nextUp(hi * hi));
}

/// sqrt over the part of a that is >= 0 (empty if a < 0 entirely).
inline Interval sqrt(const Interval& a) noexcept {
  const Interval d = intersect(a, Interval::fromBoundsUnchecked(0.0, std::numeric_limits<double>::infinity()));
  if (d.isEmpty()) return d;
  return Interval::fromBoundsUnchecked(rounding::sqrtDown(d.lower()), rounding::sqrtUp(d.upper()));
}

/// Integer power; n < 0 is 1 / a^-n (entire if a contains 0).
Interval pow(const Interval& a, int n) noexcept;

/// min / max of two intervals (elementwise, tight).
inline Interval min(const Interval& a, const Interval& b) noexcept {
  if (a.isEmpty() || b.isEmpty()) return Interval::empty();
  return Interval::fromBoundsUnchecked(std::min(a.lower(), b.lower()), std::min(a.upper(), b.upper()));
}
inline Interval max(const Interval& a, const Interval& b) noexcept {
  if (a.isEmpty() || b.isEmpty()) return Interval::empty();
  return Interval::fromBoundsUnchecked(std::max(a.lower(), b.lower()), std::max(a.upper(), b.upper()));
}

/// Fused a * b + c as an interval (no gain over separate operations; provided for generic code).
inline Interval fma(const Interval& a, const Interval& b, const Interval& c) noexcept { return a * b + c; }

std::ostream& operator<<(std::ostream& os, const Interval& a);

// ---- floating-point environment -----------------------------------------------------------------------------------
/// True when the calling thread's floating-point unit honours IEEE 754 subnormals (neither flush-to-zero nor
/// denormals-are-zero is set) and long double runs at full precision, which the rounding policy of Rounding.hpp and
/// the sin/cos enclosures need. The rounding mode does not matter.
inline bool floatingPointEnvironmentSupported() noexcept {
  return rounding::subnormalsHonoured() && rounding::subnormalOperandsHonoured() &&
         rounding::longDoublePrecisionHonoured();
}
/// @throws Error naming the problem if floatingPointEnvironmentSupported() is false (call it once per thread that
/// runs interval code when foreign code may have enabled FTZ/DAZ, e.g. at the start of a TBB task arena).
void checkFloatingPointEnvironment();

}  // namespace interval
}  // namespace pkm_accuracy
