#include "pkm_accuracy/core/model/ModelRegistry.hpp"

#include <algorithm>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/core/model/robots/Delta3Kinematics.hpp"
#include "pkm_accuracy/core/model/robots/GoughKinematics.hpp"
#include "pkm_accuracy/core/model/robots/Planar3RPRKinematics.hpp"

namespace pkm_accuracy {
namespace model {

ModelRegistry& ModelRegistry::global() {
  static ModelRegistry* registry = [] {
    auto* r = new ModelRegistry();
    registerBuiltinModels(*r);
    return r;
  }();
  return *registry;
}

void ModelRegistry::add(ModelType type) {
  if (type.name.empty()) throw InvalidArgument("model type: expected a non-empty name");
  if (type.description.type != type.name) {
    throw InvalidArgument("model type '" + type.name + "': its description names the type '" + type.description.type +
                          "'");
  }
  if (!type.make) throw InvalidArgument("model type '" + type.name + "': no factory");
  std::lock_guard<std::mutex> lock(mutex_);
  if (types_.count(type.name)) throw InvalidArgument("model type '" + type.name + "': already registered");
  const std::string name = type.name;
  types_.emplace(name, std::move(type));
}

const ModelType* ModelRegistry::find(const std::string& name) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = types_.find(name);
  return it == types_.end() ? nullptr : &it->second;
}

std::vector<std::string> ModelRegistry::names() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::string> out;
  for (const auto& t : types_) out.push_back(t.first);
  return out;
}

void registerBuiltinModels(ModelRegistry& registry) {
  {
    // The Gough platform keeps its hand-written enclosures (affine second-order forms; bench/RESULTS.md compares it
    // with KinematicModel<GoughKinematics>, and the tests check the two against each other).
    ModelType t;
    t.name = "gough";
    t.summary = "6-UPS Gough-Stewart platform, 6 prismatic legs, pose x y z roll pitch yaw";
    t.description = GoughKinematics::description();
    t.make = [](const RobotDescription& d) -> std::unique_ptr<RobotModel> {
      return std::make_unique<GoughPlatform>(goughGeometry(d));
    };
    registry.add(std::move(t));
  }
  registry.addKinematics<Planar3RPRKinematics>("planar 3-RPR robot, 3 prismatic legs, pose x y theta",
                                               Planar3RPRKinematics::description());
  registry.addKinematics<Delta3Kinematics>("Delta robot, 3 rotary actuators, translations x y z",
                                           Delta3Kinematics::description());
}

}  // namespace model
}  // namespace pkm_accuracy
