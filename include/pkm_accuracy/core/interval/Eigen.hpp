// Eigen support for Interval: Matrix<Interval, R, C> works with +, -, * and the usual expressions.
// Decompositions that compare or divide by pivots (LU, QR, ...) are NOT meaningful on intervals: use the
// interval solvers of core/enclosure instead.
#pragma once

#include <Eigen/Core>

#include "pkm_accuracy/core/interval/Interval.hpp"

namespace Eigen {

template <>
struct NumTraits<pkm_accuracy::interval::Interval> : GenericNumTraits<double> {
  using Real = pkm_accuracy::interval::Interval;
  using NonInteger = pkm_accuracy::interval::Interval;
  using Nested = pkm_accuracy::interval::Interval;
  using Literal = pkm_accuracy::interval::Interval;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = 2,
    AddCost = 6,
    MulCost = 12,
  };
};

template <typename BinaryOp>
struct ScalarBinaryOpTraits<pkm_accuracy::interval::Interval, double, BinaryOp> {
  using ReturnType = pkm_accuracy::interval::Interval;
};
template <typename BinaryOp>
struct ScalarBinaryOpTraits<double, pkm_accuracy::interval::Interval, BinaryOp> {
  using ReturnType = pkm_accuracy::interval::Interval;
};

}  // namespace Eigen

namespace pkm_accuracy {
namespace interval {

template <int R, int C>
using IntervalMatrix = Eigen::Matrix<Interval, R, C>;
using IntervalVector6 = Eigen::Matrix<Interval, 6, 1>;
using IntervalMatrix6 = Eigen::Matrix<Interval, 6, 6>;

}  // namespace interval
}  // namespace pkm_accuracy
