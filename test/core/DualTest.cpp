// Dual<T, N>: derivative enclosures over boxes (T = Interval) and point derivatives (T = double), compared with
// hand-derived derivative formulas evaluated in MPFR at 300 bits (no finite differences).
//
// Functions: f1 = sqrt(x^2 + y^2); f2 = sin(x) cos(y) / (1 + x^2); f3 = the length of a Gough-platform leg,
// |p + R(roll, pitch, yaw) b - a| with R = Rz(yaw) Ry(pitch) Rx(roll), differentiated with respect to the six pose
// coordinates. For random small boxes (and degenerate ones) the interval value and gradient must contain the exact
// value and gradient at random points of the box and at its corners. The MPFR evaluation error is far below 2^-250
// relative to the magnitudes involved; containment is required with a margin of 2^-200 (1 + |v|), which makes the
// check slightly stronger than plain containment and rigorous despite the MPFR rounding.
#include <gtest/gtest.h>
#include <mpfr.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "pkm_accuracy/core/interval/Dual.hpp"
#include "pkm_accuracy/core/interval/Functions.hpp"
#include "pkm_accuracy/core/interval/Interval.hpp"

namespace {

using pkm_accuracy::interval::Dual;
using pkm_accuracy::interval::Interval;
namespace iv = pkm_accuracy::interval;

// ---- a minimal MPFR scalar -------------------------------------------------------------------------------------
class M {
 public:
  static constexpr mpfr_prec_t kPrec = 300;
  M() {
    mpfr_init2(v_, kPrec);
    mpfr_set_zero(v_, 1);
  }
  M(double x) {  // NOLINT(runtime/explicit)
    mpfr_init2(v_, kPrec);
    mpfr_set_d(v_, x, MPFR_RNDN);
  }
  M(const M& o) {
    mpfr_init2(v_, kPrec);
    mpfr_set(v_, o.v_, MPFR_RNDN);
  }
  M& operator=(const M& o) {
    mpfr_set(v_, o.v_, MPFR_RNDN);
    return *this;
  }
  ~M() { mpfr_clear(v_); }
  friend M operator+(const M& a, const M& b) { return op(mpfr_add, a, b); }
  friend M operator-(const M& a, const M& b) { return op(mpfr_sub, a, b); }
  friend M operator*(const M& a, const M& b) { return op(mpfr_mul, a, b); }
  friend M operator/(const M& a, const M& b) { return op(mpfr_div, a, b); }
  friend M operator-(const M& a) {
    M r;
    mpfr_neg(r.v_, a.v_, MPFR_RNDN);
    return r;
  }
  friend M sin(const M& a) { return fn(mpfr_sin, a); }
  friend M cos(const M& a) { return fn(mpfr_cos, a); }
  friend M sqrt(const M& a) { return fn(mpfr_sqrt, a); }
  double toDouble() const { return mpfr_get_d(v_, MPFR_RNDN); }

  /// v lies in r with a margin of 2^-200 (1 + |v|) on both sides.
  bool insideWithMargin(const Interval& r) const {
    if (r.isEmpty()) return false;
    M e, t;
    mpfr_abs(e.v_, v_, MPFR_RNDN);
    mpfr_add_ui(e.v_, e.v_, 1, MPFR_RNDN);
    mpfr_mul_2si(e.v_, e.v_, -200, MPFR_RNDN);
    mpfr_sub(t.v_, v_, e.v_, MPFR_RNDD);
    if (mpfr_cmp_d(t.v_, r.lower()) < 0) return false;
    mpfr_add(t.v_, v_, e.v_, MPFR_RNDU);
    return mpfr_cmp_d(t.v_, r.upper()) <= 0;
  }

 private:
  template <typename F>
  static M op(F f, const M& a, const M& b) {
    M r;
    f(r.v_, a.v_, b.v_, MPFR_RNDN);
    return r;
  }
  template <typename F>
  static M fn(F f, const M& a) {
    M r;
    f(r.v_, a.v_, MPFR_RNDN);
    return r;
  }
  mpfr_t v_;
};

// ---- the functions, generic over the scalar (double, Interval, Dual) ----------------------------------------------
template <typename S>
S f1(const S* v) {
  using std::sqrt;
  return sqrt(sqr(v[0]) + sqr(v[1]));
}
template <typename S>
S f2(const S* v) {
  using std::cos;
  using std::sin;
  return sin(v[0]) * cos(v[1]) / (1.0 + sqr(v[0]));
}

struct Leg {
  std::array<double, 3> a, b;  // base and platform anchors
};

// Same structure as the Gough-platform kinematics: explicit rotation entries from the sines and cosines.
template <typename S>
S f3(const S* pose, const Leg& leg) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const S sr = sin(pose[3]), cr = cos(pose[3]);
  const S sp = sin(pose[4]), cp = cos(pose[4]);
  const S sy = sin(pose[5]), cy = cos(pose[5]);
  const S r[3][3] = {{cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr},
                     {sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr},
                     {-sp, cp * sr, cp * cr}};
  S d[3];
  for (int k = 0; k < 3; ++k) {
    d[k] = pose[k] + r[k][0] * leg.b[0] + r[k][1] * leg.b[1] + r[k][2] * leg.b[2] - leg.a[k];
  }
  return sqrt(sqr(d[0]) + sqr(d[1]) + sqr(d[2]));
}

// ---- hand-derived values and gradients in MPFR ----------------------------------------------------------------
std::vector<M> exact1(const double* p) {
  const M x(p[0]), y(p[1]);
  const M r = sqrt(x * x + y * y);
  return {r, x / r, y / r};
}

std::vector<M> exact2(const double* p) {
  const M x(p[0]), y(p[1]);
  const M q = M(1.0) + x * x;
  const M f = sin(x) * cos(y) / q;
  const M fx = cos(x) * cos(y) / q - M(2.0) * x * sin(x) * cos(y) / (q * q);
  const M fy = -sin(x) * sin(y) / q;
  return {f, fx, fy};
}

using M3 = std::array<std::array<M, 3>, 3>;
M3 mul(const M3& a, const M3& b) {
  M3 c;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
  return c;
}

// L = |d|, d = p + R b - a, R = Rz(yaw) Ry(pitch) Rx(roll). dL/dp_k = d_k / L; dL/dtheta = d . (dR/dtheta b) / L,
// with dR/droll = Rz Ry Rx', dR/dpitch = Rz Ry' Rx, dR/dyaw = Rz' Ry Rx and
//   Rx' = [[0,0,0],[0,-s,-c],[0,c,-s]], Ry' = [[-s,0,c],[0,0,0],[-c,0,-s]], Rz' = [[-s,-c,0],[c,-s,0],[0,0,0]].
std::vector<M> exact3(const double* pose, const Leg& leg) {
  const M zero(0.0), one(1.0);
  const M sr = sin(M(pose[3])), cr = cos(M(pose[3]));
  const M sp = sin(M(pose[4])), cp = cos(M(pose[4]));
  const M sy = sin(M(pose[5])), cy = cos(M(pose[5]));
  const M3 rx = {{{one, zero, zero}, {zero, cr, -sr}, {zero, sr, cr}}};
  const M3 ry = {{{cp, zero, sp}, {zero, one, zero}, {-sp, zero, cp}}};
  const M3 rz = {{{cy, -sy, zero}, {sy, cy, zero}, {zero, zero, one}}};
  const M3 drx = {{{zero, zero, zero}, {zero, -sr, -cr}, {zero, cr, -sr}}};
  const M3 dry = {{{-sp, zero, cp}, {zero, zero, zero}, {-cp, zero, -sp}}};
  const M3 drz = {{{-sy, -cy, zero}, {cy, -sy, zero}, {zero, zero, zero}}};
  const M3 r = mul(rz, mul(ry, rx));
  const M3 dR[3] = {mul(rz, mul(ry, drx)), mul(rz, mul(dry, rx)), mul(drz, mul(ry, rx))};
  M d[3];
  for (int k = 0; k < 3; ++k) {
    d[k] = M(pose[k]) + r[k][0] * M(leg.b[0]) + r[k][1] * M(leg.b[1]) + r[k][2] * M(leg.b[2]) - M(leg.a[k]);
  }
  const M len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  std::vector<M> out = {len, d[0] / len, d[1] / len, d[2] / len};
  for (int t = 0; t < 3; ++t) {
    M dot(0.0);
    for (int k = 0; k < 3; ++k) {
      dot = dot + d[k] * (dR[t][k][0] * M(leg.b[0]) + dR[t][k][1] * M(leg.b[1]) + dR[t][k][2] * M(leg.b[2]));
    }
    out.push_back(dot / len);
  }
  return out;
}

// ---- random boxes -----------------------------------------------------------------------------------------------
class Gen {
 public:
  explicit Gen(std::uint64_t seed) : rng_(seed) {}
  double unit() { return static_cast<double>(rng_() >> 11) * 0x1p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }
  double radius() {
    switch (rng_() % 4) {
      case 0:
        return 0.0;  // degenerate box
      case 1:
        return std::ldexp(unit(), -30);
      default:
        return std::ldexp(1.0 + unit(), -static_cast<int>(7 + rng_() % 14));  // 2^-20 .. 2^-6
    }
  }
  std::uint64_t bits() { return rng_(); }

 private:
  std::mt19937_64 rng_;
};

template <int N>
struct Box {
  std::array<double, N> lo, hi;
  double point(Gen& g, int i, int corner) const {
    if (corner >= 0) return ((corner >> i) & 1) ? hi[i] : lo[i];
    return std::min(std::max(lo[i] + (hi[i] - lo[i]) * g.unit(), lo[i]), hi[i]);
  }
};

template <int N>
Box<N> randomBox(Gen& g, const std::array<double, N>& cmin, const std::array<double, N>& cmax) {
  Box<N> b;
  for (int i = 0; i < N; ++i) {
    const double c = g.uniform(cmin[i], cmax[i]), r = g.radius();
    b.lo[i] = c - r;
    b.hi[i] = c + r;
    if (b.hi[i] < b.lo[i]) std::swap(b.lo[i], b.hi[i]);
  }
  return b;
}

struct Stats {
  long boxes = 0, points = 0, failures = 0;  // NOLINT(runtime/int)
  std::vector<std::string> messages;
};

// Evaluates f over the box with Dual<Interval, N>, then checks value and gradient against the exact ones at random
// points and corners of the box.
template <int N>
void checkEnclosures(const char* name, Gen& g, const Box<N>& box,
                     const std::function<Dual<Interval, N>(const Dual<Interval, N>*)>& f,
                     const std::function<std::vector<M>(const double*)>& exact, Stats* st) {
  using D = Dual<Interval, N>;
  D vars[N];
  for (int i = 0; i < N; ++i) vars[i] = D::variable(Interval(box.lo[i], box.hi[i]), i);
  const D r = f(vars);
  ++st->boxes;
  for (int k = 0; k < 8; ++k) {
    double p[N];
    const int corner = k < 2 ? static_cast<int>(g.bits() % (1u << N)) : -1;
    for (int i = 0; i < N; ++i) p[i] = box.point(g, i, corner);
    const std::vector<M> e = exact(p);
    ++st->points;
    bool ok = e[0].insideWithMargin(r.value());
    for (int i = 0; i < N; ++i) ok = ok && e[1 + i].insideWithMargin(r.d(i));
    if (!ok) {
      ++st->failures;
      if (st->messages.size() < 5) {
        std::string m = std::string(name) + ": point";
        for (int i = 0; i < N; ++i) m += " " + std::to_string(p[i]);
        m += " value " + std::to_string(e[0].toDouble()) + " in [" + std::to_string(r.value().lower()) + ", " +
             std::to_string(r.value().upper()) + "]";
        for (int i = 0; i < N; ++i) {
          m += " d" + std::to_string(i) + " " + std::to_string(e[1 + i].toDouble()) + " in [" +
               std::to_string(r.d(i).lower()) + ", " + std::to_string(r.d(i).upper()) + "]";
        }
        st->messages.push_back(m);
      }
    }
  }
  // Degenerate boxes: the enclosures must be tight (guards against a derivative rule that returns huge intervals).
  bool degenerate = true;
  for (int i = 0; i < N; ++i) degenerate = degenerate && box.lo[i] == box.hi[i];
  if (degenerate) {
    for (int i = -1; i < N; ++i) {
      const Interval& v = i < 0 ? r.value() : r.d(i);
      if (!(v.width() <= 1e-13 * (1.0 + v.mag()))) {
        ++st->failures;
        if (st->messages.size() < 5) st->messages.push_back(std::string(name) + ": loose enclosure on a point");
      }
    }
  }
}

void report(const char* name, const Stats& st) {
  for (const std::string& m : st.messages) ADD_FAILURE() << m;
  EXPECT_EQ(st.failures, 0) << name;
  std::printf("[ dual   ] %s: %ld boxes, %ld points checked\n", name, st.boxes, st.points);
}

TEST(DualEnclosure, Norm2D) {
  Gen g(11);
  Stats st;
  for (int b = 0; b < 20000; ++b) {
    const Box<2> box = randomBox<2>(g, {-3.0, -3.0}, {3.0, 3.0});
    if (box.lo[0] <= 0.0 && box.hi[0] >= 0.0 && box.lo[1] <= 0.0 && box.hi[1] >= 0.0) continue;  // singular at 0
    checkEnclosures<2>(
        "sqrt(x^2 + y^2)", g, box, [](const Dual<Interval, 2>* v) { return f1(v); }, exact1, &st);
  }
  report("sqrt(x^2 + y^2)", st);
}

TEST(DualEnclosure, TrigonometricQuotient) {
  Gen g(12);
  Stats st;
  for (int b = 0; b < 20000; ++b) {
    const Box<2> box = randomBox<2>(g, {-6.0, -6.0}, {6.0, 6.0});
    checkEnclosures<2>(
        "sin(x) cos(y) / (1 + x^2)", g, box, [](const Dual<Interval, 2>* v) { return f2(v); }, exact2, &st);
  }
  report("sin(x) cos(y) / (1 + x^2)", st);
}

TEST(DualEnclosure, GoughLegLength) {
  Gen g(13);
  Stats st;
  for (int b = 0; b < 5000; ++b) {
    Leg leg;
    for (int k = 0; k < 3; ++k) {
      leg.a[k] = g.uniform(-1.0, 1.0);
      leg.b[k] = g.uniform(-0.4, 0.4);
    }
    leg.a[2] = 0.0;
    const Box<6> box = randomBox<6>(g, {-0.3, -0.3, 0.6, -0.5, -0.5, -3.1}, {0.3, 0.3, 1.2, 0.5, 0.5, 3.1});
    checkEnclosures<6>(
        "|p + R b - a|", g, box, [&leg](const Dual<Interval, 6>* v) { return f3(v, leg); },
        [&leg](const double* p) { return exact3(p, leg); }, &st);
  }
  report("|p + R b - a|", st);
}

// Dual<double, N> at points: matches the hand formulas to a few ulps of the magnitudes involved.
TEST(DualPoint, MatchesHandFormulas) {
  Gen g(14);
  long checked = 0;  // NOLINT(runtime/int)
  double worst = 0.0;
  auto compare = [&](const Dual<double, 6>& r, const std::vector<M>& e, int n) {
    for (int i = 0; i <= n; ++i) {
      const double got = i == 0 ? r.value() : r.d(i - 1);
      const double want = e[i].toDouble();
      const double err = std::fabs(got - want) / (1.0 + std::fabs(want));
      worst = std::max(worst, err);
      EXPECT_LE(err, 1e-13) << "component " << i << ": " << got << " vs " << want;
      ++checked;
    }
  };
  using D = Dual<double, 6>;
  for (int k = 0; k < 20000; ++k) {
    D v[6];
    double p[6];
    for (int i = 0; i < 6; ++i) {
      p[i] = g.uniform(-2.0, 2.0);
      v[i] = D::variable(p[i], i);
    }
    compare(f1(v), exact1(p), 2);
    compare(f2(v), exact2(p), 2);
    Leg leg;
    for (int j = 0; j < 3; ++j) {
      leg.a[j] = g.uniform(-1.0, 1.0);
      leg.b[j] = g.uniform(-0.4, 0.4);
    }
    compare(f3(v, leg), exact3(p, leg), 6);
  }
  std::printf("[ dual   ] Dual<double, 6>: %ld components, worst relative error %.3g\n", checked, worst);
}

TEST(DualPoint, ScalarMixingAndRules) {
  using D = Dual<double, 2>;
  using DI = Dual<Interval, 2>;
  const D x = D::variable(3.0, 0), y = D::variable(2.0, 1);
  // built-in constants on both sides (int and double), and the base scalar
  const D e = 2.0 * x + x * 2 - 1 + 1.0 - x / 2.0 + 6 / y - (1 - y) + (y - 1.0) * 0.5;
  // value: 6 + 6 - 1 + 1 - 1.5 + 3 - (-1) + 0.5 = 15; d/dx = 2 + 2 - 0.5 = 3.5; d/dy = -6/4 + 1 + 0.5 = 0
  EXPECT_DOUBLE_EQ(e.value(), 15.0);
  EXPECT_DOUBLE_EQ(e.d(0), 3.5);
  EXPECT_DOUBLE_EQ(e.d(1), 0.0);
  D acc = x;
  acc += y;
  acc -= 1.0;
  acc *= y;
  acc /= x;
  // ((x + y - 1) y) / x at (3, 2): 8/3; d/dx = (y x - (x + y - 1) y) / x^2 = (6 - 8) / 9; d/dy = (x + 2y - 1) / x
  EXPECT_DOUBLE_EQ(acc.value(), 8.0 / 3.0);
  EXPECT_DOUBLE_EQ(acc.d(0), -2.0 / 9.0);
  EXPECT_DOUBLE_EQ(acc.d(1), 6.0 / 3.0);
  const D s = sqrt(sqr(x) + sqr(y)) + sin(x) * cos(y) + (-x) + (+y);
  EXPECT_NEAR(s.d(0), 3.0 / std::sqrt(13.0) + std::cos(3.0) * std::cos(2.0) - 1.0, 1e-15);
  // interval duals with double, int and Interval constants
  const DI xi = DI::variable(Interval(1.0, 2.0), 0);
  const DI ei = 2.0 * xi + xi * 2 + Interval(1.0) * xi + xi / 4.0 + 1 / xi - 3 + Interval(0.5);
  EXPECT_TRUE(ei.d(0).contains(2.0 + 2.0 + 1.0 + 0.25 - 1.0));           // at x = 1
  EXPECT_TRUE(ei.d(0).contains(2.0 + 2.0 + 1.0 + 0.25 - 0.25));          // at x = 2
  EXPECT_TRUE(ei.value().contains(2.0 + 2.0 + 1.0 + 0.25 + 1.0 - 2.5));  // at x = 1
  EXPECT_TRUE(ei.d(1).contains(0.0));
  EXPECT_LE(ei.d(1).mag(), 1e-300);  // zero, up to the outward rounding of 0 * constant
  // sqrt at a box touching 0: derivative unbounded, value still enclosed
  const DI r = sqrt(DI::variable(Interval(0.0, 1.0), 0));
  EXPECT_TRUE(r.value().contains(0.0) && r.value().contains(1.0));
  EXPECT_FALSE(r.d(0).isBounded());
}

}  // namespace
