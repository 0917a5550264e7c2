#include "pkm_accuracy/io/ModelPlugin.hpp"

#include <dlfcn.h>

#include <mutex>
#include <set>

#include "pkm_accuracy/core/Exceptions.hpp"

namespace pkm_accuracy {
namespace io {

void loadModelPlugin(const std::string& path, model::ModelRegistry& registry) {
  static std::mutex mutex;
  static std::set<std::pair<std::string, const model::ModelRegistry*>> loaded;
  std::lock_guard<std::mutex> lock(mutex);
  if (loaded.count({path, &registry})) return;
  void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = ::dlerror();
    throw InvalidArgument(path + ": cannot load the plugin library: " + (why ? why : "unknown error"));
  }
  using Entry = void (*)(model::ModelRegistry&);
  auto entry = reinterpret_cast<Entry>(::dlsym(handle, kModelPluginEntryPoint));
  if (!entry) {
    throw InvalidArgument(path + ": not a model plugin: no function " + std::string(kModelPluginEntryPoint) +
                          " (declare it extern \"C\")");
  }
  try {
    entry(registry);
  } catch (const std::exception& e) {
    throw InvalidArgument(path + ": " + kModelPluginEntryPoint + " failed: " + e.what());
  }
  loaded.insert({path, &registry});
}

}  // namespace io
}  // namespace pkm_accuracy
