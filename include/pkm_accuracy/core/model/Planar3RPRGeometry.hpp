// Plain description of a planar 3-RPR parallel robot (conventions: docs/planar3rpr.md).
// SI units; everything lies in the plane z = 0 of the base frame. Leg i joins the base anchor A_i (base frame) to
// the platform anchor b_i (platform frame); B_i = p + R(theta) b_i; the error reference point is the tool point c
// (platform frame).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace pkm_accuracy {
namespace model {

struct Planar3RPRGeometry {
  std::vector<Eigen::Vector2d> base_anchors;             ///< A_i = (x, y) in the base frame (m); one per leg
  std::vector<Eigen::Vector2d> platform_anchors;         ///< b_i = (x, y) in the platform frame (m); one per leg
  std::vector<double> sensor_error;                      ///< e_i > 0: bound on |leg-length sensor error| of leg i (m)
  Eigen::Vector2d tool_point = Eigen::Vector2d::Zero();  ///< c = (x, y) in the platform frame (m)

  std::size_t legCount() const { return base_anchors.size(); }

  /// Checks sizes (3 legs), finiteness, sensor_error > 0, and that no two base anchors and no two platform anchors
  /// coincide.
  /// @throws InvalidGeometry naming the field, e.g. "platform_anchors[2]: coincides with platform_anchors[0]".
  void validate() const;

  /// One-line human summary ("planar 3-RPR, base radius 0.5 m, ...").
  std::string summary() const;
};

}  // namespace model
}  // namespace pkm_accuracy
