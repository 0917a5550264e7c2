// Containment of interval sin / cos against MPFR (correctly rounded, directed), and the empirical check of
// kLibmUlpBound (maximum ulp error of glibc sin / cos in round-to-nearest).
//
// For every random interval A (fixed seed) the test computes S = sin(A) and C = cos(A) under one of the four IEEE
// rounding modes (cycling), then checks in MPFR that the exact sin / cos values lie in S / C
//   * at both endpoints and at a random interior point (MPFR sin_cos rounded down at 128 bits; the ternary value
//     gives the upper neighbour, so the exact real value is bracketed and compared with the bounds in MPFR);
//   * at every critical point k pi / 2 inside A, where the exact values are 0 or +-1 (k is found in MPFR with a
//     precision that grows with the exponent of the endpoints, so the membership test is exact for every double);
//     four or more such points mean the exact range is [-1, 1].
// Hard arguments: the nearest doubles to k pi / 2 (k up to 2^62) and their neighbours, intervals straddling them,
// for every binary exponent the double closest to a multiple of pi / 2 (the hardest cases of the argument reduction,
// found by continued fractions), huge and tiny magnitudes, subnormals, signed zeros, wide intervals crossing extrema.
//
// The libm figures: the error of the point evaluation the implementation uses (iv::detail::libmSin / libmCos) must
// not exceed kLibmUlpBound; the error of glibc's double sin / cos is reported separately for |x| < 2^26 and above.
#include <gmp.h>
#include <gtest/gtest.h>
#include <mpfr.h>

#include <algorithm>
#include <cfenv>
#include <cinttypes>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "UlpContract.hpp"
#include "pkm_accuracy/core/interval/Functions.hpp"
#include "pkm_accuracy/core/interval/Interval.hpp"

namespace {

using pkm_accuracy::interval::Interval;
namespace iv = pkm_accuracy::interval;
namespace rd = pkm_accuracy::interval::rounding;

constexpr int kModes[4] = {FE_TONEAREST, FE_UPWARD, FE_DOWNWARD, FE_TOWARDZERO};
constexpr const char* kModeNames[4] = {"to-nearest", "upward", "downward", "toward-zero"};

// ---- random doubles and intervals (fixed seed; generated in round-to-nearest) ---------------------------------
class Gen {
 public:
  explicit Gen(std::uint64_t seed) : rng_(seed) {}
  std::uint64_t bits() { return rng_(); }
  double unit() { return static_cast<double>(rng_() >> 11) * 0x1p-53; }  // [0, 1)
  std::int64_t uniform(std::int64_t lo, std::int64_t hi) {
    return lo + static_cast<std::int64_t>(rng_() % static_cast<std::uint64_t>(hi - lo + 1));
  }
  double sign() { return (rng_() & 1) ? -1.0 : 1.0; }
  /// sign * [1, 2) * 2^e with e uniform in [emin, emax] (normal or subnormal result).
  double scaled(int emin, int emax) { return sign() * std::ldexp(1.0 + unit(), static_cast<int>(uniform(emin, emax))); }
  /// A finite double with uniformly random exponent field (subnormals included).
  double anyFinite() {
    for (;;) {
      const double x = rd::fromBits(static_cast<std::int64_t>(rng_()));
      if (std::isfinite(x)) return x;
    }
  }
  double stepUlps(double x, int n) {
    for (; n > 0; --n) x = rd::nextUp(x);
    for (; n < 0; ++n) x = rd::nextDown(x);
    return x;
  }
  /// A point of [lo, hi] (lo <= hi finite).
  double inside(double lo, double hi) {
    const double t = unit();
    const double x = lo * (1.0 - t) + hi * t;
    return std::min(std::max(x, lo), hi);
  }

 private:
  std::mt19937_64 rng_;
};

// ---- MPFR helpers ---------------------------------------------------------------------------------------------
struct Mp {
  mpfr_t v;
  explicit Mp(mpfr_prec_t p) { mpfr_init2(v, p); }
  ~Mp() { mpfr_clear(v); }
  Mp(const Mp&) = delete;
  Mp& operator=(const Mp&) = delete;
};

/// Exact value bracketed by [down, up] (two consecutive numbers of the working precision, or equal if exact).
struct Bracket {
  Mp down, up;
  explicit Bracket(mpfr_prec_t p) : down(p), up(p) {}
  void fromDown(int ternaryIsNonZero) {
    mpfr_set(up.v, down.v, MPFR_RNDN);
    if (ternaryIsNonZero) mpfr_nextabove(up.v);
  }
  bool within(const Interval& r) const {
    return !r.isEmpty() && mpfr_cmp_d(down.v, r.lower()) >= 0 && mpfr_cmp_d(up.v, r.upper()) <= 0;
  }
  std::string str() const {
    char buf[160];
    mpfr_snprintf(buf, sizeof buf, "[%.25Rg, %.25Rg]", down.v, up.v);
    return buf;
  }
};

std::string hex(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", x);
  return buf;
}
std::string str(const Interval& r) {
  if (r.isEmpty()) return "[empty]";
  return "[" + hex(r.lower()) + ", " + hex(r.upper()) + "]";
}

/// Computes sin(A), cos(A), sinPoint(lo), cosPoint(lo) under `mode`, with volatile inputs and outputs so that the
/// compiler cannot move the interval arithmetic across the fesetround calls.
struct Results {
  Interval s, c, sp, cp;
};
Results underMode(int mode, const Interval& a) {
  volatile double in[2] = {a.lower(), a.upper()};
  std::fesetround(mode);
  const Interval x = Interval::fromBoundsUnchecked(in[0], in[1]);
  const Interval s = iv::sin(x), c = iv::cos(x), sp = iv::sinPoint(in[0]), cp = iv::cosPoint(in[0]);
  volatile double out[8] = {s.lower(), s.upper(), c.lower(), c.upper(), sp.lower(), sp.upper(), cp.lower(), cp.upper()};
  std::fesetround(FE_TONEAREST);
  return {Interval::fromBoundsUnchecked(out[0], out[1]), Interval::fromBoundsUnchecked(out[2], out[3]),
          Interval::fromBoundsUnchecked(out[4], out[5]), Interval::fromBoundsUnchecked(out[6], out[7])};
}

class SinCosChecker {
 public:
  SinCosChecker() : x_(64), s_(kPrec), c_(kPrec), diff_(kPrec), diff2_(kPrec), q_(2200), piHalf_(2200) {
    mpz_init(kLo_);
    mpz_init(kHi_);
    mpz_init(k_);
  }
  ~SinCosChecker() {
    mpz_clear(kLo_);
    mpz_clear(kHi_);
    mpz_clear(k_);
  }

  /// Nearest double to k pi / 2.
  double nearestToMultipleOfHalfPi(std::int64_t k) {
    mpfr_set_prec(piHalf_.v, 200);
    mpfr_const_pi(piHalf_.v, MPFR_RNDN);
    mpfr_mul_si(piHalf_.v, piHalf_.v, static_cast<long>(k), MPFR_RNDN);
    mpfr_div_2ui(piHalf_.v, piHalf_.v, 1, MPFR_RNDN);
    return mpfr_get_d(piHalf_.v, MPFR_RNDN);
  }

  /// Checks exact sin(x), cos(x) against S, C and, if given, against the point enclosures SP, CP (and measures the
  /// libm error at x). Returns false on a failure.
  bool checkPoint(double x, const Interval& s, const Interval& c, std::string* why, const Interval* sp = nullptr,
                  const Interval* cp = nullptr) {
    mpfr_set_d(x_.v, x, MPFR_RNDN);
    const int t = mpfr_sin_cos(s_.down.v, c_.down.v, x_.v, MPFR_RNDD);
    s_.fromDown((t & 3) != 0);
    c_.fromDown((t >> 2) != 0);
    measureLibm(x);
    ++points_;
    bool ok = true;
    if (!s_.within(s)) {
      ok = false;
      *why += " sin(" + hex(x) + ") = " + s_.str() + " not in " + str(s);
    }
    if (!c_.within(c)) {
      ok = false;
      *why += " cos(" + hex(x) + ") = " + c_.str() + " not in " + str(c);
    }
    if (sp && !s_.within(*sp)) {
      ok = false;
      *why += " sin(" + hex(x) + ") = " + s_.str() + " not in sinPoint " + str(*sp);
    }
    if (cp && !c_.within(*cp)) {
      ok = false;
      *why += " cos(" + hex(x) + ") = " + c_.str() + " not in cosPoint " + str(*cp);
    }
    return ok;
  }

  /// Checks that the exact values at every k pi / 2 in [lo, hi] lie in S, C.
  bool checkCriticalPoints(double lo, double hi, const Interval& s, const Interval& c, std::string* why) {
    int e = 0;
    std::frexp(std::max(std::fabs(lo), std::fabs(hi)), &e);
    const mpfr_prec_t p = 128 + std::max(0, e);  // absolute precision of the quotients ~2^-120 for every double
    mpfr_set_prec(q_.v, p);
    mpfr_set_prec(piHalf_.v, p + 8);
    mpfr_const_pi(piHalf_.v, MPFR_RNDN);
    mpfr_div_2ui(piHalf_.v, piHalf_.v, 1, MPFR_RNDN);
    mpfr_set_d(x_.v, lo, MPFR_RNDN);
    mpfr_div(q_.v, x_.v, piHalf_.v, MPFR_RNDN);
    mpfr_get_z(kLo_, q_.v, MPFR_RNDU);  // smallest k with k pi/2 >= lo
    mpfr_set_d(x_.v, hi, MPFR_RNDN);
    mpfr_div(q_.v, x_.v, piHalf_.v, MPFR_RNDN);
    mpfr_get_z(kHi_, q_.v, MPFR_RNDD);  // largest k with k pi/2 <= hi
    mpz_sub(k_, kHi_, kLo_);
    if (mpz_sgn(k_) < 0) return true;  // no critical point inside
    bool ok = true;
    if (mpz_cmp_ui(k_, 3) >= 0) {  // four or more: all of 0, 1, -1 are attained
      ++fullPeriods_;
      if (!(s.lower() <= -1.0 && s.upper() >= 1.0 && c.lower() <= -1.0 && c.upper() >= 1.0)) {
        *why += " >= 4 critical points in [" + hex(lo) + ", " + hex(hi) + "] but sin " + str(s) + " cos " + str(c);
        ok = false;
      }
      return ok;
    }
    static constexpr double kSinAt[4] = {0.0, 1.0, 0.0, -1.0};
    static constexpr double kCosAt[4] = {1.0, 0.0, -1.0, 0.0};
    for (mpz_set(k_, kLo_); mpz_cmp(k_, kHi_) <= 0; mpz_add_ui(k_, k_, 1)) {
      const unsigned long r = mpz_fdiv_ui(k_, 4);  // NOLINT(runtime/int): GMP API
      ++criticalPoints_;
      if (!s.contains(kSinAt[r]) || !c.contains(kCosAt[r])) {
        *why += " critical point k pi/2 (k mod 4 = " + std::to_string(r) + ") in [" + hex(lo) + ", " + hex(hi) +
                "] but sin " + str(s) + " cos " + str(c);
        ok = false;
      }
    }
    return ok;
  }

  double maxUlp(int i) const { return maxUlp_[i]; }
  double argMax(int i) const { return argMax_[i]; }
  double maxAbsSmall(int i) const { return maxAbsSmall_[i]; }
  long measured(int i) const { return measured_[i]; }      // NOLINT(runtime/int)
  long points() const { return points_; }                  // NOLINT(runtime/int)
  long criticalPoints() const { return criticalPoints_; }  // NOLINT(runtime/int)
  long fullPeriods() const { return fullPeriods_; }        // NOLINT(runtime/int)

 private:
  static constexpr mpfr_prec_t kPrec = 128;

  // |v - f(x)| / ulp(f(x)) with the double ulp of the exact value (subnormal range: 2^-1074), for the evaluation
  // used by the implementation (slots 0/1: sin/cos, all arguments; slots 6/7: only |x| >= 2^26, the sinl/cosl
  // path) and for glibc's double sin/cos (slots 2/3: |x| < 2^26, slots 4/5: |x| >= 2^26). Round-to-nearest is in
  // force here. The figure is an upper bound of the error in the unit of rounding::widenByUlps: with y in
  // [down, up], |v - y| <= max(v - down, up - v) (rounded up), and ulp(y) is at least the ulp of the bracket end
  // nearer zero.
  void measureLibm(double x) {
    const double us = iv::detail::libmSin(x), uc = iv::detail::libmCos(x);
    update(0, us, s_, x);
    update(1, uc, c_, x);
    const bool huge = !(std::fabs(x) < 0x1p26);
    if (huge) {
      update(6, us, s_, x);
      update(7, uc, c_, x);
    }
    update(huge ? 4 : 2, std::sin(x), s_, x);
    update(huge ? 5 : 3, std::cos(x), c_, x);
  }
  void update(int i, double v, const Bracket& exact, double x) {
    if (mpfr_zero_p(exact.down.v) && mpfr_zero_p(exact.up.v)) return;  // exact zero (x = 0): nothing to measure
    long e = -2000;  // NOLINT(runtime/int)  |y| >= 2^(e-1) (an end at zero: no lower bound)
    if (!mpfr_zero_p(exact.down.v) && !mpfr_zero_p(exact.up.v))
      e = std::min(mpfr_get_exp(exact.down.v), mpfr_get_exp(exact.up.v));
    const long ulpExp = std::max<long>(e - 53, -1074);  // NOLINT(runtime/int)
    mpfr_set_d(diff_.v, v, MPFR_RNDN);
    mpfr_sub(diff_.v, diff_.v, exact.down.v, MPFR_RNDU);  // v - down
    mpfr_set_d(diff2_.v, v, MPFR_RNDN);
    mpfr_sub(diff2_.v, exact.up.v, diff2_.v, MPFR_RNDU);  // up - v
    mpfr_max(diff_.v, diff_.v, diff2_.v, MPFR_RNDU);      // >= |v - y|
    const double absErr = mpfr_get_d(diff_.v, MPFR_RNDU);
    if (e < -50) maxAbsSmall_[i] = std::max(maxAbsSmall_[i], absErr);  // |f(x)| < 2^-51
    mpfr_mul_2si(diff_.v, diff_.v, -ulpExp, MPFR_RNDU);
    const double err = mpfr_get_d(diff_.v, MPFR_RNDU);
    if (err > maxUlp_[i]) {
      maxUlp_[i] = err;
      argMax_[i] = x;
    }
    ++measured_[i];
  }

  Mp x_;
  Bracket s_, c_;
  Mp diff_, diff2_, q_, piHalf_;
  mpz_t kLo_, kHi_, k_;
  double maxUlp_[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  double argMax_[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  double maxAbsSmall_[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  long measured_[8] = {0, 0, 0, 0, 0, 0, 0, 0};             // NOLINT(runtime/int)
  long points_ = 0, criticalPoints_ = 0, fullPeriods_ = 0;  // NOLINT(runtime/int)
};

// For every binary exponent e, the double q 2^e (q < 2^53) closest to a multiple of pi / 2: q is the last
// continued-fraction convergent denominator of frac(2^e * 2 / pi) below 2^53 (convergents are the best
// approximations of the second kind). Includes Muller's worst case 6381956970095103 * 2^797.
std::vector<double> hardestReductionCases() {
  std::vector<double> out;
  mpz_t an, qPrev, q, t;
  mpz_inits(an, qPrev, q, t, nullptr);
  for (int e = -60; e <= 971; ++e) {
    const mpfr_prec_t p = std::max(0, e) + 400;
    Mp a(p);
    mpfr_const_pi(a.v, MPFR_RNDN);
    mpfr_ui_div(a.v, 2, a.v, MPFR_RNDN);
    mpfr_mul_2si(a.v, a.v, e, MPFR_RNDN);
    mpfr_frac(a.v, a.v, MPFR_RNDN);
    mpz_set_ui(qPrev, 0);
    mpz_set_ui(q, 1);
    for (int it = 0; it < 300 && !mpfr_zero_p(a.v); ++it) {
      mpfr_ui_div(a.v, 1, a.v, MPFR_RNDN);
      mpfr_get_z(an, a.v, MPFR_RNDD);
      mpfr_sub_z(a.v, a.v, an, MPFR_RNDN);
      mpz_mul(t, an, q);
      mpz_add(t, t, qPrev);
      if (mpz_sizeinbase(t, 2) > 53) break;
      mpz_set(qPrev, q);
      mpz_set(q, t);
    }
    const double x = std::ldexp(mpz_get_d(q), e);
    if (std::isfinite(x) && x != 0.0) out.push_back(x);
  }
  mpz_clears(an, qPrev, q, t, nullptr);
  return out;
}

// A random interval from one of the hard classes.
Interval randomInterval(Gen& g, SinCosChecker& chk, const std::vector<double>& hardest) {
  auto widen = [&g](double lo) -> Interval {
    double hi = lo;
    switch (g.uniform(0, 5)) {
      case 0:
        break;  // point
      case 1:
        hi = g.stepUlps(lo, static_cast<int>(g.uniform(1, 8)));
        break;
      case 2:
        hi = lo + std::fabs(lo) * std::ldexp(g.unit(), -static_cast<int>(g.uniform(1, 52)));
        break;
      case 3:
        hi = lo + std::fabs(g.scaled(-30, 0));
        break;
      case 4:
        hi = lo + 6.0 * g.unit() + 0.5;  // wide: crosses one or more extrema
        break;
      default:
        hi = lo + std::fabs(g.scaled(2, 8));  // wider than a period
        break;
    }
    hi = std::min(std::max(hi, lo), std::numeric_limits<double>::max());
    return Interval(lo, hi);
  };
  switch (g.uniform(0, 9)) {
    case 0:
    case 1: {  // moderate
      return widen(g.sign() * 12.0 * g.unit());
    }
    case 2:
    case 3:
    case 4: {  // near k pi / 2, from small to 2^62
      static constexpr int kMaxBits[6] = {3, 10, 20, 31, 45, 62};
      const int bits = kMaxBits[g.uniform(0, 5)];
      const std::int64_t k = g.uniform(-(std::int64_t{1} << bits), std::int64_t{1} << bits);
      const double c = chk.nearestToMultipleOfHalfPi(k);
      const int mode = static_cast<int>(g.uniform(0, 3));
      if (mode == 0) return widen(g.stepUlps(c, static_cast<int>(g.uniform(-3, 3))));
      // straddling the critical point by a few ulps to a relative 2^-10
      const double below = g.stepUlps(c, -static_cast<int>(g.uniform(0, 4)));
      const double above = g.stepUlps(c, static_cast<int>(g.uniform(0, 4)));
      if (mode == 1) return Interval(below, above);
      const double r = std::ldexp(std::fabs(c) + 1.0, -static_cast<int>(g.uniform(10, 60)));
      return Interval(below - r * g.unit(), above + r * g.unit());
    }
    case 5: {  // huge magnitudes up to DBL_MAX
      return widen(g.scaled(20, 1023));
    }
    case 6: {  // tiny, subnormal, signed zeros
      switch (g.uniform(0, 3)) {
        case 0:
          return widen(g.scaled(-1074, -20));
        case 1:
          return Interval(g.sign() * 0.0, std::fabs(g.scaled(-1074, 0)));
        case 2:
          return Interval(-std::fabs(g.scaled(-1074, -500)), (g.bits() & 1) ? 0.0 : -0.0);
        default: {
          const double z = g.sign() * 0.0;
          return Interval(z, z);
        }
      }
    }
    case 7: {  // any finite double (mostly huge or tiny)
      return widen(g.anyFinite());
    }
    case 8: {  // the hardest cases of the reduction, one per exponent, and their neighbours
      const double w = g.sign() * hardest[g.uniform(0, static_cast<std::int64_t>(hardest.size()) - 1)];
      return widen(g.stepUlps(w, static_cast<int>(g.uniform(-2, 2))));
    }
    default: {  // wide interval crossing extrema, moderate magnitude
      const double lo = g.sign() * 60.0 * g.unit();
      return Interval(lo, lo + 7.0 * g.unit());
    }
  }
}

TEST(FunctionsMpfr, SinCosContainExactValuesInAllRoundingModes) {
  constexpr long kCases = 1000000;  // NOLINT(runtime/int)
  Gen g(20240611);
  SinCosChecker chk;
  const std::vector<double> hardest = hardestReductionCases();
  ASSERT_GT(hardest.size(), 1000u);
  ASSERT_NE(std::find(hardest.begin(), hardest.end(), std::ldexp(6381956970095103.0, 797)), hardest.end());
  long failures = 0, perMode[4] = {0, 0, 0, 0};  // NOLINT(runtime/int)
  std::vector<std::string> messages;
  for (long i = 0; i < kCases; ++i) {  // NOLINT(runtime/int)
    const Interval a = randomInterval(g, chk, hardest);
    const int m = static_cast<int>(i % 4);
    ++perMode[m];
    const Results r = underMode(kModes[m], a);
    std::string why;
    bool ok = true;
    ok &= chk.checkPoint(a.lower(), r.s, r.c, &why, &r.sp, &r.cp);  // and sinPoint / cosPoint at the lower endpoint
    if (a.upper() != a.lower()) {
      ok &= chk.checkPoint(a.upper(), r.s, r.c, &why);
      ok &= chk.checkPoint(g.inside(a.lower(), a.upper()), r.s, r.c, &why);
      ok &= chk.checkCriticalPoints(a.lower(), a.upper(), r.s, r.c, &why);
    }
    if (!(r.s.isSubsetOf(Interval(-1.0, 1.0)) && r.c.isSubsetOf(Interval(-1.0, 1.0)))) {
      ok = false;
      why += " result outside [-1, 1]";
    }
    if (!ok) {
      ++failures;
      if (messages.size() < 10) messages.push_back(std::string(kModeNames[m]) + ": A = " + str(a) + why);
    }
  }
  for (const std::string& s : messages) ADD_FAILURE() << s;
  EXPECT_EQ(failures, 0);
  std::printf(
      "[ sin/cos ] %ld interval cases (%ld / %ld / %ld / %ld per rounding mode), %ld MPFR point checks, %ld critical "
      "points checked, %ld intervals with >= 4 critical points\n",
      kCases, perMode[0], perMode[1], perMode[2], perMode[3], chk.points(), chk.criticalPoints(), chk.fullPeriods());
  static constexpr const char* kWhat[8] = {
      "used sin (detail::libmSin), all |x|  ", "used cos (detail::libmCos), all |x|  ",
      "glibc double sin, |x| < 2^26         ", "glibc double cos, |x| < 2^26         ",
      "glibc double sin, |x| >= 2^26        ", "glibc double cos, |x| >= 2^26        ",
      "used sin, |x| >= 2^26 (via sinl)     ", "used cos, |x| >= 2^26 (via cosl)     "};
  for (int i = 0; i < 8; ++i) {
    std::printf("[ libm    ] %s: max %.4f ulp (at %a) over %ld arguments; max abs. error %a where |f| < 2^-51\n",
                kWhat[i], chk.maxUlp(i), chk.argMax(i), chk.measured(i), chk.maxAbsSmall(i));
  }
  std::printf("[ libm    ] kLibmUlpBound = %d\n", iv::kLibmUlpBound);
  EXPECT_LE(chk.maxUlp(0), static_cast<double>(iv::kLibmUlpBound));
  EXPECT_LE(chk.maxUlp(1), static_cast<double>(iv::kLibmUlpBound));
}

// rounding::widenByUlps against the definition of its contract. The oracle first: for v = 1 - 4 * 2^-53 and k = 2,
// S(v, 2) = [1 - 6 * 2^-53, 1] (y = 1 is 4 * 2^-53 = 2 ulp(1) away; below 1 the ulp is 2^-53); for v = 1,
// S(1, 2) = [1 - 2 * 2^-53, 1 + 2 * 2^-52]. Then, for k = 0 ... 5 and values around every kind of ulp class boundary
// (powers of two from the subnormals to 2^999, on both sides, both signs, zeros) and random doubles: the bounds
// contain S(v, k), and they are the k-th neighbours of v except on the side away from zero when S(v, k) reaches the
// next ulp class, where they are the 2k-th (so away from powers of two the widths are those of k steps).
TEST(FunctionsMpfr, WidenByUlpsCoversTheUlpContractAndStaysTight) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  pkm_accuracy::test::UlpContract s;
  ASSERT_TRUE(s.set(1.0 - 0x1p-51, 2));
  EXPECT_EQ(mpfr_cmp_d(s.inf(), 1.0 - 6 * 0x1p-53), 0);
  EXPECT_EQ(mpfr_cmp_d(s.sup(), 1.0), 0);
  EXPECT_TRUE(s.reachesLargerBinade());
  ASSERT_TRUE(s.set(1.0, 2));
  EXPECT_EQ(mpfr_cmp_d(s.inf(), 1.0 - 2 * 0x1p-53), 0);
  EXPECT_EQ(mpfr_cmp_d(s.sup(), 1.0 + 2 * 0x1p-52), 0);
  EXPECT_FALSE(s.reachesLargerBinade());

  Gen g(4242);
  std::vector<double> values = {0.0, -0.0};
  for (int e : {-1074, -1073, -1060, -1023, -1022, -1021, -1020, -1000, -60, -2, -1, 0, 1, 2, 52, 53, 999}) {
    for (int j = -14; j <= 14; ++j) {
      const double v = g.stepUlps(std::ldexp(1.0, e), j);
      values.push_back(v);
      values.push_back(-v);
    }
  }
  for (int i = 0; i < 20000; ++i) values.push_back(i % 2 ? g.anyFinite() : g.scaled(-1074, 999));
  long checked = 0, reaching = 0;  // NOLINT(runtime/int)
  for (int k = 0; k <= 5; ++k) {
    for (double v : values) {
      if (!(std::fabs(v) < 0x1p1000)) continue;
      const rd::Bounds b = rd::widenByUlps(v, k);
      ASSERT_TRUE(s.set(v, k));
      std::string why;
      ASSERT_TRUE(s.coveredBy(b.lower, b.upper, -kInf, kInf, &why)) << "v = " << hex(v) << ", k = " << k << why;
      const bool reach = s.reachesLargerBinade();
      const double a = std::fabs(v), toward = g.stepUlps(a, -k), away = g.stepUlps(a, reach ? 2 * k : k);
      const double lower = std::signbit(v) ? -away : toward, upper = std::signbit(v) ? -toward : away;
      ASSERT_TRUE(b.lower == lower && b.upper == upper)
          << "v = " << hex(v) << ", k = " << k << ": [" << hex(b.lower) << ", " << hex(b.upper) << "], expected ["
          << hex(lower) << ", " << hex(upper) << "]";
      ++checked;
      reaching += reach;
    }
  }
  // At least the values 1 ... 2k doubles below (in magnitude) the 12 listed powers from 2^-1021 up, which start an
  // ulp class, for both signs: 12 * 2 * (2 + 4 + 6 + 8 + 10) (the random values add a few more at most).
  EXPECT_GE(reaching, 12 * 2 * 30);
  std::printf("[ ulps    ] widenByUlps: %ld values checked, %ld of them next to a larger ulp class\n", checked,
              reaching);
}

// The widening must deliver what kLibmUlpBound claims: a libm value v within k ulps of the exact value y, in ulps
// of y, stands for every y in S(v, k) = { y : |y - v| <= k ulp(y) } (test/core/UlpContract.hpp), and the enclosure
// must contain all of S(v, k) inside [-1, 1]. Away from powers of two this is [v - k ulp(v), v + k ulp(v)]; when v
// lies just below a power of two P in magnitude, S(v, k) reaches into the binade above P, where ulp(y) = 2 ulp(v),
// up to |v| + 2k ulp(v). The arguments scanned are the doubles around asin(P) / acos(P) (and tiny x for cos ~ 1),
// where libm's sin / cos values step by at most about one ulp and so land in every ulp just below P; every interval
// entry point is checked (sinPoint / cosPoint at the lower end and sin / cos of [x_prev, x], cycling the four
// rounding modes), and each scan must actually reach the binade above P.
TEST(FunctionsMpfr, EnclosuresCoverTheUlpBoundAcrossPowersOfTwo) {
  const int k = iv::kLibmUlpBound;
  pkm_accuracy::test::UlpContract s;
  struct Scan {
    const char* what;
    bool sine;  // the function whose values cross P (the other one is checked too)
    std::vector<double> xs;
  };
  std::vector<Scan> scans;
  auto around = [](double x0, int n) {
    std::vector<double> xs;
    double x = x0;
    for (int i = 0; i < n; ++i) x = rd::nextDown(x);
    for (int i = 0; i <= 2 * n; ++i, x = rd::nextUp(x)) xs.push_back(x);
    return xs;
  };
  for (double p : {0.5, 0.25, 0.125, 0x1p-10}) {
    scans.push_back({"sin near +P", true, around(std::asin(p), 64)});
    scans.push_back({"sin near -P", true, around(-std::asin(p), 64)});
  }
  scans.push_back({"cos near 0.5", false, around(std::acos(0.5), 64)});
  std::vector<double> tiny;  // cos(x) = 1 - x^2 / 2 steps through the ulps below 1
  for (int j = 1; j <= 64; ++j) tiny.push_back(std::ldexp(j, -30));
  scans.push_back({"cos near 1", false, tiny});
  long checks = 0, failures = 0;  // NOLINT(runtime/int)
  std::vector<std::string> messages;
  int mode = 0;
  for (const Scan& scan : scans) {
    int reaching = 0;
    for (std::size_t i = 1; i < scan.xs.size(); ++i) {
      const double lo = scan.xs[i - 1], hi = scan.xs[i];
      const Results r = underMode(kModes[mode], Interval(lo, hi));
      const std::string where =
          std::string(scan.what) + " (" + kModeNames[mode] + "), [" + hex(lo) + ", " + hex(hi) + "]";
      mode = (mode + 1) % 4;
      struct Check {
        const char* name;
        double v;
        Interval r;
        bool crossing;
      };
      const double sLo = iv::detail::libmSin(lo), sHi = iv::detail::libmSin(hi);
      const double cLo = iv::detail::libmCos(lo), cHi = iv::detail::libmCos(hi);
      const Check list[6] = {{"sin", sLo, r.s, scan.sine},   {"sin", sHi, r.s, scan.sine},
                             {"cos", cLo, r.c, !scan.sine},  {"cos", cHi, r.c, !scan.sine},
                             {"sinPoint", sLo, r.sp, false}, {"cosPoint", cLo, r.cp, false}};
      for (const Check& c : list) {
        ASSERT_TRUE(s.set(c.v, k)) << hex(c.v);
        if (c.crossing && s.reachesLargerBinade()) ++reaching;
        std::string why;
        ++checks;
        if (!s.coveredBy(c.r.lower(), c.r.upper(), -1.0, 1.0, &why)) {
          ++failures;
          if (messages.size() < 10)
            messages.push_back(where + ": " + c.name + " of libm value " + hex(c.v) + " = " + str(c.r) + why);
        }
      }
    }
    EXPECT_GT(reaching, 0) << scan.what
                           << ": no libm value whose ulp contract reaches the binade above (scan too coarse)";
  }
  for (const std::string& m : messages) ADD_FAILURE() << m;
  EXPECT_EQ(failures, 0) << "of " << checks;
  std::printf("[ ulps    ] %ld enclosures checked against the ulp contract near powers of two\n", checks);
}

// The enclosures must also be tight: away from extrema, a narrow interval's enclosure is at most a few ulps wider
// than the exact range (guards against a detection that adds extrema everywhere, which would pass containment).
TEST(FunctionsMpfr, NarrowIntervalsAwayFromExtremaAreTight) {
  Gen g(7);
  long loose = 0, checked = 0;  // NOLINT(runtime/int)
  for (int i = 0; i < 200000; ++i) {
    const double lo = g.sign() * std::ldexp(1.0 + g.unit(), static_cast<int>(g.uniform(-3, 29)));
    const double hi = g.stepUlps(lo, static_cast<int>(g.uniform(0, 16)));
    const Interval a(lo, hi);
    const Interval s = iv::sin(a), c = iv::cos(a);
    // exact ranges are within [min, max] of the endpoint values unless an extremum is inside; the width of both
    // enclosures must then stay below 64 ulps of 1 unless the endpoint value is within 1e-6 of +-1
    for (const auto& [r, f] :
         {std::pair<Interval, double>{s, std::sin(lo)}, std::pair<Interval, double>{c, std::cos(lo)}}) {
      if (std::fabs(f) > 1.0 - 1e-6) continue;
      ++checked;
      if (r.upper() - r.lower() > 64 * 0x1p-52 + 64 * std::fabs(hi - lo)) ++loose;
    }
  }
  EXPECT_EQ(loose, 0) << "of " << checked;
}

TEST(FunctionsMpfr, NarrowHugeArgumentsUseTheDerivativeTest) {
  // Above 2^30 a narrow interval that is far from an extremum is still enclosed tightly (not [-1, 1]).
  Gen g(99);
  int tight = 0;
  for (int i = 0; i < 10000; ++i) {
    const double lo = g.scaled(31, 44);  // 4 ulps <= 2^-6: narrow
    const Interval a(lo, g.stepUlps(lo, 4));
    // |sin'| <= 1: the exact range is at most as wide as the argument; an added extremum is within w^2 of it
    for (const Interval& r : {iv::sin(a), iv::cos(a)}) {
      if (r.upper() - r.lower() <= (a.upper() - a.lower()) + 1e-12) ++tight;
    }
  }
  EXPECT_EQ(tight, 20000);
  // Wide intervals above 2^30 are [-1, 1] by design; unbounded ones too.
  EXPECT_EQ(iv::sin(Interval(0x1p40, 0x1p40 + 2.0)), Interval(-1.0, 1.0));
  EXPECT_EQ(iv::cos(Interval(1.0, std::numeric_limits<double>::infinity())), Interval(-1.0, 1.0));
  EXPECT_EQ(iv::sin(Interval::entire()), Interval(-1.0, 1.0));
  EXPECT_TRUE(iv::sin(Interval::empty()).isEmpty());
  EXPECT_TRUE(iv::cos(Interval::empty()).isEmpty());
  EXPECT_TRUE(iv::sinPoint(std::numeric_limits<double>::quiet_NaN()).isEmpty());
  EXPECT_EQ(iv::cosPoint(std::numeric_limits<double>::infinity()), Interval(-1.0, 1.0));
}

}  // namespace
