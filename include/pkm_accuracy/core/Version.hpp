// The package's version (package.xml's <version>, set by CMakeLists.txt at build time).
#pragma once

namespace pkm_accuracy {

/// "MAJOR.MINOR.PATCH", as in package.xml.
const char* version() noexcept;

}  // namespace pkm_accuracy
