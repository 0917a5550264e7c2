// interval::Jet2 (second-order forward derivatives, the KinematicModel Hessians): over a box, every component encloses
// the derivatives at every point of the box, computed independently by nested Dual<Dual<double>> at sampled points;
// the rules of every kin:: function and of the quotient are exercised.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "pkm_accuracy/core/interval/Dual.hpp"
#include "pkm_accuracy/core/interval/Jet2.hpp"
#include "pkm_accuracy/core/model/KinematicsMath.hpp"

using namespace pkm_accuracy;
using interval::Interval;
namespace kin = pkm_accuracy::model::kin;

namespace {

// A composition of every rule: products, quotients, sqrt, sin, cos, atan2, constants.
template <typename T>
T f(const T* x) {
  const T r = kin::sqrt(kin::sqr(x[0]) + x[1] * x[2] + 2.0);
  return r / (1.5 + kin::sin(x[0]) * kin::cos(x[1])) + kin::atan2(x[2] + 0.5, x[0] - 2.0) * x[1] - 3.0 * x[2] / r;
}

}  // namespace

TEST(Jet2, EnclosesTheDerivativesOfNestedDualsAtSampledPoints) {
  constexpr int N = 3;
  using J = interval::Jet2<Interval, N>;
  using D1 = interval::Dual<double, N>;
  using D2 = interval::Dual<D1, N>;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> centre(-1.0, 1.0), width(0.0, 0.3), unit(0.0, 1.0);
  int checked = 0;
  for (int s = 0; s < 300; ++s) {
    Interval box[N];
    J x[N];
    for (int i = 0; i < N; ++i) {
      const double c = centre(rng), w = width(rng);
      box[i] = Interval(c - w, c + w);
      x[i] = J::variable(box[i], i);
    }
    const J e = f(x);
    for (int k = 0; k < 20; ++k) {
      D2 p[N];
      for (int i = 0; i < N; ++i) {
        const double v = box[i].lower() + unit(rng) * (box[i].upper() - box[i].lower());
        p[i] = D2::variable(D1::variable(v, i), i);
      }
      const D2 r = f(p);
      const double slack = 1e-12;
      EXPECT_TRUE(e.value().contains(r.value().value()) ||
                  std::abs(r.value().value() - e.value().mid()) <= e.value().rad() + slack);
      for (int a = 0; a < N; ++a) {
        EXPECT_LE(e.d(a).lower() - slack, r.value().d(a));
        EXPECT_GE(e.d(a).upper() + slack, r.value().d(a));
        for (int b = 0; b < N; ++b) {
          EXPECT_LE(e.d2(a, b).lower() - slack, r.d(a).d(b)) << a << b;
          EXPECT_GE(e.d2(a, b).upper() + slack, r.d(a).d(b)) << a << b;
          ++checked;
        }
      }
    }
  }
  EXPECT_EQ(checked, 300 * 20 * 9);
}

TEST(Jet2, MatchesNestedDualsAtAPoint) {
  // On a degenerate box the enclosures are a few ulps wide around the nested duals' values.
  constexpr int N = 3;
  using J = interval::Jet2<Interval, N>;
  using D1 = interval::Dual<double, N>;
  using D2 = interval::Dual<D1, N>;
  const double v[N] = {0.3, -0.2, 0.7};
  J x[N];
  D2 p[N];
  for (int i = 0; i < N; ++i) {
    x[i] = J::variable(Interval(v[i]), i);
    p[i] = D2::variable(D1::variable(v[i], i), i);
  }
  const J e = f(x);
  const D2 r = f(p);
  for (int a = 0; a < N; ++a)
    for (int b = 0; b < N; ++b) {
      EXPECT_NEAR(e.d2(a, b).mid(), r.d(a).d(b), 1e-12);
      EXPECT_LT(e.d2(a, b).rad(), 1e-12);
    }
}
