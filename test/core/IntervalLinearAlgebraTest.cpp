// Interval linear algebra: products (interval and midpoint-radius) and Gauss elimination contain the exact results
// for point matrices drawn from the interval matrices; exact values by MPFR (200 bits).
#include <gtest/gtest.h>
#include <mpfr.h>

#include <cfenv>
#include <random>

#include <Eigen/LU>

#include "MpfrGough.hpp"
#include "pkm_accuracy/core/enclosure/IntervalLinearAlgebra.hpp"

using namespace pkm_accuracy;
using enclosure::multiply;
using enclosure::multiplyMidRad;

namespace {

IMat randomIntervalMatrix(std::mt19937_64& rng, int n, double scale, double width) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), w(0.0, 1.0);
  IMat a(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double m = scale * u(rng), h = width * scale * w(rng);
      a(i, j) = Interval(m - h, m + h);
    }
  return a;
}

DMat pointIn(const IMat& a, std::mt19937_64& rng) {
  DMat p(a.rows(), a.cols());
  for (int i = 0; i < a.rows(); ++i)
    for (int j = 0; j < a.cols(); ++j) {
      std::uniform_real_distribution<double> u(a(i, j).lower(), a(i, j).upper());
      p(i, j) = (rng() % 4 == 0) ? (rng() % 2 ? a(i, j).lower() : a(i, j).upper()) : u(rng);
    }
  return p;
}

// Exact (200-bit) entry (i, j) of X Y compared with an interval.
bool exactProductInside(const DMat& x, const DMat& y, int i, int j, const Interval& iv) {
  mpfr_t s, t;
  mpfr_inits2(200, s, t, static_cast<mpfr_ptr>(nullptr));
  mpfr_set_zero(s, 1);
  for (int k = 0; k < x.cols(); ++k) {
    mpfr_set_d(t, x(i, k), MPFR_RNDN);
    mpfr_mul_d(t, t, y(k, j), MPFR_RNDN);  // exact at 200 bits
    mpfr_add(s, s, t, MPFR_RNDN);          // exact at 200 bits for these magnitudes
  }
  const bool ok = mpfr_cmp_d(s, iv.lower()) >= 0 && mpfr_cmp_d(s, iv.upper()) <= 0;
  mpfr_clears(s, t, static_cast<mpfr_ptr>(nullptr));
  return ok;
}

}  // namespace

TEST(IntervalLinearAlgebra, ProductsContainExactProductsInEveryRoundingMode) {
  std::mt19937_64 rng(99);
  const int modes[4] = {FE_TONEAREST, FE_UPWARD, FE_DOWNWARD, FE_TOWARDZERO};
  int checks = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const int n = 3 + trial % 4;
    const double scale = std::pow(10.0, static_cast<int>(rng() % 9) - 4);
    const double width = (trial % 3 == 0) ? 0.0 : std::pow(10.0, -static_cast<int>(rng() % 12));
    const IMat a = randomIntervalMatrix(rng, n, scale, width);
    DMat c(n, n);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) c(i, j) = u(rng);
    const int saved = std::fegetround();
    std::fesetround(modes[trial % 4]);
    const IMat left = multiplyMidRad(c, a), right = multiplyMidRad(a, c), plain = multiply(c, a);
    std::fesetround(saved);
    for (int s = 0; s < 3; ++s) {
      const DMat p = pointIn(a, rng);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          EXPECT_TRUE(exactProductInside(c, p, i, j, left(i, j))) << "C*A trial " << trial;
          EXPECT_TRUE(exactProductInside(p, c, i, j, right(i, j))) << "A*C trial " << trial;
          EXPECT_TRUE(exactProductInside(c, p, i, j, plain(i, j))) << "plain trial " << trial;
          checks += 3;
        }
    }
    // Midpoint-radius is never much wider than the interval product.
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) EXPECT_LE(left(i, j).width(), 1.5 * plain(i, j).width() + 1e-13 * scale);
  }
  EXPECT_GT(checks, 300000);
}

TEST(IntervalLinearAlgebra, GaussInverseContainsInversesOfPointMatrices) {
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 500; ++trial) {
    const int n = 6;
    IMat a = randomIntervalMatrix(rng, n, 0.05, 1e-3);
    for (int i = 0; i < n; ++i) a(i, i) += Interval(1.0);  // near identity, as after preconditioning
    IMat inv;
    ASSERT_TRUE(enclosure::gaussInverse(a, inv, false));
    for (int s = 0; s < 5; ++s) {
      const DMat p = pointIn(a, rng);
      const DMat pinv = p.inverse();
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          const double slack = 1e-14;  // the double inverse itself is only approximate
          EXPECT_LE(inv(i, j).lower() - slack, pinv(i, j));
          EXPECT_GE(inv(i, j).upper() + slack, pinv(i, j));
        }
    }
  }
  // A singular interval matrix is reported, not inverted.
  IMat s(2, 2);
  s << Interval(1.0), Interval(1.0), Interval(1.0), Interval(0.9, 1.1);
  IMat inv;
  EXPECT_FALSE(enclosure::gaussInverse(s, inv, true));
}

TEST(IntervalLinearAlgebra, DeterminantSignHoldsForEveryMemberAndFailsOnSingularOnes) {
  // Random interval matrices of every size and three widths: where a sign is certified, the exact determinant (MPFR)
  // of points drawn from the matrix (a quarter of the entries at an end) has it.
  std::mt19937_64 rng(2026);
  int certified = 0, trials = 0, positive = 0;
  for (int n = 1; n <= 6; ++n) {
    for (int trial = 0; trial < 150; ++trial, ++trials) {
      const double width = trial % 3 == 0 ? 1e-9 : (trial % 3 == 1 ? 1e-3 : 3e-2);
      const IMat a = randomIntervalMatrix(rng, n, 1.0 + trial % 7, width);
      const int s = enclosure::determinantSign(a);
      if (s == 0) continue;
      ++certified;
      positive += s > 0 ? 1 : 0;
      for (int p = 0; p < 8; ++p) EXPECT_EQ(test::mpDeterminantSign(pointIn(a, rng)), s) << n << " " << trial;
    }
  }
  // (Both signs occur, and nearly every narrow matrix is certified: 900 trials, two thirds of width <= 1e-3.)
  EXPECT_GT(certified, 700) << trials;
  EXPECT_GT(positive, certified / 4);
  EXPECT_LT(positive, 3 * certified / 4);

  // Permutation matrices: the sign of the permutation (through the pivoting's row swaps).
  IMat swap2 = IMat::Constant(6, 6, Interval(0.0)), cycle3 = swap2;
  const int s2[6] = {1, 0, 2, 3, 4, 5}, c3[6] = {1, 2, 0, 3, 4, 5};
  for (int i = 0; i < 6; ++i) {
    swap2(i, s2[i]) = Interval(1.0);
    cycle3(i, c3[i]) = Interval(1.0);
  }
  EXPECT_EQ(enclosure::determinantSign(swap2), -1);
  EXPECT_EQ(enclosure::determinantSign(cycle3), 1);
  EXPECT_EQ(enclosure::determinantSign(IMat(-swap2)), -1);  // (-1)^6 * -1

  // Matrices that contain a singular one are never certified: two equal rows, then widened.
  for (int trial = 0; trial < 50; ++trial) {
    IMat a = randomIntervalMatrix(rng, 6, 1.0, trial % 2 == 0 ? 0.0 : 1e-6);
    a.row(3) = a.row(1);
    EXPECT_EQ(enclosure::determinantSign(a), 0) << trial;
  }
}
