// Reading planar 3-RPR robot files (the format of config/planar3rpr.yaml; conventions: docs/planar3rpr.md) with
// yaml-cpp. ROS-free.
//
// Robot file:
//   type: planar3rpr                       # optional; if present it must be planar3rpr
//   base_anchors:     [[x, y] x 3]         # m, base frame
//   platform_anchors: [[x, y] x 3]         # m, platform frame
//   sensor_error:     [e1, e2, e3] or e    # m
//   tool_point:       [x, y]               # m, platform frame (optional, default 0)
//   workspaces: {name: <workspace>}        # optional
// Workspace:
//   x: [min, max]  y: [min, max]  theta: [min, max]   # m, m, rad (a box)
// or a disc of positions:
//   theta: [min, max]
//   region: {type: disc, centre: [x, y], radius: r}   # m (x and y are then given by the disc, not by keys)
#pragma once

#include <map>
#include <string>

#include "pkm_accuracy/core/domain/PlanarWorkspace.hpp"
#include "pkm_accuracy/core/model/Planar3RPRGeometry.hpp"

namespace pkm_accuracy {
namespace io {

struct PlanarRobotFile {
  model::Planar3RPRGeometry geometry;                         ///< validated
  std::map<std::string, domain::PlanarWorkspace> workspaces;  ///< named workspaces of the file
};

/// @throws ParseError (file missing, YAML syntax, wrong structure: the message names the file and key) or
///         InvalidGeometry / InvalidArgument for values that parse but are invalid.
PlanarRobotFile loadPlanarRobotFile(const std::string& path);
/// The same from a YAML document held in a string (e.g. the node's parameters); `name` stands for the file name.
PlanarRobotFile parsePlanarRobotDocument(const std::string& yamlText, const std::string& name);

}  // namespace io
}  // namespace pkm_accuracy
