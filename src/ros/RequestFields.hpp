// Checks of request fields shared by the /verify_workspace and /verify_trajectory translations. Each returns false
// with `error` naming the field, what was expected and what was given. Internal to the ROS layer.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

namespace pkm_accuracy {
namespace ros_layer {
namespace fields {

/// A number for messages (10 significant digits).
std::string num(double x);
/// "field[i]".
std::string idx(const char* field, std::size_t i);
/// An option where 0 means "default": finite, >= 0 and < upper; `out` gets the value or the default.
bool option(double x, double dflt, const char* field, const char* expected, double& out, std::string& error,
            double upper = HUGE_VAL);
/// `threads`: 0 (all hardware threads) to the node's limit.
bool threads(std::uint32_t requested, std::string& error);
/// `method`: "" gives `dflt` (the node's ~default_method, itself possibly "" = the verifier's); any other value must
/// be a registered enclosure method name.
bool method(const std::string& requested, const std::string& dflt, std::string& out, std::string& error);

}  // namespace fields
}  // namespace ros_layer
}  // namespace pkm_accuracy
