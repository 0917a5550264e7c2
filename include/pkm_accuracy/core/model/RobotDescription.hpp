// What a robot model declares about itself, and the values one robot of that type has: pose / error components,
// joints (sensors), geometry parameters with nominal values and optional uncertainty, sensor error bounds.
// KinematicModel (KinematicModel.hpp) is built from a description and the model's templated kinematics.
#pragma once

#include <string>
#include <vector>

namespace pkm_accuracy {
namespace model {

/// One pose coordinate and its error component: names and unit, e.g. {"x", "m", false} (error "dx"),
/// {"roll", "rad", true, "drx"} (a Gough-convention rotation error: a component of the small rotation vector).
struct PoseComponent {
  std::string name;
  std::string unit;
  bool angular = false;
  std::string error_name = "";  ///< the error component's name; empty: "d" + name
  std::string errorName() const { return error_name.empty() ? "d" + name : error_name; }
};

/// The pose of a rigid platform, (x, y, z) [m] and (roll, pitch, yaw) [rad] with R = Rz(yaw) Ry(pitch) Rx(roll), and
/// the Gough error convention: errors dx, dy, dz of the tool point and drx, dry, drz of the small rotation vector, in
/// the base frame (types gough and rus6; the node's requests and responses are in it).
std::vector<PoseComponent> rigidBodyPose();
/// Whether a description's pose is rigidBodyPose().
bool hasRigidBodyPose(const std::vector<PoseComponent>& pose);

/// One actuated joint, whose sensor error is bounded: e.g. {"leg_0", "m"} or {"crank_2", "rad"}.
struct Joint {
  std::string name;
  std::string unit;
};

/// One geometry value of the model, e.g. "base_anchors[2].y" [m] or "crank_axis_angle[1]" [rad]. The robot's true
/// value lies in [nominal + lo, nominal + hi] (lo <= 0 <= hi; both 0: known exactly). Uncertain values become the
/// model's geometry parameters (RobotModel::geometryParameterCount), in the order of the description.
struct GeometryValue {
  std::string name;
  std::string unit = "m";
  double nominal = 0.0;
  double lo = 0.0, hi = 0.0;
  /// 0, 1, 2 if this value is the x, y, z coordinate of the tool point c (platform frame) of a model whose pose is
  /// rigidBodyPose() (RobotModel::toolPointCoordinate); -1 otherwise.
  int tool_point_coordinate = -1;
  /// Whether a robot file may omit this value (it then keeps `nominal`, the type's default, e.g. a tool point at 0).
  bool has_default = false;
  bool uncertain() const { return lo != 0.0 || hi != 0.0; }
};

struct RobotDescription {
  std::string type;  ///< registry name, e.g. "delta3"
  std::vector<PoseComponent> pose;
  std::vector<Joint> joints;  ///< as many as pose components (J^-1 is square)
  std::vector<GeometryValue> geometry;
  std::vector<double> sensor_error;  ///< e_j > 0 per joint, in the joint's unit

  /// Index of the geometry value of that name, or -1.
  int geometryIndex(const std::string& name) const;
  /// Sets every geometry value's uncertainty to [-h, h] (h >= 0) for those whose name starts with `prefix` (all with
  /// an empty prefix). @return how many were set.
  int setUncertainty(const std::string& prefix, double h);

  /// Checks sizes (pose = joints = sensor_error, 1..kMaxDof), unique non-empty names, finite values, lo <= 0 <= hi,
  /// sensor_error > 0, tool-point flags only with rigidBodyPose(), at most kMaxGeometryParameters uncertain values.
  /// @throws InvalidGeometry naming the field, e.g. "sensor_error[2]: expected a positive number, got 0".
  void validate() const;
};

}  // namespace model
}  // namespace pkm_accuracy
