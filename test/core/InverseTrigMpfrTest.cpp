// Interval atan2 / asin (interval/InverseTrig.hpp) against MPFR, and their Dual derivative rules.
//
//   * libm figures: the error of the point evaluations used (detail::libmAtan2 / libmAsin, round-to-nearest) in ulps
//     of the exact value, on >= 10^5 random arguments per function (uniform in value and in exponent, including
//     subnormals, huge ratios, signed zeros, the axes and +-1); must not exceed kInverseTrigUlpBound.
//   * containment: for random boxes (also straddling the axes, the branch cut, the origin, +-1, and outside
//     [-1, 1] for asin), computed under each of the four IEEE rounding modes, the exact values at the corners and at
//     random interior points lie in the result (MPFR, 200 bits, compared exactly); where no wrap is possible the
//     result is also tight: within 4 ulps of the exact range spanned by the corners.
//   * Dual rules: Dual<double> values and derivatives match the closed forms, and Dual<Interval> enclosures over
//     boxes contain the Dual<double> values and derivatives at random points.
#include <gmp.h>
#include <gtest/gtest.h>
#include <mpfr.h>

#include <algorithm>
#include <cfenv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "UlpContract.hpp"
#include "pkm_accuracy/core/interval/Dual.hpp"
#include "pkm_accuracy/core/interval/InverseTrig.hpp"

namespace {

using pkm_accuracy::interval::Interval;
namespace iv = pkm_accuracy::interval;
namespace rd = pkm_accuracy::interval::rounding;

constexpr int kModes[4] = {FE_TONEAREST, FE_UPWARD, FE_DOWNWARD, FE_TOWARDZERO};
constexpr mpfr_prec_t kPrec = 200;
constexpr double kInf = std::numeric_limits<double>::infinity();

class Gen {
 public:
  explicit Gen(std::uint64_t seed) : rng_(seed) {}
  double unit() { return static_cast<double>(rng_() >> 11) * 0x1p-53; }
  int uniform(int lo, int hi) { return lo + static_cast<int>(rng_() % static_cast<std::uint64_t>(hi - lo + 1)); }
  double sign() { return (rng_() & 1) ? -1.0 : 1.0; }
  /// sign * [1, 2) * 2^e, e uniform in [emin, emax].
  double scaled(int emin, int emax) { return sign() * std::ldexp(1.0 + unit(), uniform(emin, emax)); }
  /// A value of one of several kinds (plain, tiny, huge, subnormal, zero, special).
  double any() {
    switch (uniform(0, 9)) {
      case 0:
        return sign() * 0.0;
      case 1:
        return sign() * std::ldexp(unit(), -1074 + uniform(0, 60));  // subnormal
      case 2:
        return scaled(-1022, 1023);
      case 3: {
        static const double special[] = {
            1.0,       0.5,    2.0,  std::numeric_limits<double>::min(), std::numeric_limits<double>::max(),
            0x1p-1074, 1e-300, 1e300};
        return sign() * special[uniform(0, 7)];
      }
      default:
        return scaled(-30, 30);
    }
  }
  /// A point of [lo, hi].
  double inside(double lo, double hi) {
    const double t = unit();
    return std::min(std::max(lo * (1.0 - t) + hi * t, lo), hi);
  }

 private:
  std::mt19937_64 rng_;
};

struct Mp {
  mpfr_t v;
  Mp() { mpfr_init2(v, kPrec); }
  ~Mp() { mpfr_clear(v); }
  Mp(const Mp&) = delete;
  Mp& operator=(const Mp&) = delete;
};

/// Exact value bracketed by [down, up] at kPrec bits.
struct Bracket {
  Mp down, up;
  void atan2(double y, double x) {
    Mp my, mx;
    mpfr_set_d(my.v, y, MPFR_RNDN);
    mpfr_set_d(mx.v, x, MPFR_RNDN);
    mpfr_atan2(down.v, my.v, mx.v, MPFR_RNDD);
    mpfr_atan2(up.v, my.v, mx.v, MPFR_RNDU);
  }
  void asin(double x) {
    Mp mx;
    mpfr_set_d(mx.v, x, MPFR_RNDN);
    mpfr_asin(down.v, mx.v, MPFR_RNDD);
    mpfr_asin(up.v, mx.v, MPFR_RNDU);
  }
  bool within(const Interval& r) const {
    return !r.isEmpty() && mpfr_cmp_d(down.v, r.lower()) >= 0 && mpfr_cmp_d(up.v, r.upper()) <= 0;
  }
  /// |v - exact| in ulps of the exact value (binade of the exact value; subnormal ulp below DBL_MIN), rounded up: the
  /// exact y lies in [down, up], so |v - y| <= max(v - down, up - v), and ulp(y) is at least the ulp of the end
  /// nearer zero.
  double ulpError(double v) const {
    if (mpfr_zero_p(down.v) && mpfr_zero_p(up.v)) return v == 0.0 ? 0.0 : kInf;
    Mp diff, diff2;
    mpfr_set_d(diff.v, v, MPFR_RNDN);
    mpfr_sub(diff.v, diff.v, down.v, MPFR_RNDU);  // v - down
    mpfr_set_d(diff2.v, v, MPFR_RNDN);
    mpfr_sub(diff2.v, up.v, diff2.v, MPFR_RNDU);  // up - v
    mpfr_max(diff.v, diff.v, diff2.v, MPFR_RNDU);
    long e = -1074;  // NOLINT(runtime/int)
    if (!mpfr_zero_p(down.v) && !mpfr_zero_p(up.v))
      e = std::max<long>(std::min(mpfr_get_exp(down.v), mpfr_get_exp(up.v)) - 53, -1074);  // NOLINT(runtime/int)
    mpfr_mul_2si(diff.v, diff.v, -e, MPFR_RNDU);
    return mpfr_get_d(diff.v, MPFR_RNDU);
  }
  std::string str() const {
    char buf[200];
    mpfr_snprintf(buf, sizeof buf, "[%.22Rg, %.22Rg]", down.v, up.v);
    return buf;
  }
};

std::string hex(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", x);
  return buf;
}
std::string str(const Interval& r) {
  return r.isEmpty() ? "[empty]" : "[" + hex(r.lower()) + ", " + hex(r.upper()) + "]";
}

Interval atan2Under(int mode, const Interval& y, const Interval& x) {
  volatile double in[4] = {y.lower(), y.upper(), x.lower(), x.upper()};
  std::fesetround(mode);
  const Interval r =
      iv::atan2(Interval::fromBoundsUnchecked(in[0], in[1]), Interval::fromBoundsUnchecked(in[2], in[3]));
  volatile double out[2] = {r.lower(), r.upper()};
  const bool empty = r.isEmpty();
  std::fesetround(FE_TONEAREST);
  return empty ? Interval::empty() : Interval::fromBoundsUnchecked(out[0], out[1]);
}

Interval asinUnder(int mode, const Interval& x) {
  volatile double in[2] = {x.lower(), x.upper()};
  std::fesetround(mode);
  const Interval r = iv::asin(Interval::fromBoundsUnchecked(in[0], in[1]));
  volatile double out[2] = {r.lower(), r.upper()};
  const bool empty = r.isEmpty();
  std::fesetround(FE_TONEAREST);
  return empty ? Interval::empty() : Interval::fromBoundsUnchecked(out[0], out[1]);
}

/// A random interval of one of several shapes around random values.
Interval randomInterval(Gen& g) {
  double a = g.any(), b;
  switch (g.uniform(0, 4)) {
    case 0:
      b = a;  // degenerate
      break;
    case 1:
      b = a + g.scaled(-40, 0) * std::max(std::fabs(a), 1e-300);  // narrow
      break;
    case 2:
      b = g.any();
      break;
    case 3:
      b = -a;  // symmetric: straddles zero
      break;
    default:
      b = g.scaled(-3, 3);
  }
  if (!std::isfinite(b)) b = a;
  return Interval::hullOf(a, b);
}

// ---- libm accuracy ----------------------------------------------------------------------------------------------
TEST(InverseTrigMpfr, LibmAtan2AndAsinWithinTheUlpBound) {
  Gen g(20261122);
  Bracket e;
  double worstAtan2 = 0.0, worstAsin = 0.0;
  std::string worstAtan2Case, worstAsinCase;
  constexpr int kCases = 120000;
  for (int i = 0; i < kCases; ++i) {
    const double y = i % 3 == 0 ? g.any() : g.scaled(-20, 20);
    const double x = i % 3 == 1 ? g.any() : (i % 7 == 0 ? g.sign() * 0.0 : g.scaled(-20, 20));
    e.atan2(y, x);
    const double v = iv::detail::libmAtan2(y, x);
    const double err = e.ulpError(v);
    if (err > worstAtan2) {
      worstAtan2 = err;
      worstAtan2Case = "atan2(" + hex(y) + ", " + hex(x) + ")";
    }
    ASSERT_LE(err, iv::kInverseTrigUlpBound)
        << "atan2(" << hex(y) << ", " << hex(x) << ") = " << hex(v) << " exact " << e.str();
  }
  for (int i = 0; i < kCases; ++i) {
    double x;
    switch (i % 4) {
      case 0:
        x = g.sign() * g.unit();  // uniform in [-1, 1]
        break;
      case 1:
        x = g.sign() * (1.0 - std::ldexp(g.unit(), -g.uniform(1, 53)));  // near +-1
        break;
      case 2:
        x = g.sign() * std::ldexp(1.0 + g.unit(), -g.uniform(1, 1074));  // tiny, subnormal
        break;
      default:
        x = g.any();
        if (!(std::fabs(x) <= 1.0)) x = g.sign();
    }
    e.asin(x);
    const double v = iv::detail::libmAsin(x);
    const double err = e.ulpError(v);
    if (err > worstAsin) {
      worstAsin = err;
      worstAsinCase = "asin(" + hex(x) + ")";
    }
    ASSERT_LE(err, iv::kInverseTrigUlpBound) << "asin(" << hex(x) << ") = " << hex(v) << " exact " << e.str();
  }
  std::printf("[ figures  ] glibc atan2: max %.3f ulp (%s); asin: max %.3f ulp (%s); %d cases each\n", worstAtan2,
              worstAtan2Case.c_str(), worstAsin, worstAsinCase.c_str(), kCases);
}

// ---- interval atan2 ---------------------------------------------------------------------------------------------
bool wrapPossible(const Interval& y, const Interval& x) {
  return (y.containsZero() && x.containsZero()) || (x.lower() < 0.0 && y.lower() < 0.0 && y.upper() >= 0.0);
}

void checkAtan2Box(Gen& g, const Interval& y, const Interval& x, int mode) {
  const Interval r = atan2Under(mode, y, x);
  ASSERT_FALSE(r.isEmpty()) << str(y) << " " << str(x);
  Bracket e;
  const double pi = iv::piUpper();
  ASSERT_GE(r.lower(), -pi);
  ASSERT_LE(r.upper(), pi);
  const double ys[2] = {y.lower(), y.upper()}, xs[2] = {x.lower(), x.upper()};
  // Corners and interior points (a zero y is the point on the axis: +0, angle +pi on the negative x axis).
  Mp lo, hi;
  bool first = true;
  for (int c = 0; c < 6; ++c) {
    double yc = c < 4 ? ys[c & 1] : g.inside(y.lower(), y.upper());
    double xc = c < 4 ? xs[c >> 1] : g.inside(x.lower(), x.upper());
    if (yc == 0.0) yc = 0.0;
    if (xc == 0.0) xc = 0.0;
    if (yc == 0.0 && xc == 0.0) continue;  // the origin: no angle
    e.atan2(yc, xc);
    ASSERT_TRUE(e.within(r)) << "atan2(" << str(y) << ", " << str(x) << ") = " << str(r) << " misses the point ("
                             << hex(yc) << ", " << hex(xc) << ") with exact " << e.str() << " (mode " << mode << ")";
    if (c < 4) {
      if (first || mpfr_cmp(e.down.v, lo.v) < 0) mpfr_set(lo.v, e.down.v, MPFR_RNDN);
      if (first || mpfr_cmp(e.up.v, hi.v) > 0) mpfr_set(hi.v, e.up.v, MPFR_RNDN);
      first = false;
    }
  }
  if (!wrapPossible(y, x) && !first) {
    // Tight: within 4 ulps (of the result's magnitude) of the exact corner range.
    double l = r.lower(), h = r.upper();
    for (int i = 0; i < 4; ++i) {
      l = rd::nextUp(l);
      h = rd::nextDown(h);
    }
    EXPECT_TRUE(mpfr_cmp_d(lo.v, l) <= 0 || l > h)
        << "loose lower bound " << str(r) << " for " << str(y) << ", " << str(x);
    EXPECT_TRUE(mpfr_cmp_d(hi.v, h) >= 0 || l > h)
        << "loose upper bound " << str(r) << " for " << str(y) << ", " << str(x);
  } else if (wrapPossible(y, x)) {
    EXPECT_EQ(r.lower(), -pi);
    EXPECT_EQ(r.upper(), pi);
  }
}

TEST(InverseTrigMpfr, IntervalAtan2ContainsTheExactRange) {
  Gen g(7);
  int count = 0;
  for (int i = 0; i < 25000; ++i) {
    const Interval y = randomInterval(g), x = randomInterval(g);
    checkAtan2Box(g, y, x, kModes[i % 4]);
    ++count;
    if (HasFatalFailure()) return;
  }
  // Edge cases: axes, the branch cut from above / below, signed zeros, the origin, tiny and huge ratios.
  const double z = 0.0, mz = -0.0, tiny = 0x1p-1074, big = std::numeric_limits<double>::max();
  const std::vector<std::pair<Interval, Interval>> edges = {
      {Interval(z), Interval(-2.0, -1.0)},
      {Interval(mz), Interval(-2.0, -1.0)},
      {Interval(0.0, 1.0), Interval(-2.0, -1.0)},
      {Interval::fromBoundsUnchecked(mz, 1.0), Interval(-2.0, -1.0)},
      {Interval(-1.0, 0.0), Interval(-2.0, -1.0)},
      {Interval(-1.0, -tiny), Interval(-2.0, -1.0)},
      {Interval(tiny), Interval(-1.0)},
      {Interval(-tiny), Interval(-1.0)},
      {Interval(-1.0, 1.0), Interval(1.0, 2.0)},
      {Interval(-1.0, 1.0), Interval(0.0, 2.0)},
      {Interval(1.0, 2.0), Interval(-1.0, 1.0)},
      {Interval(-2.0, -1.0), Interval(-1.0, 1.0)},
      {Interval(0.0), Interval(0.0)},
      {Interval(0.0, 1.0), Interval(0.0, 1.0)},
      {Interval(tiny, big), Interval(tiny, big)},
      {Interval(-big, -tiny), Interval(-big, big)},
      {Interval(1e-300), Interval(1e300)},
      {Interval(1e300), Interval(-1e-300)},
      {Interval(1.0), Interval(0.0)},
      {Interval(-1.0), Interval(mz)},
  };
  for (const auto& c : edges) {
    for (int mode : kModes) {
      checkAtan2Box(g, c.first, c.second, mode);
      ++count;
      if (HasFatalFailure()) return;
    }
  }
  // Unbounded or empty operands.
  EXPECT_EQ(iv::atan2(Interval(1.0, kInf), Interval(1.0)), Interval(-iv::piUpper(), iv::piUpper()));
  EXPECT_TRUE(iv::atan2(Interval::empty(), Interval(1.0)).isEmpty());
  EXPECT_TRUE(iv::atan2(Interval(1.0), Interval::empty()).isEmpty());
  std::printf("[ figures  ] interval atan2: %d boxes checked under 4 rounding modes\n", count);
}

// ---- interval asin ----------------------------------------------------------------------------------------------
TEST(InverseTrigMpfr, IntervalAsinContainsTheExactRange) {
  Gen g(11);
  Bracket e;
  int count = 0;
  auto check = [&](const Interval& x, int mode) {
    const Interval r = asinUnder(mode, x);
    const Interval d = intersect(x, Interval(-1.0, 1.0));
    if (d.isEmpty()) {
      EXPECT_TRUE(r.isEmpty()) << str(x);
      return;
    }
    ASSERT_FALSE(r.isEmpty()) << str(x);
    EXPECT_GE(r.lower(), -iv::halfPiUpper());
    EXPECT_LE(r.upper(), iv::halfPiUpper());
    for (int c = 0; c < 4; ++c) {
      const double p = c == 0 ? d.lower() : c == 1 ? d.upper() : g.inside(d.lower(), d.upper());
      e.asin(p);
      ASSERT_TRUE(e.within(r)) << "asin(" << str(x) << ") = " << str(r) << " misses " << hex(p) << " exact " << e.str();
    }
    // Tight: within 4 ulps of the exact endpoint values.
    Bracket elo, ehi;
    elo.asin(d.lower());
    ehi.asin(d.upper());
    double l = r.lower(), h = r.upper();
    for (int i = 0; i < 4; ++i) {
      l = rd::nextUp(l);
      h = rd::nextDown(h);
    }
    EXPECT_TRUE(mpfr_cmp_d(elo.down.v, l) <= 0 || l > h) << str(x) << " -> " << str(r);
    EXPECT_TRUE(mpfr_cmp_d(ehi.up.v, h) >= 0 || l > h) << str(x) << " -> " << str(r);
    ++count;
  };
  for (int i = 0; i < 25000; ++i) {
    Interval x = randomInterval(g);
    if (i % 2 == 0) {  // mostly inside [-1, 1]
      const double a = g.sign() * g.unit(), b = g.sign() * g.unit();
      x = i % 4 == 0 ? Interval::hullOf(a, b) : Interval::hullOf(a, a + g.scaled(-50, -1) * g.sign());
    }
    check(x, kModes[i % 4]);
    if (HasFatalFailure()) return;
  }
  const double tiny = 0x1p-1074;
  for (const Interval& x : {Interval(1.0), Interval(-1.0), Interval(-1.0, 1.0), Interval(0.0), Interval(-0.0),
                            Interval(-tiny, tiny), Interval(1.0, 2.0), Interval(-3.0, -1.0), Interval(0.5, 7.0),
                            Interval(-kInf, kInf), Interval(rd::nextDown(1.0), 1.0), Interval(-1e-300, 1e-300)}) {
    for (int mode : kModes) check(x, mode);
  }
  EXPECT_TRUE(iv::asin(Interval(1.5, 2.0)).isEmpty());
  EXPECT_TRUE(iv::asin(Interval::empty()).isEmpty());
  std::printf("[ figures  ] interval asin: %d intervals checked under 4 rounding modes\n", count);
}

// ---- the widening covers the ulp bound across powers of two ------------------------------------------------------
// A libm value v within k = kInverseTrigUlpBound ulps of the exact value y (in ulps of y) stands for every y in
// S(v, k) = { y : |y - v| <= k ulp(y) } (test/core/UlpContract.hpp); the enclosure must contain S(v, k) inside the
// clamping range. Just below a power of two P in magnitude, S(v, k) reaches into the binade above P (ulp twice that
// of v), up to |v| + 2k ulp(v). The scans run over the doubles around sin(P) (asin), tan(P) (atan2(y, 1)) and
// 1 / tan(P) (atan2(1, x), P = 2), where the libm values step by about one ulp or less and so land in every ulp just
// below P; the boxes are [t_prev, t] of consecutive scan points, cycling the four rounding modes. Each scan must
// reach the binade above P.
TEST(InverseTrigMpfr, EnclosuresCoverTheUlpBoundAcrossPowersOfTwo) {
  const int k = iv::kInverseTrigUlpBound;
  pkm_accuracy::test::UlpContract s;
  auto around = [](double x0, int n) {
    std::vector<double> xs;
    double x = x0;
    for (int i = 0; i < n; ++i) x = rd::nextDown(x);
    for (int i = 0; i <= 2 * n; ++i, x = rd::nextUp(x)) xs.push_back(x);
    return xs;
  };
  enum class F { kAsin, kAtan2Y, kAtan2X };  // asin(t), atan2(t, 1), atan2(1, t)
  struct Scan {
    std::string what;
    F f;
    std::vector<double> ts;
  };
  std::vector<Scan> scans;
  for (double p : {1.0, 0.5, 0.25}) {
    for (double sign : {1.0, -1.0}) {
      const std::string ps = (sign > 0 ? "+" : "-") + hex(p);
      scans.push_back({"asin near " + ps, F::kAsin, around(sign * std::sin(p), 64)});
      scans.push_back({"atan2(y, 1) near " + ps, F::kAtan2Y, around(sign * std::tan(p), 64)});
    }
  }
  scans.push_back({"atan2(1, x) near 2", F::kAtan2X, around(1.0 / std::tan(2.0), 64)});
  long checks = 0, failures = 0;  // NOLINT(runtime/int)
  std::vector<std::string> messages;
  int mode = 0;
  for (const Scan& scan : scans) {
    int reaching = 0;
    for (std::size_t i = 1; i < scan.ts.size(); ++i) {
      const double a = scan.ts[i - 1], b = scan.ts[i];
      Interval r;
      double va, vb, range;
      if (scan.f == F::kAsin) {
        r = asinUnder(kModes[mode], Interval(a, b));
        va = iv::detail::libmAsin(a);
        vb = iv::detail::libmAsin(b);
        range = iv::halfPiUpper();
      } else if (scan.f == F::kAtan2Y) {
        r = atan2Under(kModes[mode], Interval(a, b), Interval(1.0));
        va = iv::detail::libmAtan2(a, 1.0);
        vb = iv::detail::libmAtan2(b, 1.0);
        range = iv::piUpper();
      } else {
        r = atan2Under(kModes[mode], Interval(1.0), Interval(a, b));
        va = iv::detail::libmAtan2(1.0, a);
        vb = iv::detail::libmAtan2(1.0, b);
        range = iv::piUpper();
      }
      const std::string where = scan.what + " (mode " + std::to_string(mode) + "), [" + hex(a) + ", " + hex(b) + "]";
      mode = (mode + 1) % 4;
      for (double v : {va, vb}) {
        ASSERT_TRUE(s.set(v, k)) << hex(v);
        if (s.reachesLargerBinade()) ++reaching;
        std::string why;
        ++checks;
        if (!s.coveredBy(r.lower(), r.upper(), -range, range, &why)) {
          ++failures;
          if (messages.size() < 10) messages.push_back(where + ": libm value " + hex(v) + " -> " + str(r) + why);
        }
      }
    }
    EXPECT_GT(reaching, 0) << scan.what << ": no libm value whose ulp contract reaches the binade above";
  }
  for (const std::string& m : messages) ADD_FAILURE() << m;
  EXPECT_EQ(failures, 0) << "of " << checks;
  std::printf("[ figures  ] %ld atan2 / asin enclosures checked against the ulp contract near powers of two\n", checks);
}

// ---- Dual rules -------------------------------------------------------------------------------------------------
TEST(InverseTrigDual, PointDerivativesMatchClosedFormsAndIntervalsEncloseThem) {
  using DD = iv::Dual<double, 2>;
  using DI = iv::Dual<Interval, 2>;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> uni(-2.0, 2.0), w(0.0, 0.3);
  for (int i = 0; i < 20000; ++i) {
    // y = a + b s, x = c + d s^2 as functions of (s, r); evaluated at a point and over a box around it.
    const double a = uni(rng), b = uni(rng), c = uni(rng), d = uni(rng), s0 = uni(rng), r0 = uni(rng);
    const double hs = w(rng), hr = w(rng);
    const Interval sb(s0 - hs, s0 + hs), rb(r0 - hr, r0 + hr);
    std::uniform_real_distribution<double> ps(sb.lower(), sb.upper()), pr(rb.lower(), rb.upper());
    const double s = ps(rng), r = pr(rng);
    const DD S = DD::variable(s, 0), R = DD::variable(r, 1);
    const DD y = a + b * S + R * R * 0.5, x = c + d * S * S;
    const DD at = iv::atan2(y, x);
    const double yv = a + b * s + 0.5 * r * r, xv = c + d * s * s;
    if (xv * xv + yv * yv < 1e-6) continue;
    EXPECT_NEAR(at.value(), std::atan2(yv, xv), 1e-15);
    const double den = xv * xv + yv * yv;
    EXPECT_NEAR(at.d(0), (xv * b - yv * 2.0 * d * s) / den, 1e-9 * (1.0 + std::fabs(at.d(0))));
    EXPECT_NEAR(at.d(1), (xv * r) / den, 1e-9 * (1.0 + std::fabs(at.d(1))));

    const DI SI = DI::variable(sb, 0), RI = DI::variable(rb, 1);
    const DI yi = a + b * SI + RI * RI * 0.5, xi = c + d * SI * SI;
    const DI ati = iv::atan2(yi, xi);
    EXPECT_TRUE(ati.value().contains(at.value())) << ati.value() << " " << at.value();
    EXPECT_TRUE(ati.d(0).contains(at.d(0)) || !ati.d(0).isBounded()) << ati.d(0) << " " << at.d(0);
    EXPECT_TRUE(ati.d(1).contains(at.d(1)) || !ati.d(1).isBounded()) << ati.d(1) << " " << at.d(1);

    // asin of a value in (-1, 1): z = 0.4 sin(s) + 0.3 r.
    const DD zd = 0.4 * sin(S) + 0.3 * R;
    const DD as = iv::asin(zd);
    const double zv = 0.4 * std::sin(s) + 0.3 * r;
    if (std::fabs(zv) >= 0.999) continue;
    EXPECT_NEAR(as.value(), std::asin(zv), 1e-15);
    EXPECT_NEAR(as.d(0), 0.4 * std::cos(s) / std::sqrt(1.0 - zv * zv), 1e-9);
    EXPECT_NEAR(as.d(1), 0.3 / std::sqrt(1.0 - zv * zv), 1e-9);
    const DI zi = 0.4 * sin(SI) + 0.3 * RI;
    const DI asi = iv::asin(zi);
    EXPECT_TRUE(asi.value().contains(as.value()));
    EXPECT_TRUE(asi.d(0).contains(as.d(0)) || !asi.d(0).isBounded());
    EXPECT_TRUE(asi.d(1).contains(as.d(1)) || !asi.d(1).isBounded());
  }
}

}  // namespace
