// The a priori error bounds of interval/Rounding.hpp (kUnitRoundoff, gamma, up, upEach) in every IEEE rounding mode:
// up() bounds the exact value of sums of non-negative products computed in floating point, and an overflow (to +inf,
// or to DBL_MAX under round-down and round-toward-zero) or a NaN is reported as unbounded (+inf), never as a finite
// bound.
#include <gtest/gtest.h>
#include <mpfr.h>

#include <cfenv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

#include <Eigen/Core>

#include "pkm_accuracy/core/interval/Rounding.hpp"

using namespace pkm_accuracy::interval;

namespace {

constexpr int kModes[] = {FE_TONEAREST, FE_UPWARD, FE_DOWNWARD, FE_TOWARDZERO};

/// Runs `body` with the rounding mode set to `mode`, and restores the mode it found.
template <typename Body>
void inMode(int mode, Body body) {
  const int saved = std::fegetround();
  ASSERT_EQ(std::fesetround(mode), 0);
  body();
  std::fesetround(saved);
}

/// PKM_TEST_ROUNDING_MODE=upward|downward|towardzero|tonearest: the main thread runs every test in that rounding
/// mode (CMakeLists.txt registers the enclosure-level soundness tests once per mode). The core claims its bounds in
/// any mode without switching it; the tests' own oracles (MPFR, or double with relative margins) do not depend on it.
class RoundingModeEnvironment : public ::testing::Environment {
 public:
  void SetUp() override {
    const char* name = std::getenv("PKM_TEST_ROUNDING_MODE");
    if (name == nullptr || *name == '\0') return;
    const std::string mode(name);
    const int m = mode == "upward"       ? FE_UPWARD
                  : mode == "downward"   ? FE_DOWNWARD
                  : mode == "towardzero" ? FE_TOWARDZERO
                  : mode == "tonearest"  ? FE_TONEAREST
                                         : -1;
    if (m < 0) throw std::invalid_argument("PKM_TEST_ROUNDING_MODE: unknown mode '" + mode + "'");
    ASSERT_EQ(std::fesetround(m), 0);
    std::printf("[ info     ] tests run in rounding mode %s\n", name);
  }
};

const ::testing::Environment* const kRoundingModeEnvironment =
    ::testing::AddGlobalTestEnvironment(new RoundingModeEnvironment);

}  // namespace

TEST(Rounding, UpTreatsOverflowAndNaNAsUnboundedInEveryMode) {
  constexpr double inf = std::numeric_limits<double>::infinity(), big = std::numeric_limits<double>::max();
  for (const int mode : kModes) {
    inMode(mode, [&] {
      volatile double huge = big;  // (volatile: evaluated at run time, in this mode)
      EXPECT_EQ(rounding::up(huge), inf) << "mode " << mode;
      EXPECT_EQ(rounding::up(huge * 0.9999999999999), inf) << "mode " << mode;
      EXPECT_EQ(rounding::up(inf), inf) << "mode " << mode;
      EXPECT_EQ(rounding::up(std::numeric_limits<double>::quiet_NaN()), inf) << "mode " << mode;
      EXPECT_LT(rounding::up(1e300), inf) << "mode " << mode;
      const Eigen::Vector3d v(1.0, static_cast<double>(huge), std::numeric_limits<double>::quiet_NaN());
      const Eigen::Vector3d u = rounding::upEach(v);
      EXPECT_GE(u[0], 1.0);
      EXPECT_LT(u[0], 1.0 + 1e-11);
      EXPECT_EQ(u[1], inf) << "mode " << mode;
      EXPECT_EQ(u[2], inf) << "mode " << mode;
    });
  }
}

TEST(Rounding, UpBoundsSumsOfProductsComputedInEveryModeInMpfr) {
  // Sums of up to kUpOperations / 2 non-negative products of random magnitudes (subnormal results included),
  // computed in double in each mode: up() of the computed sum is >= the exact sum (MPFR, 2200 bits: exact).
  std::mt19937_64 rng(52);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  mpfr_t exact, term;
  mpfr_inits2(2200, exact, term, static_cast<mpfr_ptr>(nullptr));
  int checked = 0;
  double tightest = std::numeric_limits<double>::infinity();  // smallest (up - exact) / exact seen
  for (const int mode : kModes) {
    for (int trial = 0; trial < 200; ++trial) {
      const int terms = 1 + static_cast<int>(rng() % (rounding::kUpOperations / 2));
      const int scale = trial % 4 == 0 ? -1070 : (trial % 4 == 1 ? -500 : 0);  // subnormal, tiny, normal products
      std::vector<double> a(terms), b(terms);
      for (int i = 0; i < terms; ++i) {
        a[i] = std::ldexp(unit(rng), scale / 2);
        b[i] = std::ldexp(unit(rng), scale - scale / 2);
      }
      double sum = 0.0, bound = 0.0;
      inMode(mode, [&] {
        for (int i = 0; i < terms; ++i) {
          volatile double p = a[i] * b[i];
          sum = sum + p;
        }
        bound = rounding::up(sum);
      });
      mpfr_set_zero(exact, 1);
      for (int i = 0; i < terms; ++i) {
        mpfr_set_d(term, a[i], MPFR_RNDN);
        mpfr_mul_d(term, term, b[i], MPFR_RNDN);  // exact at 2200 bits
        mpfr_add(exact, exact, term, MPFR_RNDN);  // exact: every term is a multiple of 2^-2148, below 2^2
      }
      EXPECT_LE(mpfr_cmp_d(exact, bound), 0) << "mode " << mode << " trial " << trial << " terms " << terms;
      if (mpfr_sgn(exact) > 0 && scale == 0) tightest = std::min(tightest, bound / mpfr_get_d(exact, MPFR_RNDN) - 1.0);
      ++checked;
    }
  }
  mpfr_clears(exact, term, static_cast<mpfr_ptr>(nullptr));
  EXPECT_EQ(checked, 800);
  EXPECT_LT(tightest, 2e-12);  // (the margin is relative 1e-12: not vacuous)
}

TEST(Rounding, GammaCoversTheClassicalBoundWithTheDirectedUnitRoundoff) {
  // gamma(n) >= n u / (1 - n u) with u = 2^-52 (the directed modes' unit roundoff, not round-to-nearest's 2^-53).
  EXPECT_EQ(rounding::kUnitRoundoff, std::ldexp(1.0, -52));
  for (const int n : {1, 2, 3, 6, 48, 64, 66, 100, 4000, 1000000}) {
    const long double u = std::ldexp(1.0L, -52), exact = n * u / (1.0L - n * u);
    EXPECT_GE(static_cast<long double>(rounding::gamma(n)), exact) << n;
    EXPECT_LT(static_cast<long double>(rounding::gamma(n)), 1.02L * exact) << n;
  }
}
