// The floating-point environment contract of the interval core (Rounding.hpp):
//   * the control state (rounding direction, exception masks, x87 control word, MXCSR control bits) is bit-for-bit
//     unchanged by every public call, under each of the four rounding modes;
//   * exception flags raised before a call stay raised; a call never raises FE_INVALID or FE_DIVBYZERO, whatever the
//     operands (empty, unbounded, zero divisors); operations whose endpoint arithmetic is exact raise no flag at all;
//   * sin / cos under a non-nearest mode restore the caller's environment including the flags exactly;
//   * FTZ / DAZ and a lowered x87 precision are detected (unsupported);
//   * results stay correct under every mode (checked exhaustively in IntervalMpfrTest / FunctionsMpfrTest; here on
//     a few known values) and on threads whose mode was never set up.
#include <gtest/gtest.h>

#include <cfenv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#if defined(__x86_64__) || defined(__i386__)
#include <xmmintrin.h>
#if defined(__GLIBC__)
#include <fpu_control.h>
#endif
#endif

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/interval/Dual.hpp"
#include "pkm_accuracy/core/interval/Eigen.hpp"
#include "pkm_accuracy/core/interval/Functions.hpp"
#include "pkm_accuracy/core/interval/Interval.hpp"

namespace {

using pkm_accuracy::interval::Interval;
namespace iv = pkm_accuracy::interval;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMax = std::numeric_limits<double>::max();
constexpr int kModes[4] = {FE_TONEAREST, FE_UPWARD, FE_DOWNWARD, FE_TOWARDZERO};
constexpr const char* kModeNames[4] = {"to-nearest", "upward", "downward", "toward-zero"};
constexpr int kPresets[5] = {0, FE_INEXACT, FE_INVALID | FE_DIVBYZERO, FE_OVERFLOW | FE_UNDERFLOW, FE_ALL_EXCEPT};
constexpr int kAllowedNewFlags = FE_INEXACT | FE_OVERFLOW | FE_UNDERFLOW;

// The control part of the environment (everything but the sticky status flags and x87 bookkeeping).
struct Control {
  int round = 0;
#if defined(__x86_64__) && defined(__GLIBC__)
  unsigned short x87ControlWord = 0;  // NOLINT(runtime/int)
  unsigned int mxcsrControl = 0;
#endif
  bool operator==(const Control& o) const {
#if defined(__x86_64__) && defined(__GLIBC__)
    return round == o.round && x87ControlWord == o.x87ControlWord && mxcsrControl == o.mxcsrControl;
#else
    return round == o.round;
#endif
  }
  std::string str() const {
    std::string s = "round " + std::to_string(round);
#if defined(__x86_64__) && defined(__GLIBC__)
    s += " x87cw " + std::to_string(x87ControlWord) + " mxcsr " + std::to_string(mxcsrControl);
#endif
    return s;
  }
};

Control control() {
  Control c;
  c.round = std::fegetround();
  std::fenv_t env;
  std::fegetenv(&env);
#if defined(__x86_64__) && defined(__GLIBC__)
  c.x87ControlWord = env.__control_word;
  c.mxcsrControl = env.__mxcsr & ~0x3Fu;  // bits 0-5 are the sticky flags
#endif
  return c;
}

// A battery of calls on volatile operands (the compiler cannot evaluate them at compile time). Returns a checksum
// so that nothing is optimised away.
std::int64_t bits(double x) { return iv::rounding::bitsOf(x); }

// The checksum mixes the bits of the results with integer arithmetic only (a floating-point sum of the bounds would
// itself raise flags).
std::int64_t battery(const std::vector<Interval>& xs) {
  std::int64_t sum = 0;
  auto use = [&sum](const Interval& r) { sum = sum * 31 + (bits(r.lower()) ^ bits(r.upper())); };
  for (const Interval& a : xs) {
    for (const Interval& b : xs) {
      use(a + b);
      use(a - b);
      use(a * b);
      use(a / b);
      Interval c = a;
      c += b;
      c -= b;
      c *= b;
      c /= b;
      use(c);
      use(iv::hull(a, b));
      use(iv::intersect(a, b));
      use(iv::min(a, b));
      use(iv::max(a, b));
      sum += iv::certainlyLess(a, b) + iv::certainlyLessEqual(a, b) + a.isSubsetOf(b) + (a == b);
    }
    for (double s : {2.5, -3.0, 0.0, -0.0, kInf, -kInf, std::numeric_limits<double>::quiet_NaN(), kMax}) {
      use(a * s);
      use(s * a);
      use(a / s);
    }
    use(-a);
    use(iv::abs(a));
    use(iv::sqr(a));
    use(iv::sqrt(a));
    use(iv::pow(a, 3));
    use(iv::pow(a, -2));
    use(iv::sin(a));
    use(iv::cos(a));
    use(iv::sinPoint(a.lower()));
    use(iv::cosPoint(a.upper()));
    sum += bits(a.mid()) ^ bits(a.width()) ^ bits(a.rad()) ^ bits(a.mag()) ^ bits(a.mig());
    sum += a.contains(1.0) + a.containsZero() + a.isBounded() + a.isPoint() + iv::certainlyPositive(a) +
           iv::certainlyNegative(a);
    if (!a.isEmpty()) {
      const auto halves = a.bisect();
      use(halves.first);
    }
  }
  return sum;
}

std::vector<Interval> volatileCopy(const std::vector<Interval>& xs) {
  std::vector<Interval> out;
  for (const Interval& x : xs) {
    volatile double lo = x.lower(), hi = x.upper();
    out.push_back(Interval::fromBoundsUnchecked(lo, hi));
  }
  return out;
}

// Ordinary and edge operands, including huge arguments (sinl/cosl path) and values near pi / 2.
std::vector<Interval> allOperands() {
  return {Interval::empty(),
          Interval::entire(),
          Interval(0.0),
          Interval(-0.0, 0.0),
          Interval(0.1, 0.3),
          Interval(-2.5, 1.5),
          Interval(1.5707963267948966),
          Interval(1.0, kInf),
          Interval(-kInf, -1.0),
          Interval(kMax),
          Interval(-kMax, kMax),
          Interval(std::numeric_limits<double>::denorm_min()),
          Interval(1e-310, 1e-300),
          Interval(3e9, 3e9 + 1e-6),
          Interval(1e300),
          Interval(-7.0, 0.0)};
}

// Operands whose endpoint arithmetic is exact (small integers, powers of two, zeros, infinities).
std::vector<Interval> exactOperands() {
  return {Interval::empty(),    Interval::entire(),  Interval(0.0),       Interval(-0.0, 0.0),  Interval(1.0, 2.0),
          Interval(-4.0, -2.0), Interval(-1.0, 4.0), Interval(1.0, kInf), Interval(-kInf, 0.0), Interval(4.0)};
}

// The checksum mixes the bits of the results with integer arithmetic only (a floating-point sum of the widened
// bounds would itself raise FE_INEXACT).
std::int64_t exactBattery(const std::vector<Interval>& xs) {
  std::int64_t sum = 0;
  auto use = [&sum](const Interval& r) {
    sum = sum * 31 + (iv::rounding::bitsOf(r.lower()) ^ iv::rounding::bitsOf(r.upper()));
  };
  for (const Interval& a : xs) {
    for (const Interval& b : xs) {
      use(a + b);
      use(a - b);
      use(a * b);
      Interval c = a, d = a;  // not chained: a widened bound times b would be inexact
      c += b;
      d *= b;
      use(c);
      use(d);
      use(iv::hull(a, b));
      use(iv::intersect(a, b));
      sum += iv::certainlyLess(a, b) + a.isSubsetOf(b);
    }
    use(a / Interval(2.0));
    use(a / 2.0);
    use(a * -4.0);
    use(0.0 * a);
    use(a / 0.0);
    use(a / Interval(-0.5, 0.25));  // divisor containing zero: entire(), no division executed
    use(a / Interval(0.0));
    use(-a);
    use(iv::abs(a));
    use(iv::sqr(a));
    use(iv::pow(a, 2));
    use(iv::pow(a, 3));
    use(iv::sqrt(iv::intersect(a, Interval(4.0, 16.0))));
    use(Interval::hullOf(a.mag(), a.mig()));
    sum += a.contains(1.0) + a.containsZero();
  }
  return sum;
}

TEST(FloatingPointEnvironment, ControlStateUnchangedAndFlagsNeverClearedOrInvalid) {
  const std::vector<Interval> xs = allOperands();
  std::fenv_t saved;
  std::fegetenv(&saved);
  int calls = 0;
  for (int m = 0; m < 4; ++m) {
    for (int preset : kPresets) {
      const std::vector<Interval> ops = volatileCopy(xs);
      std::fesetround(kModes[m]);
      std::feclearexcept(FE_ALL_EXCEPT);
      if (preset) std::feraiseexcept(preset);
      const Control before = control();
      const int flagsBefore = std::fetestexcept(FE_ALL_EXCEPT);
      volatile std::int64_t sink = battery(ops);
      (void)sink;
      const Control after = control();
      const int flagsAfter = std::fetestexcept(FE_ALL_EXCEPT);
      std::fesetenv(&saved);
      ++calls;
      SCOPED_TRACE(std::string(kModeNames[m]) + ", preset flags " + std::to_string(preset));
      EXPECT_EQ(flagsBefore, preset);
      EXPECT_TRUE(after == before) << before.str() << " -> " << after.str();
      EXPECT_EQ(flagsAfter & preset, preset) << "a raised flag was cleared";
      EXPECT_EQ(flagsAfter & ~preset & ~kAllowedNewFlags, 0) << "FE_INVALID or FE_DIVBYZERO raised";
    }
  }
  EXPECT_EQ(calls, 20);
}

TEST(FloatingPointEnvironment, ExactOperationsRaiseNoFlagAtAll) {
  const std::vector<Interval> xs = exactOperands();
  std::fenv_t saved;
  std::fegetenv(&saved);
  for (int m = 0; m < 4; ++m) {
    for (int preset : kPresets) {
      const std::vector<Interval> ops = volatileCopy(xs);
      std::fesetround(kModes[m]);
      std::feclearexcept(FE_ALL_EXCEPT);
      if (preset) std::feraiseexcept(preset);
      volatile std::int64_t sink = exactBattery(ops);
      (void)sink;
      const int flagsAfter = std::fetestexcept(FE_ALL_EXCEPT);
      const int round = std::fegetround();
      std::fesetenv(&saved);
      EXPECT_EQ(flagsAfter, preset) << kModeNames[m];
      EXPECT_EQ(round, kModes[m]) << kModeNames[m];
    }
  }
}

TEST(FloatingPointEnvironment, SinCosRestoreTheWholeEnvironmentUnderDirectedModes) {
  const std::vector<Interval> xs = allOperands();
  std::fenv_t saved;
  std::fegetenv(&saved);
  for (int m = 1; m < 4; ++m) {
    for (int preset : kPresets) {
      const std::vector<Interval> ops = volatileCopy(xs);
      std::fesetround(kModes[m]);
      std::feclearexcept(FE_ALL_EXCEPT);
      if (preset) std::feraiseexcept(preset);
      const Control before = control();
      std::int64_t sum = 0;  // integer checksum: no floating-point flags of its own
      for (const Interval& a : ops) {
        for (const Interval& r : {iv::sin(a), iv::cos(a), iv::sinPoint(a.lower()), iv::cosPoint(a.upper())}) {
          sum = sum * 31 + (iv::rounding::bitsOf(r.lower()) ^ iv::rounding::bitsOf(r.upper()));
        }
      }
      volatile std::int64_t sink = sum;
      (void)sink;
      const Control after = control();
      const int flagsAfter = std::fetestexcept(FE_ALL_EXCEPT);
      std::fesetenv(&saved);
      EXPECT_TRUE(after == before) << kModeNames[m];
      EXPECT_EQ(flagsAfter, preset) << kModeNames[m];
    }
  }
}

TEST(FloatingPointEnvironment, ScopedRoundToNearestRestores) {
  std::fenv_t saved;
  std::fegetenv(&saved);
  for (int m = 0; m < 4; ++m) {
    std::fesetround(kModes[m]);
    std::feclearexcept(FE_ALL_EXCEPT);
    std::feraiseexcept(FE_DIVBYZERO);
    const Control before = control();
    {
      iv::rounding::ScopedRoundToNearest rn;
      EXPECT_EQ(std::fegetround(), FE_TONEAREST);
      {
        iv::rounding::ScopedRoundToNearest nested;
        EXPECT_EQ(std::fegetround(), FE_TONEAREST);
      }
      EXPECT_EQ(std::fegetround(), FE_TONEAREST);
      std::feraiseexcept(FE_OVERFLOW);
    }
    const Control after = control();
    const int flags = std::fetestexcept(FE_ALL_EXCEPT);
    std::fesetenv(&saved);
    EXPECT_TRUE(after == before) << kModeNames[m];
    // Under a directed mode the whole environment is restored (the overflow raised inside is discarded); under
    // round-to-nearest nothing was saved.
    EXPECT_EQ(flags, kModes[m] == FE_TONEAREST ? (FE_DIVBYZERO | FE_OVERFLOW) : FE_DIVBYZERO) << kModeNames[m];
  }
}

TEST(FloatingPointEnvironment, ResultsCorrectUnderEveryModeAndOnFreshThreads) {
  // 0.1 + 0.2 (as doubles) is 0.3000000000000000166533453693773481063544750213623046875 exactly, strictly between
  // the doubles 0.3 (= 0.29999999999999998890) and 0.30000000000000004441; 1 / 3 lies strictly between the double
  // 1.0 / 3.0 (rounded to nearest, below) and the next one. The bounds must bracket them in every mode.
  auto check = [](int mode) {
    std::fesetround(mode);
    volatile double a = 0.1, b = 0.2, t = 1.0;
    const Interval s = Interval(a) + Interval(b);
    const Interval q = Interval(t) / Interval(3.0);
    const Interval c = iv::cos(Interval(a, b));
    const Interval p = iv::sin(Interval(1.5, 1.6));  // contains pi/2: upper bound must be 1
    std::fesetround(FE_TONEAREST);
    bool ok = s.lower() <= 0.3 && s.upper() >= 0.30000000000000004 && s.upper() - s.lower() <= 4 * 0x1p-54;
    ok = ok && q.lower() <= 1.0 / 3.0 && q.upper() >= iv::rounding::nextUp(1.0 / 3.0);
    ok = ok && q.upper() - q.lower() <= 4 * 0x1p-54;
    ok = ok && c.lower() <= std::cos(0.2) && c.upper() >= std::cos(0.1) && c.upper() < 1.0;
    ok = ok && p.upper() == 1.0 && p.lower() <= std::sin(1.6);
    return ok;
  };
  std::fenv_t saved;
  std::fegetenv(&saved);
  for (int m : kModes) EXPECT_TRUE(check(m)) << m;
  std::fesetenv(&saved);
  // Threads start with the default environment; interval code needs no per-thread set-up, whatever mode the
  // thread then selects.
  bool results[4] = {false, false, false, false};
  std::vector<std::thread> threads;
  for (int i = 0; i < 4; ++i) {
    threads.emplace_back(
        [&results, &check, i] { results[i] = check(kModes[i]) && iv::floatingPointEnvironmentSupported(); });
  }
  for (std::thread& t : threads) t.join();
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(results[i]) << kModeNames[i];
}

TEST(FloatingPointEnvironment, UnsupportedModesAreDetected) {
  EXPECT_TRUE(iv::floatingPointEnvironmentSupported());
  EXPECT_NO_THROW(iv::checkFloatingPointEnvironment());
#if defined(__SSE2__)
  const unsigned int csr = _mm_getcsr();
  _mm_setcsr(csr | 0x8000u);  // FTZ
  const bool ftzSupported = iv::floatingPointEnvironmentSupported();
  bool ftzThrows = false;
  try {
    iv::checkFloatingPointEnvironment();
  } catch (const pkm_accuracy::Error&) {
    ftzThrows = true;
  }
  _mm_setcsr(csr | 0x0040u);  // DAZ
  const bool dazSupported = iv::floatingPointEnvironmentSupported();
  _mm_setcsr(csr);
  EXPECT_FALSE(ftzSupported);
  EXPECT_TRUE(ftzThrows);
  EXPECT_FALSE(dazSupported);
  // The policy really breaks under FTZ: 2^-1022 * 2^-10 is flushed to 0, and [0 - ulp, 0 + ulp] misses 2^-1032.
  volatile double tiny = 0x1p-1022, scale = 0x1p-10;
  _mm_setcsr(csr | 0x8000u);
  const Interval p = Interval(tiny) * Interval(scale);
  volatile double plo = p.lower(), phi = p.upper();
  _mm_setcsr(csr);
  EXPECT_FALSE(Interval(plo, phi).contains(0x1p-1032)) << "FTZ no longer breaks the policy? update the documentation";
#endif
#if (defined(__x86_64__) || defined(__i386__)) && defined(__GLIBC__)
  fpu_control_t cw;
  _FPU_GETCW(cw);
  fpu_control_t lowered = (cw & ~_FPU_EXTENDED) | _FPU_DOUBLE;
  _FPU_SETCW(lowered);
  const bool pcSupported = iv::floatingPointEnvironmentSupported();
  _FPU_SETCW(cw);
  EXPECT_FALSE(pcSupported);
#endif
  EXPECT_TRUE(iv::floatingPointEnvironmentSupported());
}

TEST(FloatingPointEnvironment, DualAndEigenCallsLeaveTheModeAlone) {
  std::fenv_t saved;
  std::fegetenv(&saved);
  for (int m : kModes) {
    std::fesetround(m);
    const Control before = control();
    volatile double x0 = 0.5, y0 = 0.25;
    using D = iv::Dual<Interval, 2>;
    const D x = D::variable(Interval(x0, x0 + 0.01), 0), y = D::variable(Interval(y0), 1);
    const D f = sqrt(sqr(x) + sqr(y)) * sin(x) / (1.0 + cos(y));
    iv::IntervalMatrix6 a = iv::IntervalMatrix6::Identity() * Interval(x0);
    const iv::IntervalVector6 v = a * iv::IntervalVector6::Constant(Interval(y0, 1.0));
    volatile double sink = f.d(0).upper() + v(3).lower();
    (void)sink;
    const Control after = control();
    std::fesetenv(&saved);
    EXPECT_TRUE(after == before) << m;
  }
}

}  // namespace
