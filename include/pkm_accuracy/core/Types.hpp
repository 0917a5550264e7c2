// Small fixed-capacity vector and matrix types shared by the core. Sizes are dynamic (a planar robot has 3 degrees
// of freedom, a Gough platform 6) but never exceed kMaxDof, so nothing allocates on the heap in the hot loops.
#pragma once

#include <array>

#include <Eigen/Core>

#include "pkm_accuracy/core/interval/Dual.hpp"
#include "pkm_accuracy/core/interval/Eigen.hpp"
#include "pkm_accuracy/core/interval/Interval.hpp"

namespace pkm_accuracy {

using interval::Interval;

/// Largest number of pose degrees of freedom (= legs) and of box variables a model may have.
constexpr int kMaxDof = 6;

using DVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxDof, 1>;
using DMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxDof, kMaxDof>;
using IVec = Eigen::Matrix<Interval, Eigen::Dynamic, 1, 0, kMaxDof, 1>;
using IMat = Eigen::Matrix<Interval, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxDof, kMaxDof>;

/// Value and gradient (with respect to up to kMaxDof box variables) enclosed over a box.
using DualI = interval::Dual<Interval, kMaxDof>;

/// The pose, each coordinate as a function of the box variables (value + gradient enclosures).
using DualPose = std::array<DualI, kMaxDof>;

/// Enclosures of a matrix-valued function over a box: its value and its partial derivative with respect to each
/// box variable.
struct MatrixWithGradient {
  IMat value;
  std::array<IMat, kMaxDof> d;
};

}  // namespace pkm_accuracy
