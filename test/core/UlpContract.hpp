// MPFR reference for the ulp error contract of the libm-based interval functions: the set of all reals y that a
// libm value v may stand for when it is known to be within k ulps of y, measured in ulps of y,
//   S(v, k) = { y real : |y - v| <= k ulp(y) },  ulp(y) = 2^(max(floor(log2 |y|), -1022) - 52)
// (the spacing of the doubles at |y|, the larger one at a power of two; the unit in which the MPFR tests measure the
// libm errors). Computed exactly from the definition, binade by binade, independently of the code under test.
#pragma once

#include <mpfr.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace pkm_accuracy {
namespace test {

/// Exact bounds [inf, sup] of S(v, k) for a double v with |v| < 2^1000 (zeros and subnormals included) and
/// 0 <= k <= 2^20. Every member of S(v, k) lies in v's ulp class or a neighbouring one; the bounds are dyadic numbers
/// of fewer than 60 significant bits, exact at the 128 bits used.
class UlpContract {
 public:
  UlpContract() {
    mpfr_init2(inf_, 128);
    mpfr_init2(sup_, 128);
    mpfr_init2(lo_, 128);
    mpfr_init2(hi_, 128);
    mpfr_init2(u_, 128);
  }
  ~UlpContract() {
    mpfr_clear(inf_);
    mpfr_clear(sup_);
    mpfr_clear(lo_);
    mpfr_clear(hi_);
    mpfr_clear(u_);
  }
  UlpContract(const UlpContract&) = delete;
  UlpContract& operator=(const UlpContract&) = delete;

  /// Computes the bounds of S(v, k); false if v is outside the supported range.
  bool set(double v, int k) {
    const double a = std::fabs(v);
    if (!(a < 0x1p1000) || k < 0 || k > (1 << 20)) return false;
    const int e = a < 0x1p-1022 ? -1022 : std::ilogb(a);  // ulp class of a: ulp(a) = 2^(e - 52)
    // S(a, k) is the union over the ulp classes C_f of C_f intersected with [a - k 2^(f-52), a + k 2^(f-52)], where
    // C_f = [2^f, 2^(f+1)) for f > -1022 and C_-1022 = (-2^-1021, 2^-1021) (the reals of ulp 2^-1074, of either
    // sign); its sup / inf are the largest / smallest ends of the non-empty intersections (for S(a, k) with a >= 0,
    // negative members can only lie in C_-1022).
    bool any = false;
    for (int f = std::max(e - 3, -1022); f <= e + 3; ++f) {
      mpfr_set_ui_2exp(u_, static_cast<unsigned long>(k), f - 52, MPFR_RNDN);  // NOLINT(runtime/int)
      mpfr_set_d(hi_, a, MPFR_RNDN);
      mpfr_add(hi_, hi_, u_, MPFR_RNDN);  // a + k 2^(f-52), exact
      mpfr_set_d(lo_, a, MPFR_RNDN);
      mpfr_sub(lo_, lo_, u_, MPFR_RNDN);  // a - k 2^(f-52), exact
      const bool first = f == -1022;      // C_f = [bottom, 2^(f+1)), bottom = 2^f or -2^-1021 (open, as an inf)
      const int bottomSign = first ? -1 : 1;
      const int bottomExp = first ? -1021 : f;
      if (mpfr_cmp_si_2exp(hi_, bottomSign, bottomExp) < 0 || mpfr_cmp_ui_2exp(lo_, 1, f + 1) >= 0) continue;
      if (mpfr_cmp_ui_2exp(hi_, 1, f + 1) > 0) mpfr_set_ui_2exp(hi_, 1, f + 1, MPFR_RNDN);
      if (mpfr_cmp_si_2exp(lo_, bottomSign, bottomExp) < 0) mpfr_set_si_2exp(lo_, bottomSign, bottomExp, MPFR_RNDN);
      if (!any || mpfr_cmp(hi_, sup_) > 0) mpfr_set(sup_, hi_, MPFR_RNDN);
      if (!any || mpfr_cmp(lo_, inf_) < 0) mpfr_set(inf_, lo_, MPFR_RNDN);
      any = true;
    }
    negative_ = std::signbit(v);
    if (negative_) {  // S(-a, k) = -S(a, k)
      mpfr_swap(inf_, sup_);
      mpfr_neg(inf_, inf_, MPFR_RNDN);
      mpfr_neg(sup_, sup_, MPFR_RNDN);
    }
    exponent_ = e;
    return any;
  }

  /// True when S(v, k) reaches the ulp class above that of |v| (where the ulp is twice that of v).
  bool reachesLargerBinade() const {
    return negative_ ? mpfr_cmp_si_2exp(inf_, -1, exponent_ + 1) <= 0 : mpfr_cmp_ui_2exp(sup_, 1, exponent_ + 1) >= 0;
  }

  /// The bounds (exact).
  const mpfr_t& inf() const { return inf_; }
  const mpfr_t& sup() const { return sup_; }

  /// True when [lower, upper] contains S(v, k) intersected with [rangeLo, rangeHi] (the closure of the function's
  /// range as bounded by the code). Exact comparisons.
  bool coveredBy(double lower, double upper, double rangeLo, double rangeHi, std::string* why) const {
    const bool lowOk = mpfr_cmp_d(inf_, lower) >= 0 || lower <= rangeLo;
    const bool highOk = mpfr_cmp_d(sup_, upper) <= 0 || upper >= rangeHi;
    if (!(lowOk && highOk) && why) {
      char buf[256];
      mpfr_snprintf(buf, sizeof buf, " ulp contract [%Ra, %Ra] not within [%a, %a]", inf_, sup_, lower, upper);
      *why += buf;
    }
    return lowOk && highOk;
  }

 private:
  mpfr_t inf_, sup_, lo_, hi_, u_;
  int exponent_ = 0;
  bool negative_ = false;
};

}  // namespace test
}  // namespace pkm_accuracy
