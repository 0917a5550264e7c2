// The one and only rounding policy of pkm_accuracy (and the only header that touches the FPU rounding mode).
//
// Policy "round in any mode, then step one ulp outward":
//   every elementary floating-point result r = fl(a op b) (+, -, *, /, sqrt: IEEE 754 correctly rounded in the
//   current mode) is one of the two doubles that bracket the exact value (or the exact value itself), whatever the
//   rounding mode. So [nextDown(r), nextUp(r)] always contains the exact value. Interval operations use exactly that.
//   This includes overflow (r = +-inf or +-DBL_MAX, and nextDown(+inf) = DBL_MAX) and gradual underflow (subnormal
//   results are still correctly rounded, and nextUp(0) = the smallest subnormal).
// Consequences:
//   * the core never changes the caller's rounding mode for arithmetic; it is correct under any of the four IEEE
//     modes and with any thread (TBB workers need no set-up);
//   * enclosures are at most 2 ulps wider per operation than with directed rounding, which is negligible against
//     the overestimation of interval methods;
//   * the compiler may fold or schedule arithmetic as if round-to-nearest were in force (no -frounding-math is
//     needed): a result computed in any mode, at compile time or at run time, is still a neighbour of the exact value;
//   * flush-to-zero / denormals-are-zero modes (MXCSR FTZ/DAZ) break IEEE semantics and are not supported, nor is a
//     lowered x87 precision control (floatingPointEnvironmentSupported() / checkFloatingPointEnvironment() in
//     Interval.hpp report them).
// Library functions that are not correctly rounded (sin, cos, asin, atan2 from libm) are evaluated in round-to-nearest
// under a ScopedRoundToNearest guard and widened by widenByUlps with an ulp bound checked against MPFR (see
// Functions.hpp, InverseTrig.hpp and docs/soundness.md).
//
// Floating-point environment contract of every public interval function: the control state (rounding direction,
// exception enables, x87 precision control, FTZ/DAZ bits) is left bit-for-bit unchanged, and exception flags that
// were raised before the call stay raised. A call may newly raise FE_INEXACT, FE_OVERFLOW or FE_UNDERFLOW, exactly
// as the double arithmetic on the endpoints does; it never raises FE_INVALID or FE_DIVBYZERO (empty and unbounded
// operands are handled with quiet comparisons and without 0 * inf, inf - inf or x / 0).
#pragma once

#include <cfenv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace pkm_accuracy {
namespace interval {
namespace rounding {

inline std::int64_t bitsOf(double x) noexcept {
  std::int64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

inline double fromBits(std::int64_t b) noexcept {
  double x;
  std::memcpy(&x, &b, sizeof x);
  return x;
}

/// Smallest double strictly greater than x (mode-independent, raises no floating-point exception). NaN and +inf are
/// returned unchanged; -inf maps to -DBL_MAX (an upper bound of anything that overflowed to -inf).
inline double nextUp(double x) noexcept {
  if (!std::isless(x, std::numeric_limits<double>::infinity())) return x;  // +inf or NaN (quiet comparison)
  if (x == 0.0) return std::numeric_limits<double>::denorm_min();
  const std::int64_t b = bitsOf(x);
  return fromBits(b >= 0 ? b + 1 : b - 1);
}

/// Largest double strictly smaller than x (mode-independent). NaN and -inf unchanged; +inf maps to DBL_MAX.
inline double nextDown(double x) noexcept { return -nextUp(-x); }

/// Lower / upper bounds of the exact results of the correctly rounded IEEE operations (any rounding mode).
inline double addDown(double a, double b) noexcept { return nextDown(a + b); }
inline double addUp(double a, double b) noexcept { return nextUp(a + b); }
inline double subDown(double a, double b) noexcept { return nextDown(a - b); }
inline double subUp(double a, double b) noexcept { return nextUp(a - b); }
inline double mulDown(double a, double b) noexcept { return nextDown(a * b); }
inline double mulUp(double a, double b) noexcept { return nextUp(a * b); }
inline double divDown(double a, double b) noexcept { return nextDown(a / b); }
inline double divUp(double a, double b) noexcept { return nextUp(a / b); }
inline double sqrtDown(double a) noexcept { return a <= 0.0 ? 0.0 : nextDown(std::sqrt(a)); }
inline double sqrtUp(double a) noexcept { return a <= 0.0 ? 0.0 : nextUp(std::sqrt(a)); }

// ---- A priori error bounds: the constants and helpers every midpoint-radius and affine computation uses ----------
//
// Any IEEE rounding mode: a correctly rounded operation (+, -, *, /, sqrt, fma) whose exact result x is in the normal
// range returns fl(x) with |fl(x) - x| < ulp(x) <= 2^-52 |x| (directed modes; round-to-nearest halves it), and a result
// in the subnormal range is off by less than 2^-1074 (absolute). So u = 2^-52 below, never 2^-53.

/// The unit roundoff of one operation in every rounding mode (relative, normal range).
constexpr double kUnitRoundoff = 0x1p-52;

/// gamma(n) >= gamma_n = n u / (1 - n u) (Higham, "Accuracy and Stability of Numerical Algorithms", lemma 3.1, which
/// holds for any mode with u = 2^-52): a sum of n terms, or a dot product of n products, evaluated in floating point in
/// any order differs from the exact one by at most gamma_n times the sum of the magnitudes of its terms (plus n 2^-1074
/// for underflow, which the floor of up() covers). 1.01 n u >= gamma_n for n u <= 0.0099; the constant expression is
/// evaluated in round-to-nearest at compile time, and 1.01 leaves room for its own rounding.
constexpr double gamma(int n) { return 1.01 * n * kUnitRoundoff; }

/// The relative margin and the absolute floor of up(). kUpRelative covers the rounding of a non-negative expression of
/// at most kUpOperations operations (gamma(4000) < 9e-13) plus the two operations of up() itself (2u); kUpFloor covers
/// the absolute underflow errors of those operations (4002 * 2^-1074 < 1e-320 < 1e-300).
constexpr int kUpOperations = 4000;
constexpr double kUpRelative = 1e-12;
constexpr double kUpFloor = 1e-300;
static_assert(gamma(kUpOperations) + 2.0 * kUnitRoundoff < kUpRelative, "up()'s margin must cover its operations");

/// An upper bound of the exact value of a non-negative quantity whose value computed in floating point (in any order,
/// any rounding mode, at most kUpOperations operations on non-negative terms or terms whose rounding the caller's
/// margin covers) is x. Overflow and NaN give +inf: an overflow to +-DBL_MAX (round-down, toward zero) is no bound, and
/// callers test finiteness to detect unbounded results.
inline double up(double x) noexcept {
  const double r = x * (1.0 + kUpRelative) + kUpFloor;
  return r < std::numeric_limits<double>::max() ? r : std::numeric_limits<double>::infinity();
}

/// up() of every entry of an Eigen matrix, as one array expression (the same operations per entry, so it vectorises).
template <typename Matrix>
Matrix upEach(const Matrix& m) {
  const auto r = (m.array() * (1.0 + kUpRelative) + kUpFloor).eval();
  return (r < std::numeric_limits<double>::max()).select(r, std::numeric_limits<double>::infinity()).matrix();
}

// ---- Widening of a result known to within k ulps ------------------------------------------------------------------
//
// ulp(y) of a real y is 2^(max(E, -1022) - 52) with E = floor(log2 |y|), and ulp(0) = 2^-1074: the spacing of the
// doubles at |y|, at a power of two the spacing above it. A value v "within k ulps" of y means |v - y| <= k ulp(y),
// the ulp taken at the exact value y; this is how the MPFR tests measure the libm errors. The ulp of y may be twice
// that of v: for v just below a power of two P (in magnitude) and y at or above P. So k steps from v to the
// neighbouring doubles do not always reach every such y: v = 1 - 4 * 2^-53 and y = 1 are 2 ulp(y) apart, while the
// second double above v is 1 - 2^-52.

/// Ulp class of a double: doubles of the same class have the same ulp (the biased exponent of |x|, with the
/// subnormals and zeros merged into the first normal binade; +-inf and NaN have a class of their own).
inline int ulpClass(double x) noexcept {
  const int e = static_cast<int>((bitsOf(x) >> 52) & 0x7ff);
  return e == 0 ? 1 : e;
}

/// A pair of doubles lower <= upper.
struct Bounds {
  double lower;
  double upper;
};

/// Bounds of every real y with |y - v| <= k ulp(y) (ulp as above), for a finite double v and 0 <= k < 2^51 (NaN
/// gives NaN bounds). With a = |v|, D(n) the n-th double below a (through zero into the negatives) and U(n) the n-th
/// double above a, the bounds for v >= +0 are [D(k), U(k)] when U(2k) has the ulp class of a and [D(k), U(2k)]
/// otherwise; for v <= -0 they are the mirror image. So the result is k ulps on each side, except within 2k ulps
/// below a power of two, where the side away from zero takes 2k steps. Cost: 4k nextUp / nextDown.
///
/// Proof (v >= +0; v <= -0 by symmetry, since ulp(-y) = ulp(y)). Two facts about the doubles: (G) consecutive doubles
/// p < q are ulp(min(|p|, |q|)) apart, in particular ulp(p) apart when p >= 0; (W) walking from a over consecutive
/// doubles towards y, if every step taken while y is not yet reached is at least g long, then n steps reach or pass
/// y once n g >= |a - y|. Let y satisfy |y - a| <= k ulp(y).
///   * 0 <= y <= a: every step p < q taken has q > y and p >= 0, so by (G) its length ulp(p) is >= ulp(y) when
///     p >= y, and equals ulp(y) when p < y < q (then y and p lie in one ulp class). By (W), g = ulp(y): D(k) <= y.
///   * y < 0 <= a: then |y| <= |y - a| <= k ulp(y). A normal y has ulp(y) <= 2^-52 |y|, which would need k >= 2^52;
///     so |y| < 2^-1022, ulp(y) = 2^-1074 and a <= k 2^-1074. All doubles of [y, a] lie on the grid 2^-1074 Z,
///     consecutive ones 2^-1074 apart (nextDown(+0) = -2^-1074): by (W) with g = ulp(y), D(k) <= y.
///   * y > a: every step p < q taken has p >= a, of length ulp(p) >= ulp(a). Moreover ulp(y) <= 2 ulp(a): a larger
///     ulp(y) needs y >= 2^(e+2) where a < 2^(e+1) (e = max(floor(log2 a), -1022)), so y - a > y / 2 >= 2^51 ulp(y),
///     i.e. k > 2^51. By (W) with g = ulp(a) and |y - a| <= k ulp(y) <= 2k ulp(a): U(2k) >= y. If U(2k) has the
///     ulp class of a, every real of [a, U(2k)] has ulp(a) as its ulp, so y does, the steps from a up to y are ulp(a)
///     long, and (W) with g = ulp(a), |y - a| <= k ulp(a) gives U(k) >= y.
/// The bounds of the set of such y are nondecreasing in v, but for k >= 2 the returned ones are not (U(2k) just below
/// a power of two exceeds U(k) at it), so callers widen every value they use, not only an extreme one.
inline Bounds widenByUlps(double v, int k) noexcept {
  const double a = std::fabs(v);
  double toward = a, away = a;
  for (int i = 0; i < k; ++i) {
    toward = nextDown(toward);
    away = nextUp(away);
  }
  double far = away;
  for (int i = 0; i < k; ++i) far = nextUp(far);
  if (ulpClass(far) != ulpClass(a)) away = far;
  if (std::signbit(v)) return {-away, -toward};
  return {toward, away};
}

/// RAII: saves the complete floating-point environment (rounding mode and exception flags), switches to
/// round-to-nearest, and restores the saved environment on destruction. Used around libm calls whose error
/// bounds are documented for round-to-nearest only. When the mode already is round-to-nearest nothing is saved or
/// changed (the guarded code may then raise FE_INEXACT / FE_UNDERFLOW like any arithmetic); otherwise the caller's
/// environment, flags included, is restored bit for bit.
class ScopedRoundToNearest {
 public:
  ScopedRoundToNearest() noexcept : changed_(std::fegetround() != FE_TONEAREST) {
    if (changed_) {
      std::fegetenv(&saved_);
      std::fesetround(FE_TONEAREST);
    }
  }
  ~ScopedRoundToNearest() {
    if (changed_) std::fesetenv(&saved_);
  }
  ScopedRoundToNearest(const ScopedRoundToNearest&) = delete;
  ScopedRoundToNearest& operator=(const ScopedRoundToNearest&) = delete;

 private:
  bool changed_;
  std::fenv_t saved_{};
};

/// True when the floating-point unit produces IEEE 754 subnormal results (no flush-to-zero), which the policy needs.
inline bool subnormalsHonoured() noexcept {
  volatile double tiny = std::numeric_limits<double>::min();
  volatile double half = 0.5;
  const double r = tiny * half;
  return r != 0.0;
}

/// True when subnormal operands are used as such (no denormals-are-zero), which the policy needs.
inline bool subnormalOperandsHonoured() noexcept {
  volatile double sub = std::numeric_limits<double>::denorm_min();
  volatile double big = 0x1p60;
  const double r = sub * big;
  return r != 0.0;
}

/// True when long double arithmetic runs at its full precision (an x87 precision control lowered to 53 bits would
/// break the long-double reduction margins and sinl/cosl used for huge arguments, see Functions.cpp).
inline bool longDoublePrecisionHonoured() noexcept {
  volatile long double one = 1.0L;
  volatile long double eps = std::numeric_limits<long double>::epsilon();
  const long double r = (one + eps) - one;
  return r == eps;
}

}  // namespace rounding
}  // namespace interval
}  // namespace pkm_accuracy
