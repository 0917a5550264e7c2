// Containment of the segment affine forms (interval::SegmentAffineForm: +, -, *, scalar *, sqrt, reciprocal, sin,
// cos) against MPFR, cycling through the four IEEE rounding modes: random operands over 6 noise symbols (built through
// the public operations, so that both parts of their remainders are non-zero), and points tau = s tau^ of the segments
// from the centre (tau^ corners of [-1, 1]^6 or random, s in {0, 1e-3, 0.1, 0.5, 1} or random). At such a point an
// operand may take any value within r0 + s^2 r2 of its linear part; the exact result (MPFR, 200 bits) must lie within
// the output's r0 + s^2 r2 of the output's linear part. Also: at the centre only the constant part remains (a product
// of two variables is exact there up to rounding), and the whole-box radius r0 + r2 stays within the plain first-order
// bound of the product.
#include <gtest/gtest.h>
#include <mpfr.h>

#include <cfenv>
#include <cmath>
#include <random>
#include <string>

#include "MpfrGough.hpp"
#include "pkm_accuracy/core/interval/SegmentAffineForm.hpp"

namespace {

using pkm_accuracy::interval::Interval;
using pkm_accuracy::test::Mp;  // MPFR at 200 bits (MpfrGough.hpp)
constexpr int kN = 6;
using Seg = pkm_accuracy::interval::SegmentAffineForm<kN>;

class Gen {
 public:
  explicit Gen(unsigned seed) : rng_(seed) {}
  double unit() { return std::uniform_real_distribution<double>(0.0, 1.0)(rng_); }
  double sign() { return unit() < 0.5 ? -1.0 : 1.0; }
  /// A form with centre of magnitude ~ 2^[-4, 4] (positive and above its deviation when `positive`), coefficients up
  /// to 0.3 of the centre, and both remainder parts: a product of variables (r2) and an interval constant (r0).
  Seg form(bool positive) {
    const double c = (positive ? 1.0 : sign()) * std::ldexp(0.5 + unit(), static_cast<int>(unit() * 8) - 4);
    Seg f(c);
    double budget = std::abs(c) * 0.5;
    for (int m = 0; m < kN; ++m) {
      if (unit() < 0.25) continue;
      const double a = sign() * budget * 0.3 * unit();
      budget -= std::abs(a);
      f = f + Seg::variable(Interval(-1.0, 1.0), m) * a;
    }
    if (unit() < 0.7) {  // a nonlinear part: a product of two variables
      const double q = budget * 0.3 * unit();
      budget -= q;
      f = f + Seg::variable(Interval(-1.0, 1.0), static_cast<int>(unit() * kN)) *
                  Seg::variable(Interval(-1.0, 1.0), static_cast<int>(unit() * kN)) * q;
    }
    if (unit() < 0.5) {
      const double r = budget * 0.2 * unit();
      f = f + Seg(Interval(-r, r));
    }
    return f;
  }
  double symbol() {
    const double u = unit();
    return u < 0.25 ? -1.0 : (u < 0.5 ? 1.0 : 2.0 * unit() - 1.0);
  }
  double scale() {
    const double u = unit();
    return u < 0.15 ? 0.0 : (u < 0.3 ? 1e-3 : (u < 0.45 ? 0.1 : (u < 0.6 ? 0.5 : (u < 0.75 ? 1.0 : unit()))));
  }

 private:
  std::mt19937_64 rng_;
};

/// The linear part of f at tau, in MPFR.
Mp linearAt(const Seg& f, const double* tau) {
  Mp v(f.centre());
  for (int m = 0; m < kN; ++m) v = v + Mp(f.coefficient(m)) * Mp(tau[m]);
  return v;
}
/// A value the form allows at tau = s tau^: its linear part plus eps (r0 + s^2 r2), eps in [-1, 1].
Mp valueAt(const Seg& f, const double* tau, double s, double eps) {
  return linearAt(f, tau) + (Mp(f.constantRadius()) + Mp(s) * Mp(s) * Mp(f.quadraticRadius())) * Mp(eps);
}
/// |exact - linear part| <= r0 + s^2 r2, in MPFR.
bool contains(const Seg& f, const double* tau, double s, const Mp& exact) {
  const Mp gap = pkm_accuracy::test::mpAbs(exact - linearAt(f, tau));
  const Mp allowed = Mp(f.constantRadius()) + Mp(s) * Mp(s) * Mp(f.quadraticRadius());
  return pkm_accuracy::test::mpLessEqual(gap - allowed, 0.0);
}

}  // namespace

TEST(SegmentAffineFormMpfr, OperationsContainTheExactResultsOnEverySegmentInEveryRoundingMode) {
  const int modes[4] = {FE_TONEAREST, FE_UPWARD, FE_DOWNWARD, FE_TOWARDZERO};
  Gen gen(23);
  long checked = 0;  // NOLINT(runtime/int)
  const int cases = 3000;
  for (int c = 0; c < cases; ++c) {
    const bool positive = c % 2 == 0;  // sqrt and reciprocal need positive operands
    const Seg x = gen.form(positive), y = gen.form(false);
    const double k = gen.sign() * std::ldexp(0.5 + gen.unit(), static_cast<int>(gen.unit() * 6) - 3);
    const int saved = std::fegetround();
    std::fesetround(modes[c % 4]);
    const Seg sum = x + y, diff = x - y, prod = x * y, square = x * x, scaled = x * k, neg = -x;
    const Seg root = positive ? sqrt(x) : Seg(0.0), inv = positive ? reciprocal(x) : Seg(0.0);
    const Seg sine = sin(x), cosine = cos(x);
    std::fesetround(saved);
    for (const Seg* f : {&sum, &diff, &prod, &square, &scaled, &neg, &root, &inv, &sine, &cosine})
      ASSERT_TRUE(f->finite());
    for (int sample = 0; sample < 8; ++sample) {
      const double s = gen.scale();
      double tau[kN];
      for (int m = 0; m < kN; ++m) tau[m] = s * gen.symbol();
      const double ex = gen.symbol(), ey = gen.symbol();
      const Mp xv = valueAt(x, tau, s, ex), yv = valueAt(y, tau, s, ey);
      const std::string at =
          "case " + std::to_string(c) + " sample " + std::to_string(sample) + " s " + std::to_string(s);
      ASSERT_TRUE(contains(sum, tau, s, xv + yv)) << at;
      ASSERT_TRUE(contains(diff, tau, s, xv - yv)) << at;
      ASSERT_TRUE(contains(prod, tau, s, xv * yv)) << at;
      ASSERT_TRUE(contains(square, tau, s, xv * xv)) << at;
      ASSERT_TRUE(contains(scaled, tau, s, xv * Mp(k))) << at;
      ASSERT_TRUE(contains(neg, tau, s, Mp(0.0) - xv)) << at;
      if (positive) {
        ASSERT_TRUE(contains(root, tau, s, pkm_accuracy::test::mpSqrt(xv))) << at;
        ASSERT_TRUE(contains(inv, tau, s, Mp(1.0) / xv)) << at;
      }
      ASSERT_TRUE(contains(sine, tau, s, pkm_accuracy::test::mpSin(xv))) << at;
      ASSERT_TRUE(contains(cosine, tau, s, pkm_accuracy::test::mpCos(xv))) << at;
      ++checked;
    }
    // Not trivially wide: over the whole box the product is within the plain first-order bound.
    const double plain =
        std::abs(x.centre()) * y.radius() + std::abs(y.centre()) * x.radius() + x.deviation() * y.deviation();
    ASSERT_LE(prod.radius(),
              plain * (1.0 + 1e-10) + 1e-14 * (std::abs(x.centre()) + 1.0) * (std::abs(y.centre()) + 1.0));
  }
  EXPECT_EQ(checked, 8L * cases);
}

TEST(SegmentAffineFormMpfr, TheNonlinearityVanishesQuadraticallyAtTheCentre) {
  // x = 1 + 0.5 tau_0, y = 2 - 0.25 tau_1: x y = 2 + tau_0 - 0.25 tau_1 - 0.125 tau_0 tau_1, whose nonlinear part is
  // at most 0.125 s^2 on the segment at s: r2 = 0.125 and r0 only the rounding; 1 / x has r2 = M / 2 0.25 with
  // M = 2 / 0.5^3 the largest |f''| over the range, and is exact at the centre up to rounding.
  const Seg x = Seg(1.0) + Seg::variable(Interval(-1.0, 1.0), 0) * 0.5;
  const Seg y = Seg(2.0) - Seg::variable(Interval(-1.0, 1.0), 1) * 0.25;
  const Seg p = x * y;
  EXPECT_EQ(p.centre(), 2.0);
  EXPECT_NEAR(p.coefficient(0), 1.0, 1e-11);  // (variable() rounds its coefficient up by 1e-12)
  EXPECT_NEAR(p.coefficient(1), -0.25, 1e-11);
  EXPECT_NEAR(p.quadraticRadius(), 0.125, 1e-12);
  EXPECT_LT(p.constantRadius(), 1e-13);
  const Seg inv = reciprocal(x);
  EXPECT_NEAR(inv.centre(), 1.0, 1e-15);
  EXPECT_NEAR(inv.coefficient(0), -0.5, 1e-11);
  EXPECT_NEAR(inv.quadraticRadius(), 0.5 * 16.0 * 0.25, 1e-9);
  EXPECT_LT(inv.constantRadius(), 1e-13);
  // At s = 1/4 the true deviation of 1 / x from its tangent, 1 / (1 + 0.125) - (1 - 0.125) = 0.0139, lies within
  // r0 + r2 / 16 = 0.125, and at s = 1 within 2.0.
  const double tau[kN] = {0.25, 0.0, 0.0, 0.0, 0.0, 0.0};
  EXPECT_TRUE(contains(inv, tau, 0.25, Mp(1.0) / Mp(1.125)));
}
