// Containment (and one-ulp tightness) of the interval operations +, -, *, /, sqr, sqrt, abs and pow(int) against
// MPFR, 10^6 random cases per operation with a fixed seed, each computed under one of the four IEEE rounding modes
// (cycling, 250 000 cases per mode).
//
// The exact value at a point is bracketed in MPFR (200 bits, rounded down; the ternary value gives the upper
// neighbour when inexact) and compared with the interval bounds in MPFR, never by rounding to double. The range of
// each operation over the input box is attained at the corners (and at 0 for sqr / abs / even powers when 0 is
// inside), so the test checks the corners, 0 where relevant, and a random interior point. Tightness: every bound
// must be within one ulp (outward) of the double that brackets the exact extreme, which is what the policy
// "round in any mode, step one ulp outward" promises (Rounding.hpp).
//
// Operands mix ordinary magnitudes, the full exponent range, subnormals, signed zeros and special values, with
// widths from zero (points) over a few ulps to relative and absolute widths and intervals crossing zero.
#include <gtest/gtest.h>
#include <mpfr.h>

#include <cfenv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "pkm_accuracy/core/interval/Interval.hpp"

namespace {

using pkm_accuracy::interval::Interval;
namespace iv = pkm_accuracy::interval;
namespace rd = pkm_accuracy::interval::rounding;

constexpr long kCases = 1000000;  // NOLINT(runtime/int): per operation
constexpr int kModes[4] = {FE_TONEAREST, FE_UPWARD, FE_DOWNWARD, FE_TOWARDZERO};
constexpr const char* kModeNames[4] = {"to-nearest", "upward", "downward", "toward-zero"};
constexpr double kMax = std::numeric_limits<double>::max();

class Gen {
 public:
  explicit Gen(std::uint64_t seed) : rng_(seed) {}
  std::uint64_t bits() { return rng_(); }
  double unit() { return static_cast<double>(rng_() >> 11) * 0x1p-53; }  // [0, 1)
  std::int64_t uniform(std::int64_t lo, std::int64_t hi) {
    return lo + static_cast<std::int64_t>(rng_() % static_cast<std::uint64_t>(hi - lo + 1));
  }
  double sign() { return (rng_() & 1) ? -1.0 : 1.0; }
  double scaled(int emin, int emax) { return sign() * std::ldexp(1.0 + unit(), static_cast<int>(uniform(emin, emax))); }
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
  double inside(double lo, double hi) {
    const double t = unit();
    const double x = lo * (1.0 - t) + hi * t;
    return std::min(std::max(x, lo), hi);
  }
  double point() {
    static constexpr double kSpecial[] = {
        0.0,  -0.0,  1.0,       -1.0,       2.0,       0.5,        3.0,       0.1,   -0.1,   1e-300, -1e300,  1e300,
        kMax, -kMax, 0x1p-1022, -0x1p-1022, 0x1p-1074, -0x1p-1074, 0x1p-1073, 1e154, -1e154, 1e-154, 0x1p512, 0x1p-537};
    switch (uniform(0, 9)) {
      case 0:
      case 1:
      case 2:
        return scaled(-8, 8);
      case 3:
        return scaled(-60, 60);
      case 4:
      case 5:
        return anyFinite();
      case 6:
        return kSpecial[uniform(0, sizeof kSpecial / sizeof kSpecial[0] - 1)];
      case 7:
        return static_cast<double>(uniform(-20, 20));
      case 8:
        return scaled(-1074, -1000);  // subnormal or tiny normal
      default:
        return scaled(900, 1023);  // near overflow
    }
  }
  Interval interval() {
    const double lo = point();
    double hi = lo;
    switch (uniform(0, 6)) {
      case 0:
        break;  // point
      case 1:
        hi = stepUlps(lo, static_cast<int>(uniform(1, 4)));
        break;
      case 2:
        hi = lo + std::fabs(lo) * std::ldexp(unit(), -static_cast<int>(uniform(1, 40)));
        break;
      case 3:
        hi = lo + std::fabs(scaled(-20, 3));
        break;
      case 4: {  // crossing zero
        const double a = std::fabs(point()), b = std::fabs(point());
        return Interval(-a, b);
      }
      case 5:
        hi = lo + std::fabs(point());
        break;
      default: {  // a symmetric-ish random pair
        const double b = point();
        return Interval::hullOf(lo, b);
      }
    }
    hi = std::min(std::max(hi, lo), kMax);
    return Interval(lo, hi);
  }

 private:
  std::mt19937_64 rng_;
};

struct Mp {
  mpfr_t v;
  explicit Mp(mpfr_prec_t p) { mpfr_init2(v, p); }
  ~Mp() { mpfr_clear(v); }
  Mp(const Mp&) = delete;
  Mp& operator=(const Mp&) = delete;
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

// Applies op under `mode` with volatile inputs / outputs (no motion of the arithmetic across fesetround).
Interval underMode(int mode, const Interval& a, const Interval& b,
                   const std::function<Interval(Interval, Interval)>& op) {
  volatile double in[4] = {a.lower(), a.upper(), b.lower(), b.upper()};
  std::fesetround(mode);
  const Interval r = op(Interval::fromBoundsUnchecked(in[0], in[1]), Interval::fromBoundsUnchecked(in[2], in[3]));
  volatile double out[2] = {r.lower(), r.upper()};
  std::fesetround(FE_TONEAREST);
  return Interval::fromBoundsUnchecked(out[0], out[1]);
}

using MpOp = std::function<int(mpfr_ptr, double, double, mpfr_rnd_t)>;

// Checks the exact values of `exact` at the given points against r, and tracks the exact min / max (rounded
// outward to double) for the tightness test.
class Checker {
 public:
  Checker() : down_(200), up_(200) {}
  // Returns false on a containment failure.
  bool check(const MpOp& exact, double x, double y, const Interval& r, std::string* why) {
    const int t = exact(down_.v, x, y, MPFR_RNDD);
    mpfr_set(up_.v, down_.v, MPFR_RNDN);
    if (t != 0) mpfr_nextabove(up_.v);
    minD_ = std::min(minD_, mpfr_get_d(down_.v, MPFR_RNDD));
    maxU_ = std::max(maxU_, mpfr_get_d(up_.v, MPFR_RNDU));
    ++points_;
    if (!r.isEmpty() && mpfr_cmp_d(down_.v, r.lower()) >= 0 && mpfr_cmp_d(up_.v, r.upper()) <= 0) return true;
    char buf[256];
    mpfr_snprintf(buf, sizeof buf, " exact(%a, %a) = [%.20Rg, %.20Rg] not in ", x, y, down_.v, up_.v);
    *why += buf + str(r);
    return false;
  }
  void resetExtremes() {
    minD_ = std::numeric_limits<double>::infinity();
    maxU_ = -std::numeric_limits<double>::infinity();
  }
  // r is within one ulp (outward) of the doubles that bracket the exact extremes.
  bool tight(const Interval& r, std::string* why) const {
    if (r.lower() >= rd::nextDown(minD_) && r.upper() <= rd::nextUp(maxU_)) return true;
    *why += " not tight: " + str(r) + " vs exact extremes [" + hex(minD_) + ", " + hex(maxU_) + "]";
    return false;
  }
  long points() const { return points_; }  // NOLINT(runtime/int)

 private:
  Mp down_, up_;
  double minD_ = 0.0, maxU_ = 0.0;
  long points_ = 0;  // NOLINT(runtime/int)
};

struct Report {
  long failures = 0;  // NOLINT(runtime/int)
  std::vector<std::string> messages;
  void fail(const std::string& m) {
    ++failures;
    if (messages.size() < 10) messages.push_back(m);
  }
};

void finish(const char* name, const Report& rep, const Checker& chk, long tightChecked) {  // NOLINT(runtime/int)
  for (const std::string& m : rep.messages) ADD_FAILURE() << name << ": " << m;
  EXPECT_EQ(rep.failures, 0) << name;
  std::printf("[ %-6s ] %ld cases (%ld per rounding mode), %ld MPFR point checks, %ld tightness checks\n", name, kCases,
              kCases / 4, chk.points(), tightChecked);
}

// Binary operations: corners + a random interior pair. With pointB, b is a degenerate interval (the mixed
// Interval-double operations receive b.lower()).
void runBinary(const char* name, std::uint64_t seed, const std::function<Interval(Interval, Interval)>& op,
               const MpOp& exact, bool isDivision, bool pointB = false) {
  Gen g(seed);
  Checker chk;
  Report rep;
  long tightChecked = 0;               // NOLINT(runtime/int)
  for (long i = 0; i < kCases; ++i) {  // NOLINT(runtime/int)
    const Interval a = g.interval(), b = pointB ? Interval(g.point()) : g.interval();
    const int m = static_cast<int>(i % 4);
    const Interval r = underMode(kModes[m], a, b, op);
    std::string why;
    bool ok = true;
    if (isDivision && b.containsZero()) {
      ok = r == Interval::entire();
      if (!ok) why = " divisor contains zero but result " + str(r) + " is not entire";
    } else {
      chk.resetExtremes();
      for (double x : {a.lower(), a.upper()})
        for (double y : {b.lower(), b.upper()}) ok &= chk.check(exact, x, y, r, &why);
      const double x = g.inside(a.lower(), a.upper()), y = g.inside(b.lower(), b.upper());
      ok &= chk.check(exact, x, y, r, &why);
      ++tightChecked;
      ok &= chk.tight(r, &why);
    }
    if (!ok) rep.fail(std::string(kModeNames[m]) + ": a = " + str(a) + ", b = " + str(b) + why);
  }
  finish(name, rep, chk, tightChecked);
}

// Unary operations: endpoints, extra points (0 when inside for sqr / abs / even powers), a random interior point.
void runUnary(const char* name, std::uint64_t seed, const std::function<Interval(Interval, int)>& op,
              const std::function<int(mpfr_ptr, double, int, mpfr_rnd_t)>& exact, const std::function<int(Gen&)>& pickN,
              bool zeroIsExtreme, bool checkTight, const std::function<Interval(Interval)>& domain = nullptr) {
  Gen g(seed);
  Checker chk;
  Report rep;
  long tightChecked = 0;               // NOLINT(runtime/int)
  for (long i = 0; i < kCases; ++i) {  // NOLINT(runtime/int)
    const Interval a = g.interval();
    const int n = pickN(g);
    const int m = static_cast<int>(i % 4);
    const Interval r = underMode(kModes[m], a, Interval(0.0), [&op, n](Interval x, Interval) { return op(x, n); });
    const Interval d = domain ? domain(a) : a;
    std::string why;
    bool ok = true;
    const MpOp f = [&exact, n](mpfr_ptr out, double x, double, mpfr_rnd_t rnd) { return exact(out, x, n, rnd); };
    if (d.isEmpty()) {
      ok = r.isEmpty();
      if (!ok) why = " expected empty, got " + str(r);
    } else if (n < 0 && d.containsZero()) {
      ok = r == Interval::entire();
      if (!ok) why = " negative power of an interval containing 0 must be entire, got " + str(r);
    } else {
      chk.resetExtremes();
      ok &= chk.check(f, d.lower(), 0.0, r, &why);
      ok &= chk.check(f, d.upper(), 0.0, r, &why);
      if (zeroIsExtreme && d.containsZero()) ok &= chk.check(f, 0.0, 0.0, r, &why);
      ok &= chk.check(f, g.inside(d.lower(), d.upper()), 0.0, r, &why);
      if (checkTight) {
        ++tightChecked;
        ok &= chk.tight(r, &why);
      }
    }
    if (!ok) rep.fail(std::string(kModeNames[m]) + ": a = " + str(a) + ", n = " + std::to_string(n) + why);
  }
  finish(name, rep, chk, tightChecked);
}

void setD(mpfr_ptr out, double x) { mpfr_set_d(out, x, MPFR_RNDN); }  // exact: out has >= 53 bits

TEST(IntervalMpfr, Addition) {
  runBinary(
      "a + b", 1, [](Interval a, Interval b) { return a + b; },
      [](mpfr_ptr o, double x, double y, mpfr_rnd_t r) {
        static Mp t(64);
        setD(t.v, y);
        setD(o, x);
        return mpfr_add(o, o, t.v, r);
      },
      false);
}

TEST(IntervalMpfr, Subtraction) {
  runBinary(
      "a - b", 2, [](Interval a, Interval b) { return a - b; },
      [](mpfr_ptr o, double x, double y, mpfr_rnd_t r) {
        static Mp t(64);
        setD(t.v, y);
        setD(o, x);
        return mpfr_sub(o, o, t.v, r);
      },
      false);
}

TEST(IntervalMpfr, Multiplication) {
  runBinary(
      "a * b", 3, [](Interval a, Interval b) { return a * b; },
      [](mpfr_ptr o, double x, double y, mpfr_rnd_t r) {
        static Mp t(64);
        setD(t.v, y);
        setD(o, x);
        return mpfr_mul(o, o, t.v, r);
      },
      false);
}

TEST(IntervalMpfr, Division) {
  runBinary(
      "a / b", 4, [](Interval a, Interval b) { return a / b; },
      [](mpfr_ptr o, double x, double y, mpfr_rnd_t r) {
        static Mp t(64);
        setD(t.v, y);
        setD(o, x);
        return mpfr_div(o, o, t.v, r);
      },
      true);
}

TEST(IntervalMpfr, MixedMultiplicationByDouble) {
  runBinary(
      "a * s", 9, [](Interval a, Interval b) { return b.lower() * a; },
      [](mpfr_ptr o, double x, double y, mpfr_rnd_t r) {
        static Mp t(64);
        setD(t.v, y);
        setD(o, x);
        return mpfr_mul(o, o, t.v, r);
      },
      false, true);
}

TEST(IntervalMpfr, MixedDivisionByDouble) {
  runBinary(
      "a / s", 10, [](Interval a, Interval b) { return a / b.lower(); },
      [](mpfr_ptr o, double x, double y, mpfr_rnd_t r) {
        static Mp t(64);
        setD(t.v, y);
        setD(o, x);
        return mpfr_div(o, o, t.v, r);
      },
      true, true);
}

TEST(IntervalMpfr, Square) {
  runUnary(
      "sqr", 5, [](Interval a, int) { return iv::sqr(a); },
      [](mpfr_ptr o, double x, int, mpfr_rnd_t r) {
        setD(o, x);
        return mpfr_sqr(o, o, r);
      },
      [](Gen&) { return 2; }, true, true);
}

TEST(IntervalMpfr, SquareRoot) {
  runUnary(
      "sqrt", 6, [](Interval a, int) { return iv::sqrt(a); },
      [](mpfr_ptr o, double x, int, mpfr_rnd_t r) {
        setD(o, x);
        return mpfr_sqrt(o, o, r);
      },
      [](Gen&) { return 0; }, false, true,
      [](Interval a) { return iv::intersect(a, Interval(0.0, std::numeric_limits<double>::infinity())); });
}

TEST(IntervalMpfr, AbsoluteValue) {
  runUnary(
      "abs", 7, [](Interval a, int) { return iv::abs(a); },
      [](mpfr_ptr o, double x, int, mpfr_rnd_t r) {
        setD(o, x);
        return mpfr_abs(o, o, r);
      },
      [](Gen&) { return 0; }, true, true);
}

TEST(IntervalMpfr, IntegerPower) {
  // Exponents: mostly small, some up to +-40, a few large ones. Bounds are checked for containment only (repeated
  // squaring widens by a few ulps per step).
  runUnary(
      "pow", 8, [](Interval a, int n) { return iv::pow(a, n); },
      [](mpfr_ptr o, double x, int n, mpfr_rnd_t r) {
        static Mp t(64);
        setD(t.v, x);
        return mpfr_pow_si(o, t.v, n, r);
      },
      [](Gen& g) {
        static constexpr int kLarge[] = {63, -63, 64, -64, 100, -100, 1000, -1001};
        switch (g.uniform(0, 9)) {
          case 0:
          case 1:
            return static_cast<int>(g.uniform(-40, 40));
          case 2:
            return kLarge[g.uniform(0, 7)];
          default:
            return static_cast<int>(g.uniform(-10, 10));
        }
      },
      true, false);
}

TEST(IntervalMpfr, AbsSecantBoundsTheMagnitudeExactly) {
  // |x| e <= weight x + offset for every x of the interval (checked exactly in MPFR at both ends, 0 and a random
  // interior point; |x| e - weight x is convex, so the ends decide), |weight| <= e, and offset no more than the
  // magnitude bound mag(a) e (a few ulps of slack for the roundings) nor than a few ulps where a has one sign.
  Gen g(20261203);
  Mp lhs(1200), rhs(1200), t(1200);  // every sum and product of these doubles is exact at 1200 bits
  const auto holdsAt = [&](double x, double e, const iv::AbsSecant& s) {
    mpfr_set_d(t.v, x, MPFR_RNDN);
    mpfr_abs(t.v, t.v, MPFR_RNDN);
    mpfr_mul_d(lhs.v, t.v, e, MPFR_RNDN);
    mpfr_set_d(t.v, x, MPFR_RNDN);
    mpfr_mul_d(rhs.v, t.v, s.weight, MPFR_RNDN);
    mpfr_add_d(rhs.v, rhs.v, s.offset, MPFR_RNDN);
    return mpfr_cmp(lhs.v, rhs.v) <= 0;
  };
  long failures = 0, cases = 0;  // NOLINT(runtime/int)
  for (int i = 0; i < 200000; ++i) {
    const double scale = std::ldexp(1.0, static_cast<int>(g.uniform(-30, 10)));
    const double centre = g.sign() * g.unit() * scale;
    const double radius = (i % 5 == 0 ? std::ldexp(g.unit(), -40) : g.unit()) * scale;
    const Interval a(centre - radius, centre + radius);
    const double e = g.unit() * std::ldexp(1.0, static_cast<int>(g.uniform(-25, 5)));
    const iv::AbsSecant s = iv::absSecant(a, e);
    ++cases;
    bool ok =
        std::abs(s.weight) <= e && s.offset >= 0.0 && s.offset <= rd::nextUp(rd::mulUp(a.mag(), e) * (1.0 + 1e-15));
    const double interior = a.lower() + g.unit() * (a.upper() - a.lower());
    for (const double x : {a.lower(), a.upper(), 0.0, interior})
      if (a.contains(x)) ok = ok && holdsAt(x, e, s);
    if (a.lower() >= 0.0 || a.upper() <= 0.0)
      ok = ok && s.offset <= 8.0 * std::numeric_limits<double>::epsilon() * a.mag() * e + 1e-300;
    if (!ok && ++failures <= 5)
      std::printf("absSecant([%.17g, %.17g], %.17g) = (%.17g, %.17g)\n", a.lower(), a.upper(), e, s.weight, s.offset);
  }
  EXPECT_EQ(failures, 0) << "of " << cases;
  // One sign, a point, symmetric (weight 0, offset the magnitude), unbounded.
  EXPECT_EQ(iv::absSecant(Interval(1.0, 2.0), 3.0).weight, 3.0);
  EXPECT_EQ(iv::absSecant(Interval(-2.0), 3.0).weight, -3.0);
  EXPECT_EQ(iv::absSecant(Interval(-2.0, -1.0), 3.0).weight, -3.0);
  EXPECT_EQ(iv::absSecant(Interval(-2.0, 2.0), 3.0).weight, 0.0);
  EXPECT_GE(iv::absSecant(Interval(-2.0, 2.0), 3.0).offset, 6.0);
  EXPECT_LE(iv::absSecant(Interval(-2.0, 2.0), 3.0).offset, 6.0 * (1.0 + 4.0 * std::numeric_limits<double>::epsilon()));
  EXPECT_TRUE(std::isinf(iv::absSecant(Interval(-1.0, std::numeric_limits<double>::infinity()), 1.0).offset));
}

}  // namespace
