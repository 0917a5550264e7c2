#include "pkm_accuracy/core/Version.hpp"

// CMakeLists.txt defines PKM_ACCURACY_VERSION from package.xml (CliTest compares the two); only a translation of
// this file outside that build (e.g. the core_is_ros_free check's preprocessing) goes without it.
#ifndef PKM_ACCURACY_VERSION
#define PKM_ACCURACY_VERSION "unknown"
#endif

namespace pkm_accuracy {

const char* version() noexcept { return PKM_ACCURACY_VERSION; }

}  // namespace pkm_accuracy
