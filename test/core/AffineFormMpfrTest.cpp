// Containment of the first-order affine forms (interval::AffineForm: +, -, *, scalar *, sqrt, reciprocal, sin, cos)
// against MPFR: random forms over 6 noise symbols, cycling through the four IEEE rounding modes. For values of the
// noise symbols tau (corners of [-1, 1]^6 and random points) and of the operands' own radius parts, the exact
// operands and the exact result are computed in MPFR (200 bits), and the result must lie within the output form's
// radius of its linear part at the same tau, compared in MPFR. Also: the forms are not trivially wide (the product's
// radius is below the plain bound dev(x) dev(y) plus the linear parts' rounding terms), and variable() covers its
// interval.
#include <gtest/gtest.h>
#include <mpfr.h>

#include <cfenv>
#include <cmath>
#include <functional>
#include <random>

#include "MpfrGough.hpp"
#include "pkm_accuracy/core/interval/AffineForm.hpp"

namespace {

using pkm_accuracy::interval::Interval;
using pkm_accuracy::test::Mp;  // MPFR at 200 bits (MpfrGough.hpp)
constexpr int kN = 6;
using Aff = pkm_accuracy::interval::AffineForm<kN>;

class Gen {
 public:
  explicit Gen(unsigned seed) : rng_(seed) {}
  double unit() { return std::uniform_real_distribution<double>(0.0, 1.0)(rng_); }
  double sign() { return unit() < 0.5 ? -1.0 : 1.0; }
  /// A form whose centre has magnitude ~ 2^[-4, 4] (positive when `positive`, and then > its deviation), with
  /// coefficients of relative size up to 0.3 (some zero) and a radius (sometimes zero), built through the public
  /// operations (sums of scaled variables and an interval constant).
  Aff form(bool positive) {
    const double c = (positive ? 1.0 : sign()) * std::ldexp(0.5 + unit(), static_cast<int>(unit() * 8) - 4);
    Aff f(c);
    double budget = std::abs(c) * 0.6;
    for (int m = 0; m < kN; ++m) {
      if (unit() < 0.25) continue;
      const double a = sign() * budget * 0.3 * unit();
      budget -= std::abs(a);
      f = f + Aff::variable(Interval(-1.0, 1.0), m) * a;
    }
    if (unit() < 0.7) {
      const double r = budget * 0.3 * unit();
      f = f + Aff(Interval(-r, r));
    }
    return f;
  }
  /// A point of [-1, 1]: the corners often, else uniform.
  double symbol() {
    const double u = unit();
    return u < 0.2 ? -1.0 : (u < 0.4 ? 1.0 : 2.0 * unit() - 1.0);
  }

 private:
  std::mt19937_64 rng_;
};

/// The exact value c + sum_m a_m tau_m + rad * eps of a form at (tau, eps), in MPFR.
Mp valueAt(const Aff& f, const double* tau, double eps) {
  Mp v(f.centre());
  for (int m = 0; m < kN; ++m) v = v + Mp(f.coefficient(m)) * Mp(tau[m]);
  return v + Mp(f.radius()) * Mp(eps);
}

/// |exact - linear part of f at tau| <= f.radius(), in MPFR.
bool contains(const Aff& f, const double* tau, const Mp& exact) {
  Mp lin(f.centre());
  for (int m = 0; m < kN; ++m) lin = lin + Mp(f.coefficient(m)) * Mp(tau[m]);
  const Mp gap = pkm_accuracy::test::mpAbs(exact - lin);
  return pkm_accuracy::test::mpLessEqual(gap, f.radius());
}

}  // namespace

TEST(AffineFormMpfr, OperationsContainTheExactResultsInEveryRoundingMode) {
  const int modes[4] = {FE_TONEAREST, FE_UPWARD, FE_DOWNWARD, FE_TOWARDZERO};
  Gen gen(17);
  long checked = 0;  // NOLINT(runtime/int)
  const int cases = 4000;
  for (int c = 0; c < cases; ++c) {
    const bool positive = c % 2 == 0;  // sqrt and reciprocal need positive operands
    const Aff x = gen.form(positive), y = gen.form(false);
    const double s = gen.sign() * std::ldexp(0.5 + gen.unit(), static_cast<int>(gen.unit() * 6) - 3);
    const int saved = std::fegetround();
    std::fesetround(modes[c % 4]);
    const Aff sum = x + y, diff = x - y, prod = x * y, square = x * x, scaled = x * s, neg = -x;
    const Aff root = positive ? sqrt(x) : Aff(0.0), inv = positive ? reciprocal(x) : Aff(0.0);
    const Aff sine = sin(x), cosine = cos(x);
    std::fesetround(saved);
    for (const Aff* f : {&sum, &diff, &prod, &square, &scaled, &neg, &root, &inv, &sine, &cosine})
      ASSERT_TRUE(f->finite());
    for (int sample = 0; sample < 8; ++sample) {
      double tau[kN];
      for (int m = 0; m < kN; ++m) tau[m] = gen.symbol();
      const double ex = gen.symbol(), ey = gen.symbol();
      const Mp xv = valueAt(x, tau, ex), yv = valueAt(y, tau, ey);
      const std::string at = "case " + std::to_string(c) + " sample " + std::to_string(sample);
      ASSERT_TRUE(contains(sum, tau, xv + yv)) << at;
      ASSERT_TRUE(contains(diff, tau, xv - yv)) << at;
      ASSERT_TRUE(contains(prod, tau, xv * yv)) << at;
      ASSERT_TRUE(contains(square, tau, xv * xv)) << at;
      ASSERT_TRUE(contains(scaled, tau, xv * Mp(s))) << at;
      ASSERT_TRUE(contains(neg, tau, Mp(0.0) - xv)) << at;
      if (positive) {
        ASSERT_TRUE(contains(root, tau, pkm_accuracy::test::mpSqrt(xv))) << at;
        ASSERT_TRUE(contains(inv, tau, Mp(1.0) / xv)) << at;
      }
      ASSERT_TRUE(contains(sine, tau, pkm_accuracy::test::mpSin(xv))) << at;
      ASSERT_TRUE(contains(cosine, tau, pkm_accuracy::test::mpCos(xv))) << at;
      ++checked;
    }
    // Not trivially wide: the product's radius is within the plain first-order bound (the square terms' mean only
    // tightens it), up to the rounding terms.
    const double plain =
        std::abs(x.centre()) * y.radius() + std::abs(y.centre()) * x.radius() + x.deviation() * y.deviation();
    ASSERT_LE(prod.radius(),
              plain * (1.0 + 1e-10) + 1e-14 * (std::abs(x.centre()) + 1.0) * (std::abs(y.centre()) + 1.0));
  }
  EXPECT_EQ(checked, 8L * cases);
}

TEST(AffineFormMpfr, SquareTermsKeepTheirMean) {
  // x = 1 + 0.5 tau_0: x^2 = 1 + tau_0 + 0.25 tau_0^2 with 0.25 tau_0^2 in [0, 0.25], so the form is
  // 1.125 + tau_0 +- 0.125, exact at tau_0 = -1, 0, 1 (the plain bound would give 1 + tau_0 +- 0.25). (Its range
  // [0, 2.25] is wider than that of x^2, [0.25, 2.25]: tau_0 and tau_0^2 are not independent.)
  const Aff x = Aff(1.0) + Aff::variable(Interval(-1.0, 1.0), 0) * 0.5;
  const Aff sq = x * x;
  EXPECT_NEAR(sq.centre(), 1.125, 1e-9);
  EXPECT_NEAR(sq.coefficient(0), 1.0, 1e-9);
  EXPECT_NEAR(sq.radius(), 0.125, 1e-9);
  EXPECT_NEAR(sq.toInterval().lower(), 0.0, 1e-9);
  EXPECT_NEAR(sq.toInterval().upper(), 2.25, 1e-9);
}

TEST(AffineFormMpfr, ConvexRemaindersAreOneSided) {
  // Where f'' keeps its sign over the range (1 / x and sqrt of positive forms, cos near 0), the Taylor remainder
  // f''(xi) (x - c)^2 / 2 has that sign: the form's centre carries half of its largest value and the radius the other
  // half. Checked in MPFR on x = c + a tau_0 at tau_0 in {-1, -1/2, 0, 1/2, 1} in every rounding mode: at tau_0 = 0
  // the exact value lies at one edge of the band and at tau_0 = -+1 near the other, so a shift of the wrong sign or a
  // radius of a quarter less fails; the radius is about half of the symmetric remainder's.
  const int modes[4] = {FE_TONEAREST, FE_UPWARD, FE_DOWNWARD, FE_TOWARDZERO};
  const double taus[5] = {-1.0, -0.5, 0.0, 0.5, 1.0};
  for (int mode = 0; mode < 4; ++mode) {
    for (const double rel : {0.05, 0.2, 0.4}) {
      const double c = 1.5, a = rel * c;
      const Aff x = Aff(c) + Aff::variable(Interval(-1.0, 1.0), 0) * a;
      const int saved = std::fegetround();
      std::fesetround(modes[mode]);
      const Aff inv = reciprocal(x), root = sqrt(x), cosine = cos(x * (0.2 / c));
      std::fesetround(saved);
      for (const double t : taus) {
        double tau[kN] = {t, 0.0, 0.0, 0.0, 0.0, 0.0};
        const Mp xv = Mp(c) + Mp(a) * Mp(t);
        ASSERT_TRUE(contains(inv, tau, Mp(1.0) / xv)) << rel << " " << t;
        ASSERT_TRUE(contains(root, tau, pkm_accuracy::test::mpSqrt(xv))) << rel << " " << t;
        ASSERT_TRUE(contains(cosine, tau, pkm_accuracy::test::mpCos(xv * Mp(0.2 / c)))) << rel << " " << t;
      }
      // 1 / x: f'' = 2 / x^3 over [c - a, c + a], symmetric remainder M a^2 / 2; one-sided: M a^2 / 4.
      const double m = 2.0 / std::pow(c - a, 3);
      EXPECT_LT(inv.radius(), 0.26 * m * a * a) << rel;
      EXPECT_GT(inv.radius(), 0.24 * m * a * a) << rel;
    }
  }
}

TEST(AffineFormMpfr, VariableCoversItsInterval) {
  Gen gen(5);
  for (int c = 0; c < 1000; ++c) {
    const double lo = gen.sign() * std::ldexp(gen.unit(), static_cast<int>(gen.unit() * 10) - 5);
    const double hi = lo + std::ldexp(gen.unit(), static_cast<int>(gen.unit() * 10) - 8);
    const Aff v = Aff::variable(Interval(lo, hi), c % kN);
    for (double t : {lo, hi}) {
      const Mp gap = pkm_accuracy::test::mpAbs(Mp(t) - Mp(v.centre()));
      ASSERT_TRUE(pkm_accuracy::test::mpLessEqual(gap, v.coefficient(c % kN))) << lo << " " << hi;
    }
    for (int m = 0; m < kN; ++m) {
      if (m != c % kN) {
        ASSERT_EQ(v.coefficient(m), 0.0);
      }
    }
    ASSERT_EQ(v.radius(), 0.0);
  }
}
