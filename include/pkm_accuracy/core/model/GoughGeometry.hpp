// Plain description of a 6-UPS Gough-Stewart platform (and of its bounded geometric uncertainty).
// Conventions (docs/conventions.md): SI units; leg i joins base anchor A_i (base frame) to platform anchor b_i
// (platform frame); B_i = p + R b_i with R = Rz(yaw) Ry(pitch) Rx(roll); the error reference point is the tool
// point c (platform frame).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace pkm_accuracy {
namespace model {

/// How one uncertain coordinate is given: a half-width h >= 0 (it lies in value +- h; lo = -h, hi = h, symmetric) or
/// offsets lo <= hi from its given value (it lies in [value + lo, value + hi]: a general box, e.g. a one-sided
/// tolerance [-0.0002, 0]).
struct CoordinateBound {
  double lo = 0.0, hi = 0.0;
  bool symmetric = true;
  static CoordinateBound halfwidth(double h) { return {-h, h, true}; }
  static CoordinateBound offsets(double lo, double hi) { return {lo, hi, false}; }
};

/// Applies a bound to one coordinate of a point (an anchor or the tool point) and its half-width: a symmetric bound
/// sets halfwidth = h and keeps the value; offsets move the value to the centre of [value + lo, value + hi] and set
/// the half-width to half its width, rounded so that value +- halfwidth contains that range (the centre is the
/// nominal coordinate the models and reports then use).
/// @throws InvalidGeometry (the message names no field; callers add it) if h < 0, lo > hi or a value is not finite.
void applyCoordinateBound(const CoordinateBound& bound, double& value, double& halfwidth);

struct GoughGeometry {
  std::vector<Eigen::Vector3d> base_anchors;             ///< A_i in the base frame (m); one per leg
  std::vector<Eigen::Vector3d> platform_anchors;         ///< b_i in the platform frame (m); one per leg
  std::vector<double> sensor_error;                      ///< e_i > 0: bound on |leg-length sensor error| of leg i (m)
  Eigen::Vector3d tool_point = Eigen::Vector3d::Zero();  ///< c in the platform frame (m)

  /// Bounded uncertainty: A_i is only known to lie in base_anchors[i] +- base_anchor_halfwidth[i] (per coordinate,
  /// m). Empty vectors mean "known exactly". Same for the platform anchors and the tool point.
  std::vector<Eigen::Vector3d> base_anchor_halfwidth;
  std::vector<Eigen::Vector3d> platform_anchor_halfwidth;
  Eigen::Vector3d tool_point_halfwidth = Eigen::Vector3d::Zero();

  std::size_t legCount() const { return base_anchors.size(); }
  bool hasUncertainty() const;

  /// Sets every anchor coordinate's half-width to h (m); h = 0 removes the uncertainty.
  void setUniformAnchorUncertainty(double h);

  /// Checks sizes (6 legs for the Gough platform), finiteness, sensor_error > 0, half-widths >= 0, and that no two
  /// base anchors and no two platform anchors coincide.
  /// @throws InvalidGeometry naming the field, e.g. "platform_anchors[2]: coincides with platform_anchors[0]".
  void validate() const;

  /// One-line human summary ("6 legs, base radius 0.158 m, ...").
  std::string summary() const;
};

}  // namespace model
}  // namespace pkm_accuracy
