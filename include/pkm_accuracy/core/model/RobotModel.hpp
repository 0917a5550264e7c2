// Interface of a parallel kinematic machine for accuracy analysis. A model knows its inverse Jacobian J^-1(X)
// (row j: how the length of leg j changes with the pose), point-exactly in double and as interval enclosures over
// boxes of poses, for every admissible geometry (bounded geometric uncertainty enters as interval coefficients).
//
// Everything here is ROS-free and thread-safe for concurrent const use.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "pkm_accuracy/core/Types.hpp"

namespace pkm_accuracy {
namespace model {

class RobotModel {
 public:
  virtual ~RobotModel() = default;

  /// Number of pose coordinates, equal to the number of legs (J^-1 is square).
  virtual int dof() const = 0;
  /// Short identifier ("gough6", "planar3rpr").
  virtual std::string name() const = 0;
  /// Name and unit of pose coordinate / error component k, e.g. "x [m]", "roll [rad]".
  virtual std::string componentName(int k) const = 0;
  /// Name and unit of joint (sensor) j, e.g. "leg_2 [m]", "crank_0 [rad]"; sensorError()[j] is in that unit.
  virtual std::string jointName(int j) const;
  /// True for the components measured in radians.
  virtual bool isAngular(int k) const = 0;
  /// e_j: bound on the sensor error of leg j (m).
  virtual const std::vector<double>& sensorError() const = 0;
  /// True when the geometry is only known within bounds (then the interval methods enclose every geometry).
  virtual bool hasGeometryUncertainty() const = 0;

  // ---- point evaluation with the nominal geometry (double; not certified) ------------------------------------
  /// J^-1 at a pose.
  virtual DMat inverseJacobian(const DVec& pose) const = 0;
  /// Joint coordinates at a pose (inverse kinematics: leg lengths, crank angles, ...; jointName() gives the units).
  virtual DVec legLengths(const DVec& pose) const = 0;

  // ---- certified enclosures over every admissible geometry ------------------------------------------------------
  /// Enclosure of { J^-1(X) : X in pose box, geometry admissible }. Where it is bounded, J^-1 must be continuous
  /// over the box (for the models here: no leg length can be zero there, since the division by an interval that
  /// contains zero is unbounded); the verifier's singularity certificate relies on it.
  virtual IMat inverseJacobian(const IVec& pose) const = 0;
  /// Enclosures of J^-1 and of its derivatives with respect to the box variables, for a pose given as a function
  /// of those variables (value + gradient), e.g. the identity map of a workspace box or a trajectory.
  virtual void inverseJacobian(const DualPose& pose, MatrixWithGradient& out) const = 0;

  // ---- geometry parameters (bounded uncertainty as variables) --------------------------------------------------
  // The uncertain coordinates of the geometry (those with a non-zero half-width) as parameters p = 0..count-1, each
  // ranging over an interval. They let the enclosures keep the correlations of the uncertainty (first-order terms
  // per parameter, strategy (b) of the seed paper without extra dimensions) and let a search bisect them
  // (restrictGeometry). Models without this support keep the defaults: uncertainty as interval coefficients only.

  /// Number of uncertain geometry parameters (<= kMaxGeometryParameters); 0 when the geometry is exact.
  virtual int geometryParameterCount() const { return 0; }
  /// Name of parameter p, e.g. "base_anchors[2].y". @throws InvalidArgument if p is out of range.
  virtual std::string geometryParameterName(int p) const;
  /// The interval parameter p ranges over (m). @throws InvalidArgument if p is out of range.
  virtual Interval geometryParameterRange(int p) const;
  /// The value of parameter p that inverseJacobianAtGeometryCentre() uses (a point of the range, near its middle).
  virtual double geometryParameterCentre(int p) const;
  /// Doubles that parameter p may take as the geometry was given (nominal value +- half-width as real numbers): an
  /// interval of doubles inside that set (rounded inward: at most an ulp narrower at each end than the largest one),
  /// within geometryParameterRange(p) (which is rounded outward, so its ends may lie an ulp outside the set).
  /// Geometry points that results report are taken in it. Default: the range.
  /// @throws InvalidArgument if p is out of range.
  virtual Interval geometryParameterAdmissible(int p) const { return geometryParameterRange(p); }
  /// The coordinate (0: x, 1: y, 2: z, platform frame) of the tool point c that parameter p is, or -1 if p is not
  /// one. Moving the error reference point only changes the error of the point, not the motion: for two geometries
  /// g, g' that differ in c alone, J(X, g) = T(R(X) (c - c')) J(X, g') with T(v) = [[I, -[v]x], [0, I]] (6 x 6,
  /// [v]x the cross-product matrix). So the rotation rows of J do not depend on c, and the translation rows are
  /// affine in c: each translation component f_k is convex in c, and its maximum over a box of tool points is
  /// attained at the box's vertices (MeanValueEnclosure bounds it there).
  virtual int toolPointCoordinate(int /*p*/) const { return -1; }
  /// Enclosure of J^-1 over a pose box with every geometry parameter at its centre value.
  virtual IMat inverseJacobianAtGeometryCentre(const IVec& pose) const { return inverseJacobian(pose); }
  /// inverseJacobian(DualPose) with every geometry parameter at its centre value.
  virtual void inverseJacobianAtGeometryCentre(const DualPose& pose, MatrixWithGradient& out) const {
    inverseJacobian(pose, out);
  }
  /// Enclosures, over a pose box with every geometry parameter at its centre value, of the first and (with
  /// `second`) the second derivatives of J^-1 with respect to the pose coordinates (for centred forms of the first
  /// derivatives, which keep the cancellations between legs that the derivatives' own enclosures lose). They may be
  /// computed more cheaply and slightly more loosely than inverseJacobianAtGeometryCentre(DualPose). @return false if
  /// the model does not provide them.
  virtual bool inverseJacobianHessianAtGeometryCentre(const IVec& /*pose*/, MatrixHessian& /*out*/,
                                                      bool /*second*/ = true) const {
    return false;
  }
  /// Upper bounds, over a pose box with every geometry parameter at its centre value, of |C d^2 J^-1 / dt_i dt_l|
  /// entry by entry for a given matrix C (out[MatrixHessian::index(i, l)]), where the model can keep the first-order
  /// correlations of the second derivatives over the box (affine forms), so that the products with C cancel between
  /// legs where the interval enclosures' |C| rad(H) does not.
  /// The model's affine forms give H_il(t) in Hc + sum_m A_m tau_m +- R entry by entry, tau_m = (t_m - mid_m) /
  /// (half-width of pose coordinate m) in [-1, 1]. Without `linear`, out[p] bounds |C Hc| + sum_m |C A_m| + |C| R;
  /// with it, out[p] bounds |C Hc| + |C| R and linear[p] bounds sum_m |C A_m|, the part that varies linearly in tau,
  /// so that |C H_il(t0 + s dt)| <= out[p] + s linear[p] on the segments from the box midpoint t0 (s in [0, 1]):
  /// mean-value and Taylor forms about t0 may weight it by 1/2 and 1/3. With `quadratic` too (then `linear` is
  /// required), R splits into R0 + s^2 R2 on those segments (the nonlinearity vanishes quadratically at t0): out[p]
  /// bounds |C Hc| + |C| R0 and quadratic[p] |C| R2, so |C H_il(t0 + s dt)| <= out[p] + s linear[p] + s^2
  /// quadratic[p] (weights 1/3 and 1/6 in the mean-value and Taylor forms). With `centre` and `rest`: centre[p] = C Hc
  /// computed in floating point and rest[p] >= |C| R (R0 with `quadratic`) plus the rounding of every product with C,
  /// so that |C H_il(t0 + s dt) - centre[p]| <= rest[p] + s linear[p] + s^2 quadratic[p] (the expansion's third-order
  /// rest, PreconditionedInverseEnclosure::tightenByResidual). @return false if the model does not provide them.
  virtual bool preconditionedHessianMagnitude(const IVec& /*pose*/, const DMat& /*c*/,
                                              std::array<DMat, MatrixHessian::kPairs>& /*out*/,
                                              std::array<DMat, MatrixHessian::kPairs>* /*linear*/ = nullptr,
                                              std::array<DMat, MatrixHessian::kPairs>* /*quadratic*/ = nullptr,
                                              std::array<DMat, MatrixHessian::kPairs>* /*rest*/ = nullptr,
                                              std::array<DMat, MatrixHessian::kPairs>* /*centre*/ = nullptr) const {
    return false;
  }
  /// Enclosures, over a pose box and every admissible geometry, of the derivatives of J^-1 with respect to the
  /// geometry parameters. @return false if the model does not provide them.
  virtual bool geometryDerivatives(const IVec& pose, GeometryDerivatives& out) const;
  /// The same robot with parameter p restricted to ranges[p] (a sub-interval of geometryParameterRange(p), possibly
  /// a single value); the parameter numbering is kept. Used to bisect the geometry and to evaluate one geometry.
  /// @throws InvalidArgument if the size is wrong, a range is empty or leaves the current range; or if the model
  ///         has no geometry parameters.
  virtual std::unique_ptr<RobotModel> restrictGeometry(const std::vector<Interval>& ranges) const;
  /// The same robot with every parameter p whose values[p] is not NaN fixed at values[p] (a point of its range) and
  /// no longer a parameter; the others keep their ranges and their order (parameter q of the result is the q-th
  /// parameter with values[p] NaN). Used to enclose f_k on a face of the geometry box.
  /// @throws InvalidArgument if the size is wrong, a value leaves its range; or if the model has no geometry
  ///         parameters.
  virtual std::unique_ptr<RobotModel> fixGeometryParameters(const GVec& values) const;

  // ---- helpers built on the above ------------------------------------------------------------------------------
  /// J = (J^-1)^-1 at a pose. @throws SingularMatrix if J^-1 is (numerically) singular there.
  DMat jacobian(const DVec& pose) const;
  /// Worst error of every component at one pose, sum_j |J_kj| e_j (double, not certified).
  DVec worstErrorAt(const DVec& pose) const;
};

}  // namespace model
}  // namespace pkm_accuracy
