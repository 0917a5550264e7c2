// Loading a Gough-Stewart platform (model::GoughGeometry) from ROS parameters or from a URDF, in the style of
// ros_control's joint_limits_interface (getJointLimits): plain functions that fill a core struct and report what is
// wrong. They never throw and never call ROS_FATAL; the caller decides what a failure means.
#pragma once

#include <map>
#include <string>

#include <ros/node_handle.h>
#include <urdf/model.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include "pkm_accuracy/core/model/GoughGeometry.hpp"
#include "pkm_accuracy/io/ModelFile.hpp"
#include "pkm_accuracy/ros/WorkspaceQuery.hpp"

namespace pkm_accuracy {
namespace ros_layer {

/// Numbers in parameters. A number may arrive as a string: `sensor_error:=2e-5` on a roslaunch line (through
/// <rosparam subst_value="true">) and `2e-5` in a YAML 1.1 file (no dot: not a float in YAML 1.1) both reach the
/// parameter server as the string "2e-5". Such a string is read as the number when its whole text parses as a
/// finite number (strtod syntax, no surrounding spaces or units); any other string is refused by the readers below,
/// naming the parameter.
bool numberFromString(const std::string& text, double& out);
/// An int, a double, or a numeric string as above.
bool parameterNumber(const XmlRpc::XmlRpcValue& v, double& out);
/// An int, or a string whose whole text is a finite number with an integral value that fits an int.
bool parameterInteger(const XmlRpc::XmlRpcValue& v, int& out);
/// Optional numeric parameter `key` of `nh`: unchanged `out` if unset; false (error naming the resolved parameter,
/// the expected and the given value) if set to anything but a number or a numeric string.
bool readOptionalNumber(const ros::NodeHandle& nh, const std::string& key, double& out, std::string& error);
/// Optional integer parameter, likewise.
bool readOptionalInteger(const ros::NodeHandle& nh, const std::string& key, int& out, std::string& error);

/// Default name of the frame the base anchors are expressed in.
constexpr const char* kDefaultBaseFrame = "base_link";
/// Default name of the moving platform's frame (the frame the platform anchors and the tool point are expressed in).
constexpr const char* kDefaultPlatformFrame = "platform";

/// Reads a Gough platform from the parameters in the namespace of `nh` (pass ros::NodeHandle("~") for a node's
/// private parameters). Expected parameters, exactly the format of config/ref6.yaml, so that
/// `<rosparam file="$(find pkm_accuracy)/config/ref6.yaml"/>` inside a <node> element loads as is:
///
/// @code{.yaml}
/// base_anchors:               # required: 6 points A_i [x, y, z] in base_frame (m); leg i = i-th entry
///   - [-0.097,   0.091,  0.0]
///   - [ 0.097,   0.091,  0.0]
///   - [ 0.1276,  0.039,  0.0]
///   - [ 0.031,  -0.129,  0.0]
///   - [-0.031,  -0.129,  0.0]
///   - [-0.1276,  0.039,  0.0]
/// platform_anchors:           # required: 6 points b_i [x, y, z] in the platform frame (m)
///   - [-0.030,    0.073,   0.0]
///   - [ 0.030,    0.073,   0.0]
///   - [ 0.07822, -0.01052, 0.0]
///   - [ 0.04822, -0.06248, 0.0]
///   - [-0.04822, -0.06248, 0.0]
///   - [-0.07822, -0.01052, 0.0]
/// sensor_error: [1.0e-5, 1.0e-5, 1.0e-5, 1.0e-5, 1.0e-5, 1.0e-5]  # required: per-leg bound (m) > 0,
///                             # or a single number used for all 6 legs (sensor_error: 1.0e-5)
/// tool_point: [0.0, 0.0, 0.0] # optional (default 0): error reference point c in the platform frame (m)
/// anchor_uncertainty: 0.0005  # optional (default 0): every coordinate of every A_i and b_i is only known to
///                             # +- this half-width (m)
/// base_anchor_uncertainty:    # optional: per-coordinate bounds of the A_i (m), 6 triples [bx, by, bz] or one
///   - [0.001, 0.001, 0.0]     # number for every coordinate; replaces anchor_uncertainty for the base anchors;
///   - [[-0.0002, 0.0], 0.001, 0.0]  # each bound a half-width or offsets [lo, hi] (the coordinate lies in
///   - ...                     # [a + lo, a + hi] and moves to its centre: model::applyCoordinateBound)
///                             # (platform_anchor_uncertainty: the same for the b_i)
/// tool_point_uncertainty: [0.0, 0.0, 0.0005]  # optional (default 0): bounds of the tool point (m), as above
/// base_frame: base_link       # optional (default "base_link"): read by loadRobotFrames(), not by this function
/// @endcode
///
/// Integers, and strings holding a number ("2e-5", see numberFromString()), are accepted wherever numbers are
/// expected. Other keys are not read here (workspaces: see loadNamedWorkspaces(); anchor_uncertainty_cases, ...). The
/// result is checked with GoughGeometry::validate().
///
/// @param nh    node handle whose namespace holds the parameters
/// @param out   filled only on success
/// @param error on failure: one line naming the fully resolved parameter, what was expected and what was found,
///              e.g. "/pkm_accuracy/base_anchors: expected a list of 6 points [x, y, z] (m), got a list of 5 items"
/// @return true on success
bool loadGoughGeometry(const ros::NodeHandle& nh, model::GoughGeometry& out, std::string& error);

/// Reads the parameters of a robot that are not geometry: `sensor_error` (required), `tool_point` and the
/// uncertainty (`anchor_uncertainty`, `base_anchor_uncertainty`, `platform_anchor_uncertainty`,
/// `tool_point_uncertainty`; optional), same format as above, into `inout` (whose anchors must already be set, e.g. by
/// loadGoughGeometryFromUrdf()), then validates the whole geometry. Used for URDF robots.
bool loadSensorParameters(const ros::NodeHandle& nh, model::GoughGeometry& inout, std::string& error);

/// Reads the robot's named workspaces from the optional parameter `workspaces` (a map name -> workspace, in the
/// format of the robot file's `workspaces`, include/pkm_accuracy/io/RobotFile.hpp and config/ref6.yaml):
///
/// @code{.yaml}
/// workspaces:
///   paper:
///     x: [-0.15, 0.15]              # m, base frame (the box region, or the bounds of another region)
///     y: [-0.15, 0.15]
///     z: [0.45, 0.50]
///     roll: [-0.26, 0.26]           # rad
///     pitch: [-0.26, 0.26]
///     yaw: [-0.26, 0.26]
///     region: {type: cylinder, centre: [0.0, 0.0], radius: 0.1, z: [0.45, 0.5]}  # optional (default: the box);
///             # sphere: centre [x, y, z], radius; polyhedron: normals [[nx, ny, nz], ...], offsets [d, ...]
/// @endcode
///
/// Entries with a `frame` key are read with has_frame set. Not set: `out` is empty.
/// @param error on failure: one line naming the resolved parameter, e.g. "/pkm_accuracy/workspaces/paper/x:
///              expected a range [min, max] of 2 numbers (m) with min <= max, got [0.2, 0.1]"
bool loadNamedWorkspaces(const ros::NodeHandle& nh, std::map<std::string, NamedWorkspace>& out, std::string& error);

/// Names of the frames of a loaded robot.
struct RobotFrames {
  std::string base_frame = kDefaultBaseFrame;          ///< frame of A_i and of every pose
  std::string platform_frame = kDefaultPlatformFrame;  ///< frame of b_i and c
};

/// Reads the optional string parameters `base_frame` and `platform_frame` (defaults above). Fails (naming the
/// parameter) only if one is set but is not a non-empty string.
bool loadRobotFrames(const ros::NodeHandle& nh, RobotFrames& out, std::string& error);

/// How the anchors are found in a URDF. Anchor i (i = 1..6, the leg numbering of the URDF and of the TF frames;
/// leg i is entry i-1 of GoughGeometry's vectors and of the YAML lists) is the origin of the link named
/// printf(base_anchor_pattern, i) expressed in base_link, resp. printf(platform_anchor_pattern, i) expressed in
/// platform_link. Each anchor link must be connected to its reference link by a chain of fixed joints (of any
/// length); the chain's transforms are composed. Set first_index = 0 for URDFs numbering their anchors 0..5.
struct UrdfAnchorNames {
  std::string base_link = kDefaultBaseFrame;
  std::string platform_link = kDefaultPlatformFrame;
  std::string base_anchor_pattern = "base_anchor_%d";
  std::string platform_anchor_pattern = "platform_anchor_%d";
  int first_index = 1;
};

/// printf(pattern, index) if `pattern` contains exactly one %d (or %i) and no other conversion ("%%" allowed),
/// else "" (patterns are user input: anything else is rejected rather than passed to printf).
std::string formatAnchorName(const std::string& pattern, int index);

/// Reads optional parameters `base_frame` (-> base_link), `platform_frame` (-> platform_link),
/// `base_anchor_pattern`, `platform_anchor_pattern` and `anchor_first_index` into `out` (defaults above).
bool loadUrdfAnchorNames(const ros::NodeHandle& nh, UrdfAnchorNames& out, std::string& error);

/// Sets out.base_anchors and out.platform_anchors (6 each) from the URDF as described in UrdfAnchorNames. Leaves
/// every other field of `out` untouched (sensor errors are not in a URDF: see loadSensorParameters()). Checks the
/// anchors (6, distinct, finite) but not the rest of the geometry.
/// @param error on failure, names the link or joint, e.g. "URDF link 'base_anchor_4' (base anchor 4): not found"
bool loadGoughGeometryFromUrdf(const urdf::Model& urdf, const UrdfAnchorNames& names, model::GoughGeometry& out,
                               std::string& error);

/// A robot of a registered type other than gough from the parameters under `nh` (the keys of a robot file of that
/// type, docs/models.md: its geometry groups, sensor_error, optional uncertainty; `workspaces` too for a type whose
/// pose is not the rigid-body pose (out.workspaces: boxes of its pose coordinates), else loadNamedWorkspaces() reads
/// them). The parameters are translated to the robot file's YAML form and read by io::parseModelDocument, so the node
/// and pkm_verify read a robot the same way.
/// @return false with `error` naming the parameter (or the type, if it is not registered).
bool loadModelFromParameters(const ros::NodeHandle& nh, const std::string& type, io::ModelFile& out,
                             std::string& error);

/// An XmlRpc parameter value in YAML flow form (maps, lists, numbers, strings as double-quoted scalars).
std::string toYaml(const XmlRpc::XmlRpcValue& value);

}  // namespace ros_layer
}  // namespace pkm_accuracy
