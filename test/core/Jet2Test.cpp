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
struct EveryRule {
  template <typename T>
  T operator()(const T* x) const {
    const T r = kin::sqrt(kin::sqr(x[0]) + x[1] * x[2] + 2.0);
    return r / (1.5 + kin::sin(x[0]) * kin::cos(x[1])) + kin::atan2(x[2] + 0.5, x[0] - 2.0) * x[1] - 3.0 * x[2] / r;
  }
};

// Every rule with each operand of each order a Jet2 tracks (Jet2::order): constants of the jet type itself (order
// 0), the variables and their sums (order 1), and general jets (order 2), in every pairing, so that a term the rules
// skip as an exact zero that is not one makes the enclosures miss the nested duals' values.
struct EveryOrderPairing {
  template <typename T>
  T operator()(const T* x) const {
    const T c(1.25), d(-0.5);
    const T constants = kin::sqrt(c * c + d * d) / (c - d) + kin::atan2(d, c) * kin::sin(c) - kin::cos(d) / c;
    const T linear = x[0] + x[1], linear2 = x[1] - x[2] * 2.0;
    const T general = kin::sin(x[0]) * x[2];
    return constants * linear + c * general + linear * linear2 + linear * general + kin::sin(general) * c +
           linear / (linear2 * linear2 + 1.0) + general * linear - d / (general * general + 0.5) + linear2 / c +
           c / (linear + 3.0) + kin::sqrt(linear + 4.0) * kin::atan2(linear2, c + x[0] * 0.5) +
           kin::cos(linear) * general / (general * general + c) - (linear - linear) * d + general / (linear * c + 4.0);
  }
};

template <typename F>
void expectEnclosesNestedDualsAtSampledPoints(F f) {
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

}  // namespace

TEST(Jet2, EnclosesTheDerivativesOfNestedDualsAtSampledPoints) {
  expectEnclosesNestedDualsAtSampledPoints(EveryRule());
}

TEST(Jet2, SkipsOnlyExactZerosForConstantsVariablesAndGeneralJets) {
  expectEnclosesNestedDualsAtSampledPoints(EveryOrderPairing());
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
  const J e = EveryRule()(x);
  const D2 r = EveryRule()(p);
  for (int a = 0; a < N; ++a)
    for (int b = 0; b < N; ++b) {
      EXPECT_NEAR(e.d2(a, b).mid(), r.d(a).d(b), 1e-12);
      EXPECT_LT(e.d2(a, b).rad(), 1e-12);
    }
}
