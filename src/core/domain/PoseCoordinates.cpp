#include "pkm_accuracy/core/domain/PoseCoordinates.hpp"

#include <utility>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/Types.hpp"

namespace pkm_accuracy {
namespace domain {

PoseCoordinates::PoseCoordinates() : PoseCoordinates("gough", model::rigidBodyPose()) {}

PoseCoordinates::PoseCoordinates(std::string type, std::vector<model::PoseComponent> components)
    : type_(std::move(type)), components_(std::move(components)) {
  if (components_.empty() || static_cast<int>(components_.size()) > kMaxDof) {
    throw InvalidArgument("pose coordinates of " + type_ + ": expected 1 to " + std::to_string(kMaxDof) + ", got " +
                          std::to_string(components_.size()));
  }
  for (int i = 0; i < size(); ++i) {
    if (components_[static_cast<std::size_t>(i)].name.empty() || indexOf(name(i)) != i) {
      throw InvalidArgument("pose coordinates of " + type_ + ": coordinate " + std::to_string(i) +
                            ": expected a unique non-empty name, got '" + name(i) + "'");
    }
  }
  rigidBody_ = model::hasRigidBodyPose(components_);
}

PoseCoordinates PoseCoordinates::of(const model::RobotDescription& description) {
  return PoseCoordinates(description.type, description.pose);
}

std::string PoseCoordinates::name(int i) const {
  return i >= 0 && i < size() ? components_[static_cast<std::size_t>(i)].name : "?";
}

std::string PoseCoordinates::names() const {
  std::string s;
  for (int i = 0; i < size(); ++i) s += (i ? ", " : "") + name(i);
  return s;
}

int PoseCoordinates::indexOf(const std::string& n) const {
  for (int i = 0; i < size(); ++i)
    if (components_[static_cast<std::size_t>(i)].name == n) return i;
  return -1;
}

std::array<int, 3> PoseCoordinates::positionIndices() const { return {indexOf("x"), indexOf("y"), indexOf("z")}; }

std::string PoseCoordinates::describe() const { return type_ + " has the pose coordinates (" + names() + ")"; }

}  // namespace domain
}  // namespace pkm_accuracy
