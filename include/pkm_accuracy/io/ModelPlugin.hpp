// Robot types from a user's shared library: the library defines
//   extern "C" void pkm_accuracy_register_models(pkm_accuracy::model::ModelRegistry& registry);
// and registers its types there (ModelRegistry::addKinematics; docs/models.md, examples/). pkm_verify --plugin and
// the node's ~plugins load such libraries before reading the robot.
#pragma once

#include <string>

#include "pkm_accuracy/core/model/ModelRegistry.hpp"

namespace pkm_accuracy {
namespace io {

/// The entry point a plugin library defines.
constexpr const char* kModelPluginEntryPoint = "pkm_accuracy_register_models";

/// Loads the library (dlopen, kept loaded for the life of the process) and calls its entry point with `registry`.
/// Loading the same path twice registers nothing the second time.
/// @throws InvalidArgument naming the library: cannot be loaded (dlerror), no entry point, or its registration
///         failed (e.g. a type name already taken).
void loadModelPlugin(const std::string& path, model::ModelRegistry& registry);

}  // namespace io
}  // namespace pkm_accuracy
