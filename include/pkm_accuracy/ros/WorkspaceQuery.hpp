// ROS-free description of one /verify_workspace request and of its outcome: what the ROS layer hands to the core
// and gets back. Plain std/Eigen types only (and the core's plain PolynomialTrajectory::Segment), already validated
// by fromRequest() (VerifyWorkspaceConversion.hpp, VerifyTrajectoryConversion.hpp).
// CoreBridge.hpp converts them to the core's domain::Workspace / verify::VerifierOptions and the core's
// verify::VerifierResult back to a WorkspaceOutcome.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "pkm_accuracy/core/domain/Domain.hpp"
#include "pkm_accuracy/core/domain/ParametricVariety.hpp"
#include "pkm_accuracy/core/domain/PolynomialTrajectory.hpp"
#include "pkm_accuracy/core/model/RobotDescription.hpp"

namespace pkm_accuracy {
namespace ros_layer {

/// Set of positions (m, in the query's frame_id) of the platform frame's origin.
struct PositionRegion {
  enum class Type { Box, Cylinder, Sphere, Polyhedron };
  Type type = Type::Box;
  Eigen::Vector3d box_min = Eigen::Vector3d::Zero();  ///< Box, Polyhedron (bounding box)
  Eigen::Vector3d box_max = Eigen::Vector3d::Zero();
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< Sphere: centre; Cylinder: (x, y) of the vertical axis
  double radius = 0.0;                               ///< Sphere, Cylinder (> 0)
  double z_min = 0.0, z_max = 0.0;                   ///< Cylinder
  std::vector<Eigen::Vector3d> halfspace_normals;    ///< Polyhedron: n_j . p <= d_j
  std::vector<double> halfspace_offsets;

  /// Axis-aligned box enclosing the region (m).
  void boundingBox(Eigen::Vector3d& lo, Eigen::Vector3d& hi) const;
};

/// Workspace: positions in `position`, angles (rad) in [angle_min[k], angle_max[k]], k = roll, pitch, yaw.
struct WorkspaceSpec {
  PositionRegion position;
  Eigen::Vector3d angle_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d angle_max = Eigen::Vector3d::Zero();
};

/// A named workspace of the robot (the `workspaces` map of its parameters, as in config/ref6.yaml), in the base frame.
struct NamedWorkspace {
  WorkspaceSpec spec;
  /// A robot whose pose is not the rigid-body pose: the workspace as a domain of its own pose coordinates (as the robot
  /// file's reader makes it; `spec` is then unused). Null for rigid-body robots.
  std::shared_ptr<const domain::Domain> domain;
  /// The entry has a `frame` key (a workspace given in a frame fixed to the base frame; pkm_verify reads it, the
  /// node refuses to verify such an entry).
  bool has_frame = false;
};

enum class QueryMode { Verify, MaxError };

/// A trajectory of /verify_trajectory in the query's frame, already validated: timed waypoints (times (s) strictly
/// increasing, poses x, y, z (m), roll, pitch, yaw (rad), R = Rz(yaw) Ry(pitch) Rx(roll)), or polynomial segments
/// (`segments` not empty: then `times` are the segment boundaries and `poses` the poses at the ends of every segment,
/// for reports only).
struct TrajectorySpec {
  std::vector<double> times;
  std::vector<std::array<double, 6>> poses;
  bool slerp = true;  ///< waypoints: orientation interpolation, slerp or linear in roll, pitch, yaw
  std::vector<domain::PolynomialTrajectory::Segment> segments;  ///< the polynomial segments (empty: waypoints)
  /// t_0 + u (t_N - t_0), clamped to [t_0, t_N] (s).
  double timeOf(double u) const;
};

/// A motion variety of /verify_variety in the query's frame, already validated: `parameters` (m, 1 .. 6) parameters
/// in [0, 1]^m, every pose coordinate (x, y, z in m; roll, pitch, yaw in rad) a sum of monomials (the core's plain
/// ParametricVariety::Monomial).
struct VarietySpec {
  int parameters = 0;
  std::array<std::vector<domain::ParametricVariety::Monomial>, 6> coordinates;
};

/// What a query verifies.
enum class QueryDomain {
  Workspace,   ///< /verify_workspace: `workspace`; min_width in m / rad
  Trajectory,  ///< /verify_trajectory: `trajectory` (one box variable u over its time span); min_width in s
  Variety,     ///< /verify_variety: `variety` (its m parameters are the box variables); min_width in parameter units
};

/// One request. Zeros in the options mean "the node's default"; fromRequest() has already substituted them.
struct WorkspaceQuery {
  QueryDomain domain = QueryDomain::Workspace;  ///< which of the three below is verified
  WorkspaceSpec workspace;
  std::string workspace_name;  ///< the named workspace `workspace` is (QueryDefaults::workspaces); "" = none
  /// A robot whose pose is not the rigid-body pose: the workspace as a domain of its own pose coordinates (a named
  /// workspace or the request's pose_min / pose_max box; then `workspace` is unused and there is no transform).
  std::shared_ptr<const domain::Domain> pose_domain;
  /// The robot's number of error components n (= pose coordinates): thresholds, bounds and pose vectors use their
  /// first n entries, the rest are 0.
  int components = 6;
  /// The robot's pose is the rigid-body pose (x, y, z, roll, pitch, yaw): poses are reported as geometry_msgs/Pose too.
  bool rigid_body_pose = true;
  TrajectorySpec trajectory;
  VarietySpec variety;
  std::array<double, 6> thresholds{};  ///< on |dX_k|: m, m, m, rad, rad, rad (may be +inf); all 0 = none given
  bool has_thresholds = false;
  QueryMode mode = QueryMode::Verify;
  double alpha = 0.0;        ///< max_error: relative accuracy > 0: upper - lower <= alpha * lower
  double time_budget = 0.0;  ///< s, > 0
  double min_width = 0.0;    ///< m / rad, s or parameter units (see QueryDomain), >= 0 (0: the verifier chooses)
  unsigned threads = 0;      ///< 0 = all hardware threads
  std::string method;        ///< enclosure method name; "": the verifier's default
  /// Geometric uncertainty (robots with anchor uncertainty): "auto", "never" or "always" (verify::GeometrySplitting).
  std::string geometry_splitting = "auto";
  /// Frame of the workspace and of every pose of the outcome; "" = the robot's base frame. For another frame the
  /// node fills the transform below from tf2 (has_transform) before the core runs.
  std::string frame_id;
  bool has_transform = false;
  /// base_from_frame, the pose of frame_id in the base frame: p_base = translation + rotation p_frame.
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  /// Workspaces in mode verify: keep up to this many boxes proven safe (set by the node for ~boxes; 0: none).
  std::size_t record_safe_boxes = 0;
};

/// A box of the search (x, y, z in m; roll, pitch, yaw in rad; in the query's frame).
struct Box6 {
  std::array<double, 6> lo{};
  std::array<double, 6> hi{};
};

/// The first uncertainty-sensitive pose of a result (verify::SensitivePose; units and frames as the witness).
struct SensitiveSummary {
  int component = -1;                          ///< 0..5; -1: none
  double failing_lower = 0.0;                  ///< certified, for failing_geometry
  std::array<double, 6> pose{};                ///< x, y, z (m), roll, pitch, yaw (rad); workspace: in the query's frame
  Box6 region;                                 ///< workspace: the search box it was found in (query's frame)
  double t = 0.0, t_start = 0.0, t_end = 0.0;  ///< trajectory: its time and the time interval searched (s)
  /// variety: its parameter point and the parameter box searched (m numbers each; empty: none)
  std::vector<double> parameters, region_lower, region_upper;
  std::vector<double> failing_geometry;  ///< one value per geometry parameter (model order)
  std::vector<double> passing_geometry;  ///< empty: none found
  double passing_upper = 0.0;
  bool passes_all = false;
};

/// Outcome of one request (mirrors the response of srv/VerifyWorkspace.srv, whose comments give units and frames). For
/// a robot with n < 6 components every 6-number vector holds them first, then zeros.
struct WorkspaceOutcome {
  bool rigid_body_pose = true;  ///< as the query's: false: no geometry_msgs/Pose of the poses (argmax, witness)
  bool success = false;
  std::string message;
  bool busy = false;
  std::uint64_t job_id = 0;
  std::string verdict;  ///< "SAFE" | "UNSAFE" | "UNDECIDED" | ""
  std::string reason;   ///< UNDECIDED: "precision_limit" | "time_budget" | "box_budget" | "cancelled" | ...; else ""
  std::array<double, 6> lower_bound{};
  std::array<double, 6> upper_bound{};
  bool converged = false;
  std::vector<double> lower_bound_poses;  ///< max_error: 6 x 6 row-major (row k: pose attaining lower_bound[k])
  std::vector<double> lower_bound_times;  ///< trajectory, max_error: 6 times (s) attaining lower_bound[k]
  /// variety, max_error: 6 x m row-major (row k: the parameter point of row k of lower_bound_poses)
  std::vector<double> lower_bound_parameters;
  /// max_error with geometry parameters: 6 x P row-major (row k: an admissible geometry, one value per parameter,
  /// attaining lower_bound[k] at row k of lower_bound_poses / at lower_bound_times[k]); empty otherwise.
  std::vector<double> lower_bound_geometries;
  bool has_witness = false;
  std::array<double, 6> witness_pose{};    ///< x, y, z (m), roll, pitch, yaw (rad)
  double witness_t = 0.0;                  ///< trajectory: time of the witness (s)
  std::vector<double> witness_parameters;  ///< variety: the witness's parameter point (m numbers; empty: none)
  int witness_component = -1;
  std::array<double, 6> witness_error{};
  /// A certified singular pose between the two poses of singular_poses (x, y, z, roll, pitch, yaw each; see
  /// verify::VerifierResult::singular); trajectory: singular_t, their times (s).
  bool singular = false;
  std::array<double, 12> singular_poses{};
  std::array<double, 2> singular_t{};
  std::vector<double> singular_parameters;  ///< variety: the two parameter points (2 x m; empty unless singular)
  std::uint64_t boxes = 0;
  unsigned max_depth = 0;
  unsigned threads = 0;
  double seconds = 0.0;
  double safe_fraction = 0.0, unsafe_fraction = 0.0, undecided_fraction = 0.0, outside_fraction = 0.0;
  std::uint64_t undecided_boxes = 0;
  std::uint64_t undecided_boxes_recorded = 0;
  std::array<double, 6> undecided_min{};  ///< hull of the recorded undecided boxes
  std::array<double, 6> undecided_max{};
  std::vector<Box6> undecided_recorded;  ///< the recorded undecided boxes themselves (for ~boxes; not in the srv)
  /// variety: the recorded undecided parameter boxes, lower and upper corners (k x m row-major each)
  std::vector<double> undecided_parameters_lower, undecided_parameters_upper;
  std::vector<Box6> safe_recorded;  ///< boxes proven safe (query.record_safe_boxes of them; for ~boxes; not in the srv)
  /// trajectory: the recorded undecided boxes as time intervals (s), sorted, merged where they touch or overlap
  std::vector<std::pair<double, double>> undecided_times;
  // Geometric uncertainty.
  std::uint64_t geometry_switches = 0;  ///< boxes that switched to bisecting the geometry
  std::uint64_t geometry_splits = 0;    ///< bisections of a geometry parameter
  std::uint64_t face_switches = 0;      ///< search paths that switched to the faces of the geometry box
  std::uint64_t face_boxes = 0;         ///< boxes enclosed on faces
  std::uint64_t unenclosed_boxes = 0;   ///< boxes split without an enclosure (SearchTuning::skip_hopeless)
  std::uint64_t sensitive_poses = 0;    ///< uncertainty-sensitive poses found
  SensitiveSummary sensitive;           ///< the first of them (component -1 if none)
};

/// Node-wide defaults for the options a request leaves at 0, and the loaded robot as a request names it: its type,
/// pose coordinates and error components, and the named workspaces a request may ask for.
struct QueryDefaults {
  std::string robot_type = "gough";
  std::vector<model::PoseComponent> pose = model::rigidBodyPose();  ///< the robot's pose coordinates, in order
  bool rigidBodyPose() const { return model::hasRigidBodyPose(pose); }
  double alpha = 0.01;
  double time_budget = 10.0;                         ///< s: jobs take well under a second; a long one must ask for more
  double min_width = 0.0;                            ///< 0: let the verifier choose (relative to the workspace)
  std::string method;                                ///< "": the verifier's default (verify::VerifierOptions::method)
  std::map<std::string, NamedWorkspace> workspaces;  ///< by name (the robot's `workspaces` parameter)
};

}  // namespace ros_layer
}  // namespace pkm_accuracy
