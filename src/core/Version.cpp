#include "pkm_accuracy/core/Version.hpp"

#ifndef PKM_ACCURACY_VERSION
#error "PKM_ACCURACY_VERSION must be defined by the build (CMakeLists.txt, from package.xml)"
#endif

namespace pkm_accuracy {

const char* version() noexcept { return PKM_ACCURACY_VERSION; }

}  // namespace pkm_accuracy
