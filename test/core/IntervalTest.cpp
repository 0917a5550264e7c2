#include <gtest/gtest.h>

#include "pkm_accuracy/core/interval/Dual.hpp"
#include "pkm_accuracy/core/interval/Eigen.hpp"
#include "pkm_accuracy/core/interval/Functions.hpp"
#include "pkm_accuracy/core/interval/Interval.hpp"

using pkm_accuracy::interval::Interval;

TEST(Interval, AdditionContainsExactSum) {
  const Interval a(0.1), b(0.2);
  const Interval s = a + b;
  EXPECT_LT(s.lower(), 0.30000000000000004);
  EXPECT_GT(s.upper(), 0.3);
}
