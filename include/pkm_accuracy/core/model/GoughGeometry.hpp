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
