// Small fixed-capacity vector and matrix types shared by the core. Sizes are dynamic (a planar robot has 3 degrees
// of freedom, a Gough platform 6) but never exceed kMaxDof, so nothing allocates on the heap in the hot loops.
#pragma once

#include <array>
#include <utility>

#include <Eigen/Core>

#include "pkm_accuracy/core/interval/Dual.hpp"
#include "pkm_accuracy/core/interval/Eigen.hpp"
#include "pkm_accuracy/core/interval/Interval.hpp"
#include "pkm_accuracy/core/interval/MidRad.hpp"

namespace pkm_accuracy {

using interval::Interval;

/// Largest number of pose degrees of freedom (= legs) and of box variables a model may have.
constexpr int kMaxDof = 6;

using DVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxDof, 1>;
using DMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxDof, kMaxDof>;
using IVec = Eigen::Matrix<Interval, Eigen::Dynamic, 1, 0, kMaxDof, 1>;
using IMat = Eigen::Matrix<Interval, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxDof, kMaxDof>;

/// Largest number of uncertain geometry parameters a model may expose (Gough platform: 36 anchor coordinates + 3
/// tool-point coordinates).
constexpr int kMaxGeometryParameters = 48;
/// Per geometry parameter values (fixed capacity, no heap).
using GVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxGeometryParameters, 1>;
/// Per component (rows) and geometry parameter (columns) values.
using GMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxDof, kMaxGeometryParameters>;

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

/// Enclosures over a box of the first and second derivatives of a matrix-valued function of the kMaxDof pose
/// coordinates: first[a] = dM / dq_a, d[index(a, b)] = d^2 M / dq_a dq_b (symmetric: one matrix per pair a <= b).
struct MatrixHessian {
  static constexpr int kPairs = kMaxDof * (kMaxDof + 1) / 2;
  std::array<IMat, kMaxDof> first;
  std::array<IMat, kPairs> d;
  /// Index of the pair (a, b), either order (0 <= a, b < kMaxDof).
  static int index(int a, int b) {
    if (a > b) std::swap(a, b);
    return a * kMaxDof - a * (a - 1) / 2 + (b - a);
  }
};

/// Enclosure of the derivative of one row of J^-1 with respect to one uncertain geometry parameter (a parameter may
/// move several rows: one entry per row it moves).
struct GeometryRowDerivative {
  int parameter = 0;
  int row = 0;
  std::array<interval::MidRad, kMaxDof> d;  ///< midpoint-radius form (what the enclosures use)
  /// Optional (affine = true): the same derivative as a first-order affine form in the pose. For every pose t of the
  /// box and every admissible geometry there is one tau in [-1, 1]^kMaxDof, the same for every component of every
  /// entry of the GeometryDerivatives (tau_m: pose coordinate m, scaled to the box), with component l of d in
  ///   centre[l] + sum_m slope[l][m] tau_m + [-radius[l], radius[l]].
  /// So dot products d . v keep the correlations between the components, which `d` loses (each component varies
  /// over the whole box independently).
  bool affine = false;
  std::array<double, kMaxDof> centre, radius;
  std::array<std::array<double, kMaxDof>, kMaxDof> slope;
  /// Optional (parameterSlopes = true, only where GeometryDerivatives::withParameterSlopes asked for it): the affine
  /// form also has terms in the geometry parameters of the row's leg, and `radius` is then only its remainder: for
  /// every pose of the box and every admissible geometry, component l of d lies in
  ///   centre[l] + sum_m slope[l][m] tau_m + sum_s parameterSlope[l][s] gamma_s + [-radius[l], radius[l]],
  /// gamma_s = (g_q - g0_q) / parameterScale[s] in [-1, 1] for the parameter q = slopeParameter[s] (s unused where it
  /// is -1), g0 the centre of the parameters' ranges (RobotModel::geometryParameterCentre).
  bool parameterSlopes = false;
  std::array<int, kMaxDof> slopeParameter;
  std::array<double, kMaxDof> parameterScale;
  std::array<std::array<double, kMaxDof>, kMaxDof> parameterSlope;
};

/// Derivatives of J^-1 with respect to every uncertain geometry parameter, as row entries (fixed capacity).
struct GeometryDerivatives {
  static constexpr int kCapacity = 64;
  /// Set by the caller: the entries' affine forms with their geometry terms apart where the model can
  /// (GeometryRowDerivative::parameterSlopes); else `radius` covers every geometry.
  bool withParameterSlopes = false;
  int count = 0;
  std::array<GeometryRowDerivative, kCapacity> entries;
};

}  // namespace pkm_accuracy
