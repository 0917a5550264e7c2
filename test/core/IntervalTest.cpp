// Edge tables of the Interval type: empty, +-inf bounds, DBL_MAX, degenerate intervals, [0, 0], signed zeros,
// entire(); every binary operation in its plain, compound (+=, -=, *=, /=) and swapped forms, checked for
// containment in MPFR at representative points of both operands, plus the documented special results (division by
// an interval containing zero is entire(), 0 * inf counts as 0, empty in -> empty out, ...).
#include <gtest/gtest.h>
#include <mpfr.h>

#include <cfloat>
#include <climits>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/interval/Eigen.hpp"
#include "pkm_accuracy/core/interval/Functions.hpp"
#include "pkm_accuracy/core/interval/Interval.hpp"

namespace {

using pkm_accuracy::interval::Interval;
namespace iv = pkm_accuracy::interval;
namespace rd = pkm_accuracy::interval::rounding;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMax = std::numeric_limits<double>::max();
constexpr double kDen = std::numeric_limits<double>::denorm_min();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string str(const Interval& r) {
  if (r.isEmpty()) return "[empty]";
  char buf[128];
  std::snprintf(buf, sizeof buf, "[%a, %a]", r.lower(), r.upper());
  return buf;
}

// Bitwise-identical bounds (distinguishes -0 from +0; all empties are equal).
bool same(const Interval& a, const Interval& b) {
  if (a.isEmpty() || b.isEmpty()) return a.isEmpty() && b.isEmpty();
  return rd::bitsOf(a.lower()) == rd::bitsOf(b.lower()) && rd::bitsOf(a.upper()) == rd::bitsOf(b.upper());
}

// A valid value: empty, or lo <= hi with lo != +inf, hi != -inf and no NaN.
bool valid(const Interval& r) {
  if (r.isEmpty()) return std::isnan(r.upper());
  return r.lower() <= r.upper() && r.lower() != kInf && r.upper() != -kInf && !std::isnan(r.upper());
}

std::vector<Interval> edgeIntervals() {
  return {Interval::empty(),      Interval::entire(),      Interval(0.0),        Interval(-0.0),
          Interval(-0.0, 0.0),    Interval(0.0, -0.0),     Interval(1.0),        Interval(-1.0),
          Interval(1.0, 2.0),     Interval(-2.0, -1.0),    Interval(-1.0, 2.0),  Interval(-0.0, 1.0),
          Interval(-1.0, -0.0),   Interval(-kInf, 0.0),    Interval(0.0, kInf),  Interval(-kInf, -1.0),
          Interval(1.0, kInf),    Interval(-kInf, 1.0),    Interval(-1.0, kInf), Interval(kMax),
          Interval(-kMax),        Interval(-kMax, kMax),   Interval(kMax, kInf), Interval(-kInf, -kMax),
          Interval(kInf),         Interval(-kInf),         Interval(kDen),       Interval(-kDen, kDen),
          Interval(DBL_MIN, 1.0), Interval(1e-300, 1e300), Interval(0.0, kMax),  Interval(0.1, 0.3)};
}

// Finite representatives of an interval: finite bounds, 0 if inside, a middle point, and huge values standing in
// for infinite bounds.
std::vector<double> samples(const Interval& a) {
  std::vector<double> s;
  if (a.isEmpty()) return s;
  if (std::isfinite(a.lower())) s.push_back(a.lower());
  if (std::isfinite(a.upper())) s.push_back(a.upper());
  if (a.contains(0.0)) s.push_back(0.0);
  for (double v : {1.0, -1.0, 1e300, -1e300, kMax, -kMax, 2.5, -2.5, 1e-300, -1e-300}) {
    if (a.contains(v)) s.push_back(v);
  }
  if (a.isBounded()) s.push_back(a.mid());
  return s;
}

struct Mp {
  mpfr_t v;
  explicit Mp(mpfr_prec_t p) { mpfr_init2(v, p); }
  ~Mp() { mpfr_clear(v); }
};

// Is the exact x op y (op in "+-*/") inside r? Bracketed in MPFR (exact at 2200 bits for + - *).
bool exactInside(char op, double x, double y, const Interval& r) {
  Mp a(64), b(64), z(2200);
  mpfr_set_d(a.v, x, MPFR_RNDN);
  mpfr_set_d(b.v, y, MPFR_RNDN);
  int t = 0;
  switch (op) {
    case '+':
      t = mpfr_add(z.v, a.v, b.v, MPFR_RNDD);
      break;
    case '-':
      t = mpfr_sub(z.v, a.v, b.v, MPFR_RNDD);
      break;
    case '*':
      t = mpfr_mul(z.v, a.v, b.v, MPFR_RNDD);
      break;
    default:
      t = mpfr_div(z.v, a.v, b.v, MPFR_RNDD);
      break;
  }
  if (r.isEmpty() || mpfr_cmp_d(z.v, r.lower()) < 0) return false;
  if (t != 0) mpfr_nextabove(z.v);
  return mpfr_cmp_d(z.v, r.upper()) <= 0;
}

Interval apply(char op, const Interval& a, const Interval& b) {
  switch (op) {
    case '+':
      return a + b;
    case '-':
      return a - b;
    case '*':
      return a * b;
    default:
      return a / b;
  }
}

Interval applyCompound(char op, Interval a, const Interval& b) {
  switch (op) {
    case '+':
      a += b;
      break;
    case '-':
      a -= b;
      break;
    case '*':
      a *= b;
      break;
    default:
      a /= b;
      break;
  }
  return a;
}

TEST(IntervalEdge, EveryPairOfEdgeIntervalsEveryOperationAndForm) {
  const std::vector<Interval> e = edgeIntervals();
  int pairs = 0, points = 0;
  for (char op : {'+', '-', '*', '/'}) {
    for (const Interval& a : e) {
      for (const Interval& b : e) {
        ++pairs;
        const Interval r = apply(op, a, b);
        SCOPED_TRACE(std::string("a = ") + str(a) + " " + op + " b = " + str(b) + " -> " + str(r));
        ASSERT_TRUE(valid(r));
        // compound form gives the identical result
        EXPECT_TRUE(same(applyCompound(op, a, b), r));
        // self-assignment through the compound form (aliasing)
        {
          Interval c = a;
          Interval d = applyCompound(op, c, c);
          c = applyCompound(op, c, c);
          EXPECT_TRUE(same(c, d));
        }
        // swapped forms
        if (op == '+' || op == '*') {
          EXPECT_TRUE(same(apply(op, b, a), r));
        }
        if (op == '-') {
          EXPECT_TRUE(same(r, a + (-b)));
          EXPECT_EQ(r, -(b - a));
        }
        // empty in, empty out
        if (a.isEmpty() || b.isEmpty()) {
          EXPECT_TRUE(r.isEmpty());
          continue;
        }
        EXPECT_FALSE(r.isEmpty());
        // division by an interval containing zero: entire() as documented
        if (op == '/' && b.containsZero()) {
          EXPECT_TRUE(same(r, Interval::entire()));
          continue;
        }
        for (double x : samples(a)) {
          for (double y : samples(b)) {
            ++points;
            EXPECT_TRUE(exactInside(op, x, y, r)) << "x = " << x << ", y = " << y;
          }
        }
      }
    }
  }
  std::printf("[ edges  ] %d operation/pair combinations, %d MPFR point checks\n", pairs, points);
}

TEST(IntervalEdge, MixedDoubleOperationsMatchThePromotedOnes) {
  // a * s, s * a, a / s, a *= s, a /= s are bit-identical to the operations with Interval(s), for every edge
  // interval and edge double (signed zeros, infinities, NaN, DBL_MAX, subnormals).
  const std::vector<double> ds = {0.0,  -0.0,  1.0,  -1.0,  2.5,  -3.0,  kMax,  -kMax,
                                  kDen, -kDen, kInf, -kInf, kNaN, 1e300, 1e-300};
  int n = 0;
  for (const Interval& a : edgeIntervals()) {
    for (double s : ds) {
      SCOPED_TRACE(str(a) + " and " + std::to_string(s));
      EXPECT_TRUE(same(a * s, a * Interval(s)));
      EXPECT_TRUE(same(s * a, Interval(s) * a));
      EXPECT_TRUE(same(a / s, a / Interval(s)));
      Interval m = a, d = a;
      m *= s;
      d /= s;
      EXPECT_TRUE(same(m, a * Interval(s)));
      EXPECT_TRUE(same(d, a / Interval(s)));
      ++n;
    }
  }
  EXPECT_EQ(n, static_cast<int>(edgeIntervals().size() * ds.size()));
}

TEST(IntervalEdge, ConstructionAndInvariants) {
  EXPECT_TRUE(Interval(kNaN).isEmpty());
  EXPECT_TRUE(same(Interval(kInf), Interval(kMax, kInf)));
  EXPECT_TRUE(same(Interval(-kInf), Interval(-kInf, -kMax)));
  EXPECT_TRUE(same(Interval(), Interval(0.0)));
  EXPECT_THROW(Interval(2.0, 1.0), pkm_accuracy::InvalidArgument);
  EXPECT_THROW(Interval(kNaN, 1.0), pkm_accuracy::InvalidArgument);
  EXPECT_THROW(Interval(0.0, kNaN), pkm_accuracy::InvalidArgument);
  EXPECT_THROW(Interval(kInf, kInf), pkm_accuracy::InvalidArgument);
  EXPECT_THROW(Interval(-kInf, -kInf), pkm_accuracy::InvalidArgument);
  EXPECT_NO_THROW(Interval(-kInf, kInf));
  EXPECT_NO_THROW(Interval(0.0, -0.0));  // equal as reals
  EXPECT_TRUE(Interval::hullOf(3.0, kNaN).isEmpty());
  EXPECT_TRUE(same(Interval::hullOf(3.0, -1.0), Interval(-1.0, 3.0)));
  // predicates on empty / unbounded
  const Interval empty = Interval::empty(), entire = Interval::entire();
  EXPECT_FALSE(empty.contains(0.0));
  EXPECT_FALSE(empty.containsZero());
  EXPECT_FALSE(empty.isBounded());
  EXPECT_FALSE(empty.isPoint());
  EXPECT_TRUE(empty.isSubsetOf(empty));
  EXPECT_TRUE(empty.isSubsetOf(Interval(1.0)));
  EXPECT_FALSE(Interval(1.0).isSubsetOf(empty));
  EXPECT_FALSE(entire.isBounded());
  EXPECT_TRUE(entire.contains(kMax));
  EXPECT_FALSE(entire.contains(kInf));  // +-inf are not real numbers
  EXPECT_FALSE(Interval(1.0, kInf).contains(kInf));
  EXPECT_FALSE(Interval(-kInf, 1.0).contains(-kInf));
  EXPECT_FALSE(Interval(1.0).contains(kNaN));
  EXPECT_TRUE(Interval(-0.0).containsZero());
  EXPECT_TRUE(Interval(-0.0, 0.0) == Interval(0.0));
  EXPECT_TRUE(empty == Interval::empty());
  EXPECT_TRUE(empty != Interval(0.0));
}

TEST(IntervalEdge, Accessors) {
  const Interval empty = Interval::empty(), entire = Interval::entire();
  EXPECT_TRUE(std::isnan(empty.mid()));
  EXPECT_TRUE(std::isnan(empty.width()));
  EXPECT_TRUE(std::isnan(empty.rad()));
  EXPECT_TRUE(std::isnan(empty.mag()));
  EXPECT_TRUE(std::isnan(empty.mig()));
  EXPECT_EQ(entire.mid(), 0.0);
  EXPECT_EQ(Interval(-kInf, 3.0).mid(), -kMax);
  EXPECT_EQ(Interval(3.0, kInf).mid(), kMax);
  EXPECT_EQ(Interval(-kMax, kMax).mid(), 0.0);
  EXPECT_EQ(Interval(kMax).mid(), kMax);
  EXPECT_EQ(Interval(kDen).mid(), kDen);
  EXPECT_EQ(entire.width(), kInf);
  EXPECT_EQ(Interval(-kMax, kMax).width(), kInf);  // exact 2 DBL_MAX overflows: an upper bound
  EXPECT_GE(Interval(0.1, 0.3).width(), 0.3 - 0.1);
  EXPECT_GE(Interval(1.0, 2.0).rad(), 0.5);
  EXPECT_EQ(Interval(-3.0, 2.0).mag(), 3.0);
  EXPECT_EQ(Interval(-3.0, 2.0).mig(), 0.0);
  EXPECT_EQ(Interval(-3.0, -2.0).mig(), 2.0);
  EXPECT_EQ(Interval(-kInf, -2.0).mag(), kInf);
  const auto halves = Interval(1.0, 3.0).bisect();
  EXPECT_TRUE(same(halves.first, Interval(1.0, 2.0)));
  EXPECT_TRUE(same(halves.second, Interval(2.0, 3.0)));
  const auto at = Interval(1.0, 3.0).bisectAt(kNaN);  // NaN split point: the midpoint
  EXPECT_TRUE(same(at.first, Interval(1.0, 2.0)));
  const auto clamped = Interval(1.0, 3.0).bisectAt(10.0);
  EXPECT_TRUE(same(clamped.second, Interval(3.0)));
  const auto unb = entire.bisect();
  EXPECT_TRUE(same(unb.first, Interval(-kInf, 0.0)));
  std::ostringstream os;
  os << Interval(1.0, 2.0) << ' ' << empty;
  EXPECT_EQ(os.str(), "[1, 2] [empty]");
}

TEST(IntervalEdge, SetOperationsAndComparisons) {
  const Interval empty = Interval::empty(), entire = Interval::entire();
  EXPECT_TRUE(same(iv::hull(empty, Interval(1.0, 2.0)), Interval(1.0, 2.0)));
  EXPECT_TRUE(same(iv::hull(Interval(1.0, 2.0), empty), Interval(1.0, 2.0)));
  EXPECT_TRUE(iv::hull(empty, empty).isEmpty());
  EXPECT_TRUE(same(iv::hull(Interval(-kInf, 0.0), Interval(5.0)), Interval(-kInf, 5.0)));
  EXPECT_TRUE(iv::intersect(Interval(1.0, 2.0), Interval(3.0, 4.0)).isEmpty());
  EXPECT_TRUE(iv::intersect(empty, entire).isEmpty());
  EXPECT_TRUE(same(iv::intersect(Interval(1.0, 2.0), Interval(2.0, 4.0)), Interval(2.0)));
  EXPECT_TRUE(same(iv::intersect(entire, Interval(kMax, kInf)), Interval(kMax, kInf)));
  EXPECT_TRUE(same(iv::min(Interval(1.0, 5.0), Interval(2.0, 3.0)), Interval(1.0, 3.0)));
  EXPECT_TRUE(same(iv::max(Interval(1.0, 5.0), Interval(2.0, 3.0)), Interval(2.0, 5.0)));
  EXPECT_TRUE(iv::min(empty, Interval(1.0)).isEmpty());
  EXPECT_TRUE(iv::max(Interval(1.0), empty).isEmpty());
  EXPECT_TRUE(iv::certainlyLess(Interval(1.0, 2.0), Interval(3.0, kInf)));
  EXPECT_FALSE(iv::certainlyLess(Interval(1.0, 2.0), Interval(2.0, 3.0)));
  EXPECT_TRUE(iv::certainlyLessEqual(Interval(1.0, 2.0), Interval(2.0, 3.0)));
  EXPECT_FALSE(iv::certainlyLess(empty, Interval(1.0)));
  EXPECT_FALSE(iv::certainlyLess(Interval(1.0), empty));
  EXPECT_FALSE(iv::certainlyLessEqual(empty, empty));
  EXPECT_TRUE(iv::certainlyPositive(Interval(kDen, 1.0)));
  EXPECT_FALSE(iv::certainlyPositive(Interval(0.0, 1.0)));
  EXPECT_FALSE(iv::certainlyPositive(empty));
  EXPECT_TRUE(iv::certainlyNegative(Interval(-kInf, -kDen)));
  EXPECT_FALSE(iv::certainlyNegative(Interval(-1.0, -0.0)));
  EXPECT_FALSE(iv::certainlyNegative(empty));
}

TEST(IntervalEdge, DocumentedSpecialResults) {
  const Interval empty = Interval::empty(), entire = Interval::entire();
  // overflow: the exact result exceeds DBL_MAX
  EXPECT_TRUE(same(Interval(kMax) + Interval(kMax), Interval(kMax, kInf)));
  EXPECT_TRUE(same(Interval(-kMax) - Interval(kMax), Interval(-kInf, -kMax)));
  EXPECT_TRUE(same(Interval(kMax) * Interval(2.0), Interval(kMax, kInf)));
  // unbounded sums never produce NaN
  EXPECT_TRUE(same(Interval(-kInf, 1.0) + Interval(1.0, kInf), entire));
  EXPECT_TRUE(same(entire - entire, entire));
  // 0 * inf counts as 0: the product set of [0, 0] and anything non-empty is {0}
  for (const Interval& b : {entire, Interval(1.0, kInf), Interval(-kInf, -1.0), Interval(kMax, kInf)}) {
    const Interval p = Interval(0.0) * b;
    EXPECT_TRUE(p.contains(0.0));
    EXPECT_TRUE(p.isSubsetOf(Interval(-kDen, kDen))) << str(p);
    EXPECT_TRUE(same(p, b * Interval(0.0)));
  }
  EXPECT_TRUE(same(Interval(0.0, 1.0) * Interval(1.0, kInf), Interval(-kDen, kInf)));
  EXPECT_TRUE(same(Interval(-1.0, 1.0) * entire, entire));
  // division by an interval containing zero: entire()
  for (const Interval& b : {Interval(0.0), Interval(-0.0), Interval(-0.0, 0.0), Interval(0.0, 1.0), Interval(-1.0, 0.0),
                            Interval(-1.0, 1.0), entire, Interval(0.0, kInf)}) {
    EXPECT_TRUE(same(Interval(1.0, 2.0) / b, entire)) << str(b);
    EXPECT_TRUE(same(Interval(0.0) / b, entire)) << str(b);
    EXPECT_TRUE(same(entire / b, entire)) << str(b);
    EXPECT_TRUE((empty / b).isEmpty());
  }
  EXPECT_TRUE((Interval(1.0) / empty).isEmpty());
  // division by unbounded intervals without zero
  EXPECT_TRUE(same(Interval(1.0, 2.0) / Interval(1.0, kInf), Interval(-kDen, rd::nextUp(2.0))));
  EXPECT_TRUE(same(Interval(-2.0, -1.0) / Interval(-kInf, -1.0), Interval(-kDen, rd::nextUp(2.0))));
  EXPECT_TRUE(same(entire / Interval(1.0, 2.0), entire));
  EXPECT_TRUE(same(Interval(1.0) / Interval(kDen), Interval(kMax, kInf)));  // 2^1074 overflows
  // exact operations are still widened by one ulp (the policy does not detect exactness)
  EXPECT_TRUE(same(Interval(1.0) + Interval(2.0), Interval(rd::nextDown(3.0), rd::nextUp(3.0))));
  // unary minus, abs, min, max are exact
  EXPECT_TRUE(same(-Interval(1.0, 2.0), Interval(-2.0, -1.0)));
  EXPECT_TRUE(same(-entire, entire));
  EXPECT_TRUE((-empty).isEmpty());
}

TEST(IntervalEdge, ElementaryFunctions) {
  const Interval empty = Interval::empty(), entire = Interval::entire();
  // abs
  EXPECT_TRUE(same(iv::abs(Interval(-3.0, 2.0)), Interval(0.0, 3.0)));
  EXPECT_TRUE(same(iv::abs(Interval(-3.0, -2.0)), Interval(2.0, 3.0)));
  EXPECT_TRUE(same(iv::abs(entire), Interval(0.0, kInf)));
  EXPECT_TRUE(same(iv::abs(Interval(-kInf, -1.0)), Interval(1.0, kInf)));
  EXPECT_TRUE(iv::abs(empty).isEmpty());
  EXPECT_EQ(iv::abs(Interval(-0.0)), Interval(0.0));
  // sqr
  EXPECT_TRUE(same(iv::sqr(entire), Interval(0.0, kInf)));
  EXPECT_TRUE(same(iv::sqr(Interval(-2.0, 1.0)), Interval(0.0, rd::nextUp(4.0))));
  EXPECT_TRUE(same(iv::sqr(Interval(-0.0, 0.0)), Interval(0.0, kDen)));
  EXPECT_TRUE(same(iv::sqr(Interval(kMax)), Interval(kMax, kInf)));
  EXPECT_TRUE(same(iv::sqr(Interval(kDen)), Interval(0.0, kDen)));
  EXPECT_TRUE(iv::sqr(empty).isEmpty());
  // sqrt
  EXPECT_TRUE(iv::sqrt(Interval(-2.0, -1.0)).isEmpty());
  EXPECT_TRUE(iv::sqrt(empty).isEmpty());
  EXPECT_TRUE(same(iv::sqrt(Interval(-1.0, 4.0)), Interval(0.0, rd::nextUp(2.0))));
  EXPECT_TRUE(same(iv::sqrt(Interval(-0.0)), Interval(0.0)));
  EXPECT_TRUE(same(iv::sqrt(Interval(-kInf, 0.0)), Interval(0.0)));
  EXPECT_TRUE(same(iv::sqrt(entire), Interval(0.0, kInf)));
  EXPECT_TRUE(same(iv::sqrt(Interval(kMax, kInf)), Interval(rd::nextDown(std::sqrt(kMax)), kInf)));
  // pow
  EXPECT_TRUE(same(iv::pow(entire, 0), Interval(1.0)));
  EXPECT_TRUE(same(iv::pow(Interval(0.0), 0), Interval(1.0)));
  EXPECT_TRUE(iv::pow(empty, 0).isEmpty());
  EXPECT_TRUE(iv::pow(empty, -3).isEmpty());
  EXPECT_TRUE(same(iv::pow(entire, 2), Interval(0.0, kInf)));
  EXPECT_TRUE(same(iv::pow(entire, 3), entire));
  EXPECT_TRUE(same(iv::pow(Interval(0.0), -1), entire));
  EXPECT_TRUE(same(iv::pow(Interval(-1.0, 2.0), -2), entire));
  EXPECT_TRUE(iv::pow(Interval(-2.0, -1.0), 3).contains(-8.0));
  EXPECT_TRUE(iv::pow(Interval(-2.0, -1.0), 3).contains(-1.0));
  EXPECT_TRUE(iv::pow(Interval(-2.0, -1.0), 3).isSubsetOf(Interval(-8.0001, -0.9999)));
  EXPECT_TRUE(iv::pow(Interval(-2.0, 3.0), 2).isSubsetOf(Interval(0.0, 9.0001)));
  EXPECT_TRUE(iv::pow(Interval(-2.0, 3.0), 2).contains(0.0));
  EXPECT_TRUE(iv::pow(Interval(-1.0), INT_MAX).contains(-1.0));
  EXPECT_TRUE(iv::pow(Interval(-1.0), INT_MIN).contains(1.0));
  // 2^-2^31 is positive but below every positive double
  EXPECT_TRUE(iv::pow(Interval(2.0), INT_MIN).isSubsetOf(Interval(-kDen, 1e-307)));
  EXPECT_GT(iv::pow(Interval(2.0), INT_MIN).upper(), 0.0);
  EXPECT_TRUE(same(iv::pow(Interval(2.0), INT_MAX), Interval(kMax, kInf)));
  EXPECT_TRUE(iv::pow(Interval(0.5, 2.0), -3).contains(8.0));
  EXPECT_TRUE(iv::pow(Interval(0.5, 2.0), -3).contains(0.125));
  EXPECT_TRUE(same(iv::pow(Interval(2.0, kInf), 2), Interval(rd::nextDown(4.0), kInf)));
  EXPECT_TRUE(same(iv::pow(Interval(-3.0, 2.0), 2), iv::sqr(Interval(-3.0, 2.0))));
  EXPECT_TRUE(same(iv::pow(Interval(-3.0, 2.0), 1), Interval(-3.0, 2.0)));
  // fma is a * b + c
  EXPECT_TRUE(same(iv::fma(Interval(1.0, 2.0), Interval(3.0), Interval(-1.0)), Interval(1.0, 2.0) * 3.0 - 1.0));
  // sin / cos special inputs
  EXPECT_TRUE(iv::sin(Interval(-0.0)).contains(0.0));
  EXPECT_TRUE(iv::sin(Interval(-0.0)).isSubsetOf(Interval(-2 * kDen, 2 * kDen)));
  EXPECT_TRUE(iv::sin(Interval(-0.0, 0.0)).isSubsetOf(Interval(-2 * kDen, 2 * kDen)));
  EXPECT_TRUE(iv::cos(Interval(0.0)).contains(1.0));
  EXPECT_EQ(iv::cos(Interval(0.0)).upper(), 1.0);
  EXPECT_TRUE(iv::sin(Interval(kMax)).isSubsetOf(Interval(-1.0, 1.0)));
  EXPECT_TRUE(same(iv::sin(Interval(-kMax, kMax)), Interval(-1.0, 1.0)));
}

TEST(IntervalEdge, MixedDoubleArithmeticAndEigen) {
  const Interval a(1.0, 2.0);
  EXPECT_TRUE(same(a * 2.0, 2.0 * a));
  EXPECT_TRUE(same(a + 1.0, 1.0 + a));
  EXPECT_TRUE((1.0 / a).contains(0.5));
  EXPECT_TRUE((3.0 - a).contains(1.0));
  iv::IntervalMatrix6 m = iv::IntervalMatrix6::Identity();
  m(0, 1) = Interval(-0.1, 0.1);
  iv::IntervalVector6 v = iv::IntervalVector6::Constant(Interval(1.0, 1.5));
  const iv::IntervalVector6 w = m * v;
  EXPECT_TRUE(w(0).contains(1.0 + 1.5 * 0.1));
  EXPECT_TRUE(w(0).contains(1.0 - 1.5 * 0.1));
  EXPECT_TRUE(w(5).contains(1.25));
  const Interval d = v.dot(v);
  EXPECT_TRUE(d.contains(6.0) && d.contains(6.0 * 2.25));
  const Eigen::Matrix<double, 6, 1> p = Eigen::Matrix<double, 6, 1>::Constant(1.2);
  const iv::IntervalVector6 q = m * p.cast<Interval>();
  EXPECT_TRUE(q(0).contains(1.2 + 1.2 * 0.1));
  const iv::IntervalVector6 q2 = m * p;  // mixed Interval-double product through ScalarBinaryOpTraits
  EXPECT_TRUE(q2(0).contains(1.2 + 1.2 * 0.1) && q2(0).contains(1.2 - 1.2 * 0.1));
  const Interval n = v.norm();  // Eigen's sqrt finds interval::sqrt by argument-dependent lookup
  EXPECT_TRUE(n.contains(std::sqrt(6.0)) && n.contains(1.5 * std::sqrt(6.0)));
  EXPECT_TRUE(v.squaredNorm().contains(6.0 * 2.25));
  const iv::IntervalMatrix6 mtm = m.transpose() * m;
  EXPECT_TRUE(mtm(1, 1).contains(1.0) && mtm(1, 1).contains(1.01));
  EXPECT_TRUE(m.sum().contains(6.0));
}

}  // namespace
