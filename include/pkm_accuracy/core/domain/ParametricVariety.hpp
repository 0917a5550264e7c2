// An m-dimensional motion variety (m = 1 .. 6, typically 2 or 3): the pose as explicit polynomials of parameters
// (u, v, w, ...) in [0, 1]^m. Every pose coordinate (of a robot type's PoseCoordinates: x, y, z, roll, pitch, yaw for
// gough, x, y, z for delta3, ...) is a list of monomials coefficient * u^a v^b w^c ...
// The verifier explores [0, 1]^m directly (the box variables are the parameters); the pose map is smooth, so
// poseView gives the usual mean-value data (pose and gradient over the box by forward-mode Dual over intervals,
// the pose at the box centre, deviations from the centre).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "pkm_accuracy/core/Types.hpp"
#include "pkm_accuracy/core/domain/Domain.hpp"
#include "pkm_accuracy/core/domain/PoseCoordinates.hpp"
#include "pkm_accuracy/core/domain/PositionRegion.hpp"

namespace pkm_accuracy {
namespace domain {

class ParametricVariety final : public Domain {
 public:
  struct Monomial {
    double coefficient = 0.0;
    std::array<int, kMaxDof> exponents{};  ///< exponent of each parameter (entries >= m must be 0)
  };
  /// Highest accepted exponent of one parameter.
  static constexpr int kMaxExponent = 31;

  /// A variety of the rigid-body pose (x, y, z in m; roll, pitch, yaw in rad) of type gough.
  /// @throws InvalidArgument as below.
  ParametricVariety(int m, std::array<std::vector<Monomial>, kMaxDof> coordinates);
  /// @param m number of parameters (1 .. 6).
  /// @param coordinates per pose coordinate i < n of `pose`, in its order: its monomials (an empty list is the
  ///        constant 0); the entries i >= n stay empty.
  /// @throws InvalidArgument naming the coordinate and monomial for a bad m, non-finite coefficients or exponents
  ///         outside 0 .. kMaxExponent (or non-zero for a parameter >= m), or monomials for more coordinates than the
  ///         n of `pose` (the message names the expected number).
  ParametricVariety(int m, std::array<std::vector<Monomial>, kMaxDof> coordinates, PoseCoordinates pose);

  int variables() const override { return m_; }
  int poseDimension() const override { return pose_.size(); }
  const PoseCoordinates& poseCoordinates() const { return pose_; }
  std::string variableName(int i) const override;
  const IVec& initialBox() const override { return initial_; }
  void poseView(const IVec& box, bool gradient, enclosure::BoxInput& out) const override;
  Containment classify(const IVec& box) const override;
  IVec poseAt(const DVec& t) const override;

  /// The pose and its Jacobian d pose / d parameters (n x m) at a point, in double (not certified; for tests).
  void pointAt(const DVec& t, DVec& pose, DMat& jacobian) const;

  /// @throws InvalidArgument if the pose coordinates lack x, y or z (the message names the type and its coordinates).
  void setRegion(PositionRegion region);
  const std::optional<PositionRegion>& region() const { return region_; }
  const std::array<std::vector<Monomial>, kMaxDof>& coordinates() const { return coordinates_; }
  std::string description() const;

 private:
  template <typename D>
  void evaluate(const std::array<D, kMaxDof>& vars, std::array<D, kMaxDof>& out) const;
  IVec values(const IVec& box) const;
  void checkMonomials();

  int m_;
  std::array<std::vector<Monomial>, kMaxDof> coordinates_;
  PoseCoordinates pose_;
  std::array<int, 3> position_{};  ///< indices of x, y, z among the pose coordinates (with a region)
  int maxExponent_ = 0;
  IVec initial_;
  std::optional<PositionRegion> region_;
};

}  // namespace domain
}  // namespace pkm_accuracy
