// The pose coordinates in which a trajectory or motion variety gives its poses: the robot type's name and its pose
// components, in the order of its description (model/RobotDescription.hpp), e.g. delta3 (x, y, z), prs3 (z, tilt_x,
// tilt_y), planar3rpr (x, y, theta), gough and rus6 the rigid-body pose (x, y, z, roll, pitch, yaw). The domain's
// poses have size() coordinates, in that order: what the model of that type takes.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "pkm_accuracy/core/model/RobotDescription.hpp"

namespace pkm_accuracy {
namespace domain {

class PoseCoordinates {
 public:
  /// The rigid-body pose (model::rigidBodyPose()) of type "gough".
  PoseCoordinates();
  /// @throws InvalidArgument if there are no components or more than kMaxDof, or a name is empty or repeated.
  PoseCoordinates(std::string type, std::vector<model::PoseComponent> components);
  /// The type and pose components of a description.
  static PoseCoordinates of(const model::RobotDescription& description);

  int size() const { return static_cast<int>(components_.size()); }
  const std::string& type() const { return type_; }
  const std::vector<model::PoseComponent>& components() const { return components_; }
  /// Name of coordinate i, e.g. "x" ("?" out of range).
  std::string name(int i) const;
  /// The names separated by commas, e.g. "x, y, z".
  std::string names() const;
  /// Index of the coordinate of that name, or -1.
  int indexOf(const std::string& name) const;
  /// Whether the components are the rigid-body pose (model::hasRigidBodyPose: slerp and frames apply).
  bool rigidBody() const { return rigidBody_; }
  /// Indices of the coordinates x, y, z (a position region needs all three), each -1 if missing.
  std::array<int, 3> positionIndices() const;
  /// E.g. "delta3 has the pose coordinates (x, y, z)": for messages.
  std::string describe() const;

 private:
  std::string type_;
  std::vector<model::PoseComponent> components_;
  bool rigidBody_ = false;
};

}  // namespace domain
}  // namespace pkm_accuracy
