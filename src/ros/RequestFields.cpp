#include "RequestFields.hpp"

#include <algorithm>
#include <sstream>
#include <vector>

#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"

namespace pkm_accuracy {
namespace ros_layer {
namespace fields {

namespace {
constexpr std::uint32_t kMaxThreads = 1024;
}  // namespace

std::string num(double x) {
  std::ostringstream os;
  os.precision(10);
  os << x;
  return os.str();
}

std::string idx(const char* field, std::size_t i) { return std::string(field) + "[" + std::to_string(i) + "]"; }

bool option(double x, double dflt, const char* field, const char* expected, double& out, std::string& error,
            double upper) {
  if (!std::isfinite(x) || x < 0.0 || !(x < upper)) {
    error = std::string(field) + ": expected " + expected + ", got " + num(x);
    return false;
  }
  out = x == 0.0 ? dflt : x;
  return true;
}

bool threads(std::uint32_t requested, std::string& error) {
  if (requested <= kMaxThreads) return true;
  error = "threads: expected 0 (all hardware threads) to " + std::to_string(kMaxThreads) + ", got " +
          std::to_string(requested);
  return false;
}

bool method(const std::string& requested, const std::string& dflt, std::string& out, std::string& error) {
  out = requested.empty() ? dflt : requested;
  if (out.empty()) return true;
  const std::vector<std::string> methods = enclosure::enclosureNames();
  if (std::find(methods.begin(), methods.end(), out) != methods.end()) return true;
  std::string list;
  for (const auto& m : methods) list += (list.empty() ? "\"" : ", \"") + m + "\"";
  error = std::string(requested.empty() ? "method (from ~default_method)" : "method") + ": expected one of " + list +
          " or \"\" (default), got \"" + out + "\"";
  return false;
}

bool geometrySplitting(const std::string& requested, std::string& out, std::string& error) {
  if (requested.empty() || requested == "auto" || requested == "never" || requested == "always") {
    out = requested.empty() ? "auto" : requested;
    return true;
  }
  error = "geometry_splitting: expected \"auto\", \"never\", \"always\" or \"\" (auto), got \"" + requested + "\"";
  return false;
}

bool geometryForm(const std::string& requested, std::string& out, std::string& error) {
  if (requested.empty() || requested == "combined" || requested == "decomposed") {
    out = requested.empty() ? "decomposed" : requested;
    return true;
  }
  error = "geometry_form: expected \"decomposed\", \"combined\" or \"\" (decomposed), got \"" + requested + "\"";
  return false;
}

bool stallLevels(std::int32_t requested, int& out, std::string& error) {
  if (requested >= 0 && requested <= kMaxStallLevels) {
    out = static_cast<int>(requested);
    return true;
  }
  error = "stall_levels: expected 0 (half the number of box variables, at least 2) to " +
          std::to_string(kMaxStallLevels) + ", got " + std::to_string(requested);
  return false;
}

}  // namespace fields
}  // namespace ros_layer
}  // namespace pkm_accuracy
