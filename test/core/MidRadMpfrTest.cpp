// Containment of the midpoint-radius operations (interval::MidRad: +, -, *, unary -) against MPFR: 2*10^5 random
// cases per operation, cycling through the four IEEE rounding modes. The exact result at the corners of the operands
// (where the extremes of +, -, * over the operand boxes are attained) and at a random interior point is computed in
// MPFR (200 bits: exact for sums and products of doubles) and must lie in [m - r, m + r], compared in MPFR. Also:
// the product of two intervals that do not contain 0 is the exact hull up to a relative 1e-9 and the rounding terms
// (the tighter formula),
// and toInterval() contains the midpoint-radius set.
#include <gtest/gtest.h>
#include <mpfr.h>

#include <cfenv>
#include <cmath>
#include <random>

#include "MpfrGough.hpp"
#include "pkm_accuracy/core/interval/MidRad.hpp"

namespace {

using pkm_accuracy::interval::Interval;
using pkm_accuracy::interval::MidRad;

using pkm_accuracy::test::Mp;  // MPFR at 200 bits (MpfrGough.hpp)

/// m - r <= x <= m + r, in MPFR (the bounds m -+ r are exact at 200 bits).
bool inside(const mpfr_t x, const MidRad& a) {
  Mp lo(a.mid()), hi(a.mid()), r(a.rad());
  mpfr_sub(lo.v, lo.v, r.v, MPFR_RNDN);
  mpfr_add(hi.v, hi.v, r.v, MPFR_RNDN);
  return mpfr_cmp(lo.v, x) <= 0 && mpfr_cmp(x, hi.v) <= 0;
}

class Gen {
 public:
  explicit Gen(unsigned seed) : rng_(seed) {}
  double unit() { return std::uniform_real_distribution<double>(0.0, 1.0)(rng_); }
  MidRad operand() {
    const double m = (unit() < 0.5 ? -1.0 : 1.0) * std::ldexp(0.5 + unit(), static_cast<int>(unit() * 40) - 20);
    const double kind = unit();
    // Points, radii of a few ulps, relative radii up to 1 and beyond (intervals containing 0).
    const double r = kind < 0.1 ? 0.0
                                : std::abs(m) * (kind < 0.3 ? 1e-15 * unit()
                                                            : std::ldexp(unit(), -static_cast<int>(unit() * 30)) * 2.0);
    return MidRad(m, r);
  }
  double pointIn(const MidRad& a, int corner) {
    if (corner == 0) return a.mid() - a.rad();
    if (corner == 1) return a.mid() + a.rad();
    return a.mid() + (2.0 * unit() - 1.0) * a.rad();
  }

 private:
  std::mt19937_64 rng_;
};

}  // namespace

TEST(MidRadMpfr, OperationsContainTheExactResultsInEveryRoundingMode) {
  const int modes[4] = {FE_TONEAREST, FE_UPWARD, FE_DOWNWARD, FE_TOWARDZERO};
  Gen gen(11);
  long checked = 0;  // NOLINT(runtime/int)
  const int cases = 200000;
  for (int c = 0; c < cases; ++c) {
    const MidRad a = gen.operand(), b = gen.operand();
    const int saved = std::fegetround();
    std::fesetround(modes[c % 4]);
    const MidRad sum = a + b, diff = a - b, prod = a * b, neg = -a;
    std::fesetround(saved);
    for (int ca = 0; ca < 3; ++ca)
      for (int cb = 0; cb < 3; ++cb) {
        // Endpoints m -+ r may not be doubles; the corners of the operand sets are, up to one rounding: take the
        // double nearest to them and accept it only if it lies in the operand (so the check stays exact).
        const double x = gen.pointIn(a, ca), y = gen.pointIn(b, cb);
        Mp xm(x), ym(y), ax(a.mid()), ar(a.rad()), bx(b.mid()), br(b.rad());
        auto within = [](const Mp& p, const Mp& m, const Mp& r) {
          Mp lo, hi;
          mpfr_sub(lo.v, m.v, r.v, MPFR_RNDN);
          mpfr_add(hi.v, m.v, r.v, MPFR_RNDN);
          return mpfr_cmp(lo.v, p.v) <= 0 && mpfr_cmp(p.v, hi.v) <= 0;
        };
        if (!within(xm, ax, ar) || !within(ym, bx, br)) continue;
        Mp s, d, p;
        mpfr_add(s.v, xm.v, ym.v, MPFR_RNDN);
        mpfr_sub(d.v, xm.v, ym.v, MPFR_RNDN);
        mpfr_mul(p.v, xm.v, ym.v, MPFR_RNDN);
        ASSERT_TRUE(inside(s.v, sum)) << a.mid() << " +- " << a.rad() << " + " << b.mid() << " +- " << b.rad();
        ASSERT_TRUE(inside(d.v, diff)) << a.mid() << " +- " << a.rad() << " - " << b.mid() << " +- " << b.rad();
        ASSERT_TRUE(inside(p.v, prod)) << a.mid() << " +- " << a.rad() << " * " << b.mid() << " +- " << b.rad();
        Mp n;
        mpfr_neg(n.v, xm.v, MPFR_RNDN);
        ASSERT_TRUE(inside(n.v, neg));
        ++checked;
      }
    // toInterval() contains the set.
    const Interval iv = prod.toInterval();
    ASSERT_LE(iv.lower(), prod.mid() - prod.rad());
    ASSERT_GE(iv.upper(), prod.mid() + prod.rad());
  }
  EXPECT_GT(checked, 4L * cases);
}

TEST(MidRadMpfr, ProductWithoutZeroIsTheHull) {
  Gen gen(12);
  int tight = 0;
  for (int c = 0; c < 100000; ++c) {
    const MidRad a = gen.operand(), b = gen.operand();
    if (!(std::abs(a.mid()) > a.rad()) || !(std::abs(b.mid()) > b.rad())) continue;
    const MidRad p = a * b;
    const double c1 = (a.mid() - a.rad()) * (b.mid() - b.rad()), c2 = (a.mid() - a.rad()) * (b.mid() + b.rad());
    const double c3 = (a.mid() + a.rad()) * (b.mid() - b.rad()), c4 = (a.mid() + a.rad()) * (b.mid() + b.rad());
    const double lo = std::min(std::min(c1, c2), std::min(c3, c4)), hi = std::max(std::max(c1, c2), std::max(c3, c4));
    const double width = hi - lo;
    EXPECT_LE(2.0 * p.rad(), width * (1 + 1e-9) + 3e-15 * std::abs(p.mid()) + 1e-300)
        << a.mid() << " " << a.rad() << " " << b.mid() << " " << b.rad();
    ++tight;
  }
  EXPECT_GT(tight, 30000);
}
