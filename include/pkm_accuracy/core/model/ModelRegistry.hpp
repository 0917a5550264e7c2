// The robot types the tools know by name (`type:` in a robot file, `~robot_type` of the node): for each, the
// description of its components, joints and geometry values, and a factory that builds a model from a filled-in
// description. The built-in types are registered at first use; a user's shared library adds its own through
// pkm_accuracy_register_models (io/ModelPlugin.hpp, docs/models.md).
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "pkm_accuracy/core/model/KinematicModel.hpp"
#include "pkm_accuracy/core/model/RobotDescription.hpp"
#include "pkm_accuracy/core/model/RobotModel.hpp"

namespace pkm_accuracy {
namespace model {

struct ModelType {
  std::string name;     ///< e.g. "delta3"
  std::string summary;  ///< one line for listings, e.g. "Delta robot, 3 rotary actuators, translations x y z"
  /// Components, joints and geometry value names and units; nominal values are those of the reference robot where
  /// the type has one (else 0), sensor errors empty.
  RobotDescription description;
  /// Builds the model from a description of this type (the same values, filled in).
  /// @throws InvalidGeometry if the values do not make a valid robot.
  std::function<std::unique_ptr<RobotModel>(const RobotDescription&)> make;
};

class ModelRegistry {
 public:
  /// The process-wide registry, holding the built-in types.
  static ModelRegistry& global();

  /// @throws InvalidArgument if the name is empty or already taken, or the description's type differs from it.
  void add(ModelType type);
  /// Registers templated kinematics K (KinematicModel<K>) under description.type.
  template <typename K>
  void addKinematics(const std::string& summary, RobotDescription description, K kinematics = K()) {
    ModelType t;
    t.name = description.type;
    t.summary = summary;
    t.description = std::move(description);
    t.make = [kinematics](const RobotDescription& d) -> std::unique_ptr<RobotModel> {
      return std::make_unique<KinematicModel<K>>(kinematics, d);
    };
    add(std::move(t));
  }
  /// The type of that name, or nullptr.
  const ModelType* find(const std::string& name) const;
  /// Every registered name, sorted.
  std::vector<std::string> names() const;

 private:
  mutable std::mutex mutex_;
  std::map<std::string, ModelType> types_;
};

/// Registers the built-in types (gough, planar3rpr, delta3, rus6, prs3) into a registry (ModelRegistry::global()
/// does it once).
void registerBuiltinModels(ModelRegistry& registry);

}  // namespace model
}  // namespace pkm_accuracy
