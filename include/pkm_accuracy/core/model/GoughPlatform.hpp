// 6-UPS Gough-Stewart platform (conventions: docs/conventions.md).
//   pose X = (x, y, z, roll, pitch, yaw), R = Rz(yaw) Ry(pitch) Rx(roll), B_i = p + R b_i,
//   n_i = (B_i - A_i) / |B_i - A_i|, row i of J^-1 = [n_i^T, ((R (b_i - c)) x n_i)^T].
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "pkm_accuracy/core/model/GoughGeometry.hpp"
#include "pkm_accuracy/core/model/RobotModel.hpp"

namespace pkm_accuracy {
namespace model {

class GoughPlatform final : public RobotModel {
 public:
  /// @throws InvalidGeometry if geometry.validate() fails.
  explicit GoughPlatform(GoughGeometry geometry);

  int dof() const override { return 6; }
  std::string name() const override { return "gough6"; }
  std::string componentName(int k) const override;
  bool isAngular(int k) const override { return k >= 3; }
  const std::vector<double>& sensorError() const override { return geometry_.sensor_error; }
  bool hasGeometryUncertainty() const override { return uncertain_; }
  const GoughGeometry& geometry() const { return geometry_; }

  DMat inverseJacobian(const DVec& pose) const override;
  DVec legLengths(const DVec& pose) const override;
  IMat inverseJacobian(const IVec& pose) const override;
  void inverseJacobian(const DualPose& pose, MatrixWithGradient& out) const override;

  int geometryParameterCount() const override { return static_cast<int>(params_.size()); }
  std::string geometryParameterName(int p) const override;
  Interval geometryParameterRange(int p) const override;
  double geometryParameterCentre(int p) const override;
  /// [value - h, value + h] of the plain description (GoughGeometry: the coordinate and its half-width) rounded inward
  /// (the value itself when h is below its ulp), within the range.
  Interval geometryParameterAdmissible(int p) const override;
  int toolPointCoordinate(int p) const override;
  IMat inverseJacobianAtGeometryCentre(const IVec& pose) const override;
  void inverseJacobianAtGeometryCentre(const DualPose& pose, MatrixWithGradient& out) const override;
  /// Also fills the entries' affine forms in the pose (GeometryRowDerivative::affine) for the anchor coordinates.
  bool geometryDerivatives(const IVec& pose, GeometryDerivatives& out) const override;
  bool inverseJacobianHessianAtGeometryCentre(const IVec& pose, MatrixHessian& out, bool second = true) const override;
  bool preconditionedHessianMagnitude(const IVec& pose, const DMat& c, std::array<DMat, MatrixHessian::kPairs>& out,
                                      std::array<DMat, MatrixHessian::kPairs>* linear = nullptr,
                                      std::array<DMat, MatrixHessian::kPairs>* quadratic = nullptr,
                                      std::array<DMat, MatrixHessian::kPairs>* rest = nullptr,
                                      std::array<DMat, MatrixHessian::kPairs>* centre = nullptr) const override;
  std::unique_ptr<RobotModel> restrictGeometry(const std::vector<Interval>& ranges) const override;
  std::unique_ptr<RobotModel> fixGeometryParameters(const GVec& values) const override;

  /// Enclosure of the leg lengths over a pose box (every admissible geometry).
  IVec legLengths(const IVec& pose) const;

  /// Enclosures of J^-1 and of its partial derivatives with respect to (x, y, z, roll, pitch, yaw) over a pose box,
  /// by analytic differentiation (what inverseJacobian(DualPose) uses, followed by the chain rule).
  void poseDerivatives(const IVec& pose, MatrixWithGradient& out) const;
  /// The same as inverseJacobian(DualPose) by generic forward-mode dual numbers: a slower, independent
  /// implementation kept as a reference for the tests.
  void inverseJacobianByDualNumbers(const DualPose& pose, MatrixWithGradient& out) const;

 private:
  /// The affine forms of geometryDerivatives() (anchor entries; tool-point entries keep affine = false).
  void affineGeometryDerivatives(const IVec& pose, GeometryDerivatives& out) const;
  /// The same with N noise symbols: 6 for the pose (the anchors' ranges in the radii), or 12, the pose and the
  /// anchor coordinates of the entry's leg (GeometryRowDerivative::parameterSlopes).
  template <int N>
  void affineGeometryDerivativesWith(const IVec& pose, GeometryDerivatives& out) const;
  /// preconditionedHessianMagnitude() in the affine form type S (interval::AffineForm or, for the split remainder,
  /// interval::SegmentAffineForm).
  template <typename S>
  bool hessianMagnitude(const IVec& pose, const DMat& c, std::array<DMat, MatrixHessian::kPairs>& out,
                        std::array<DMat, MatrixHessian::kPairs>* linear,
                        std::array<DMat, MatrixHessian::kPairs>* quadratic,
                        std::array<DMat, MatrixHessian::kPairs>* rest = nullptr,
                        std::array<DMat, MatrixHessian::kPairs>* centre = nullptr) const;

  GoughGeometry geometry_;
  bool uncertain_;
  /// Geometry parameter p: which coordinate it is.
  struct Parameter {
    enum Kind { Base, Platform, Tool } kind;
    int leg;    ///< 0..5 (unused for the tool point)
    int coord;  ///< 0..2
  };
  using Anchors = std::array<std::array<Interval, 3>, 6>;
  using Tool = std::array<Interval, 3>;
  /// poseDerivatives / inverseJacobian(DualPose) for given anchors and tool point.
  void derivatives(const IVec& pose, const Anchors& a, const Anchors& b, const Tool& c, MatrixWithGradient& out) const;
  /// Second derivatives of J^-1 with respect to (x, y, z, roll, pitch, yaw) over a pose box, analytic, for given
  /// anchors and tool point. @return false if some value is not finite (a degenerate leg).
  bool hessian(const IVec& pose, const Anchors& a, const Anchors& b, const Tool& c, MatrixHessian& out,
               bool second) const;
  void chainRule(const DualPose& pose, const Anchors& a, const Anchors& b, const Tool& c,
                 MatrixWithGradient& out) const;
  Interval& slot(const Parameter& p, bool centre);
  /// Sets the plain description (geometry_, used by the evaluations in double) of parameter p: value and half-width.
  void describe(const Parameter& p, double value, double half);
  const Interval& slot(const Parameter& p, bool centre) const;

  // Anchors and tool point as intervals (degenerate when known exactly), used by the enclosures; and the same at
  // the centre of every uncertain coordinate's range (degenerate).
  std::array<std::array<Interval, 3>, 6> a_, b_, aMid_, bMid_;
  std::array<Interval, 3> c_, cMid_;
  std::vector<Parameter> params_;
};

}  // namespace model
}  // namespace pkm_accuracy
