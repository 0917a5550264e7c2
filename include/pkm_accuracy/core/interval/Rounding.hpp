// The one and only rounding policy of pkm_accuracy (and the only header that touches the FPU rounding mode).
//
// Policy "round in any mode, then step one ulp outward":
//   every elementary floating-point result r = fl(a op b) (+, -, *, /, sqrt: IEEE 754 correctly rounded in the
//   current mode) lies within one ulp of the exact value, on one side or the other, whatever the rounding mode.
//   So [nextDown(r), nextUp(r)] always contains the exact value. Interval operations use exactly that.
// Consequences:
//   * the core never changes the caller's rounding mode for arithmetic; it is correct under any of the four IEEE
//     modes and with any thread (TBB workers need no set-up);
//   * enclosures are at most 2 ulps wider per operation than with directed rounding, which is negligible against
//     the overestimation of interval methods;
//   * flush-to-zero / denormals-are-zero modes (MXCSR FTZ/DAZ) break IEEE semantics and are not supported
//     (checkFloatingPointEnvironment() reports them).
// Library functions that are not correctly rounded (sin, cos, atan2 from libm) are evaluated in round-to-nearest
// under a ScopedRoundToNearest guard and widened by a proven error bound (see Functions.hpp).
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

/// Smallest double strictly greater than x (mode-independent). NaN and +inf are returned unchanged;
/// -inf maps to -DBL_MAX (an upper bound of anything that overflowed to -inf).
inline double nextUp(double x) noexcept {
  if (!(x < std::numeric_limits<double>::infinity())) return x;  // +inf or NaN
  if (x == 0.0) return std::numeric_limits<double>::denorm_min();
  const std::int64_t b = bitsOf(x);
  return fromBits(b >= 0 ? b + 1 : b - 1);
}

/// Largest double strictly smaller than x (mode-independent). NaN and -inf unchanged; +inf maps to DBL_MAX.
inline double nextDown(double x) noexcept { return -nextUp(-x); }

/// Lower / upper bounds of the exact results of the correctly rounded IEEE operations.
inline double addDown(double a, double b) noexcept { return nextDown(a + b); }
inline double addUp(double a, double b) noexcept { return nextUp(a + b); }
inline double subDown(double a, double b) noexcept { return nextDown(a - b); }
inline double subUp(double a, double b) noexcept { return nextUp(a - b); }
inline double sqrtDown(double a) noexcept { return a <= 0.0 ? 0.0 : nextDown(std::sqrt(a)); }
inline double sqrtUp(double a) noexcept { return a <= 0.0 ? 0.0 : nextUp(std::sqrt(a)); }

/// RAII: saves the complete floating-point environment (rounding mode and exception flags), switches to
/// round-to-nearest, and restores the saved environment on destruction. Used around libm calls whose error
/// bounds are documented for round-to-nearest only.
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

/// True when the floating-point unit honours IEEE 754 subnormals (no flush-to-zero), which the policy needs.
inline bool subnormalsHonoured() noexcept {
  volatile double tiny = std::numeric_limits<double>::min();
  volatile double half = 0.5;
  const double r = tiny * half;
  return r != 0.0;
}

}  // namespace rounding
}  // namespace interval
}  // namespace pkm_accuracy
