// Reading robot files (the format of config/ref6.yaml) and workspace files with yaml-cpp. ROS-free; used by the
// command-line tool, the tests and the benchmarks. The ROS node reads the same keys from the parameter server.
//
// Robot file:
//   base_anchors:     [[x, y, z] x 6]      # m, base frame
//   platform_anchors: [[x, y, z] x 6]      # m, platform frame
//   sensor_error:     [e1..e6] or e        # m
//   tool_point:       [x, y, z]            # m, platform frame (optional, default 0)
//   anchor_uncertainty: h                  # m, half-width of every anchor coordinate (optional, default 0)
//   base_anchor_uncertainty: h or [[bx, by, bz] x 6]      # m, optional: per-coordinate bounds of the A_i,
//   platform_anchor_uncertainty: h or [[bx, by, bz] x 6]  # resp. b_i (each replaces anchor_uncertainty for its
//                                                         # anchors); each bound a half-width h or offsets
//                                                         # [lo, hi] (the coordinate moves to the range's centre:
//                                                         # model::applyCoordinateBound)
//   tool_point_uncertainty: [bx, by, bz]   # m, optional (default 0): bounds of the tool point, as above
//   workspaces: {name: <workspace>}        # optional
// Workspace (inline under `workspaces:` or as a file of its own with these keys at top level):
//   x: [min, max]  y: [min, max]  z: [min, max]          # m (the box region, or the bounds of another region)
//   roll: [min, max]  pitch: [min, max]  yaw: [min, max]  # rad
//   region:                                               # optional; default the x/y/z box
//     type: box | cylinder | sphere | polyhedron
//     centre: [x, y(, z)]  radius: r  z: [min, max]       # cylinder (z range) / sphere (3-D centre)
//     normals: [[nx, ny, nz], ...]  offsets: [d, ...]     # polyhedron: n . p <= d (x/y/z give its bounds)
//   frame:                                                # optional: the workspace is given in a frame F fixed to
//     translation: [x, y, z]  rpy: [roll, pitch, yaw]     # the base frame at this pose (m, rad; each optional, 0);
//                                                         # verified exactly in the base frame (TransformedDomain)
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "pkm_accuracy/core/domain/TransformedDomain.hpp"
#include "pkm_accuracy/core/domain/Workspace.hpp"
#include "pkm_accuracy/core/model/GoughGeometry.hpp"

namespace pkm_accuracy {
namespace io {

struct RobotFile {
  model::GoughGeometry geometry;                        ///< validated
  std::map<std::string, domain::Workspace> workspaces;  ///< named workspaces of the file (each in its own frame)
  /// The frames of the named workspaces that have a `frame` key (the pose of the workspace's frame in the base frame).
  std::map<std::string, domain::RigidTransform> workspace_frames;
  std::vector<double> anchor_uncertainty_cases;  ///< optional list (m)
  /// Top-level keys that neither the robot file nor the node's parameters (docs/ros_api.md) use, e.g. a misspelt
  /// "tool_point_uncertanty": not errors (a file may carry other tools' keys), but worth a warning.
  std::vector<std::string> unknown_keys;
};

/// @throws ParseError (file missing, YAML syntax, wrong structure: the message names the file and key) or
///         InvalidGeometry / InvalidArgument for values that parse but are invalid.
RobotFile loadRobotFile(const std::string& path);

/// A workspace from a YAML node with the keys above; `where` prefixes error messages (e.g. "file.yaml:
/// workspaces.paper").
/// @param frame if not null: the file's `frame` (the pose of the workspace's frame in the base frame), or nullopt.
domain::Workspace parseWorkspaceFile(const std::string& path, std::optional<domain::RigidTransform>* frame = nullptr);

}  // namespace io
}  // namespace pkm_accuracy
