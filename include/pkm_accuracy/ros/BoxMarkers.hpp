// ~boxes: a finished job drawn for RViz (visualization_msgs/MarkerArray, in the robot's base frame): the workspace
// (its region as a translucent shape and its bounding box as a wireframe), the recorded undecided boxes (position
// projection, orange cubes), the witness of an UNSAFE verdict (red sphere), the first uncertainty-sensitive pose and
// its region (yellow sphere and translucent cube), the boxes proven safe that the node asked the verifier to record
// (translucent green cubes, position projections; WorkspaceQuery::record_safe_boxes) and a text label with the
// verdict. Only what the verifier reports is drawn.
// A trajectory job is drawn as its path (the positions of the platform frame's origin, sampled in time) coloured by
// what the verifier reports about each stretch, with the same witness, singular, sensitive and label markers.
#pragma once

#include <cstddef>
#include <string>

#include <ros/time.h>
#include <visualization_msgs/MarkerArray.h>

#include "pkm_accuracy/ros/WorkspaceQuery.hpp"

namespace pkm_accuracy {
namespace ros_layer {

/// Marker namespaces of ~boxes.
constexpr const char* kMarkerNsWorkspace = "workspace";      ///< id 0: the region (CUBE, SPHERE or CYLINDER)
constexpr const char* kMarkerNsBounds = "workspace_bounds";  ///< id 0: LINE_LIST, the region's bounding box
constexpr const char* kMarkerNsUndecided = "undecided";      ///< ids 0..n-1: CUBE per distinct position projection
/// Verify mode: ids 0..n-1: CUBE per distinct position projection of the recorded boxes proven safe (green).
constexpr const char* kMarkerNsSafe = "safe";
constexpr const char* kMarkerNsWitness = "witness";  ///< id 0: SPHERE at the witness position (UNSAFE)
/// Anchor uncertainty, reason uncertainty_sensitive: id 0: SPHERE at the first uncertainty-sensitive pose's position,
/// id 1: CUBE, the position projection of the search box it was found in.
constexpr const char* kMarkerNsSensitive = "sensitive";
/// A certified singular pose (the response's `singular`): id 0: LINE_LIST, the segment between the positions of the
/// two poses of singular_poses, on which J^-1 is singular.
constexpr const char* kMarkerNsSingular = "singular";
constexpr const char* kMarkerNsLabel = "label";  ///< id 0: TEXT_VIEW_FACING, "job N: VERDICT ..."
/// Trajectory jobs: id 0: LINE_LIST, the path in pieces of at most 1/kTrajectoryPieces of the time span (and at
/// least one per segment), each coloured: orange where it meets a recorded undecided time interval; green elsewhere
/// when every other time is proven within the thresholds (verify mode, no witness, every undecided interval
/// recorded); blue otherwise (no claim: max_error mode, or an UNSAFE verdict whose search stopped early).
constexpr const char* kMarkerNsTrajectory = "trajectory";
constexpr int kTrajectoryPieces = 200;
/// Variety jobs: id 0: LINE_LIST, the parameter grid: for each parameter, the lines along it with the other
/// parameters at grid values (at most kVarietyGridValues per parameter and about kVarietyGridLines lines in all), each
/// in kVarietyLinePieces pieces (kTrajectoryPieces for one parameter), coloured as a trajectory's path: orange where
/// a piece meets a recorded undecided parameter box, green where proven, blue otherwise.
constexpr const char* kMarkerNsVariety = "variety";
constexpr int kVarietyGridValues = 11;
constexpr int kVarietyGridLines = 60;
constexpr int kVarietyLinePieces = 40;

/// The markers of a finished job: first a DELETEALL (clears the previous job's), then the markers above. Poses of
/// the query's frame are mapped to `base_frame` with the query's transform (poses only: display, not a proof).
/// At most `max_boxes` undecided boxes are drawn (distinct position projections, in the verifier's order). A workspace
/// of a robot's own pose coordinates (query.pose_domain: not positions of the base frame) gets the label only.
visualization_msgs::MarkerArray makeJobMarkers(const WorkspaceQuery& query, const WorkspaceOutcome& outcome,
                                               const std::string& base_frame, const ros::Time& stamp,
                                               std::size_t max_boxes);

/// The markers of a finished variety job (QueryDomain::Variety): a DELETEALL, its parameter grid (kMarkerNsVariety),
/// the witness, singular and sensitive markers and the label; positions of the query's frame mapped to `base_frame`
/// as above. @throws InvalidArgument if the query's variety was not validated.
visualization_msgs::MarkerArray makeVarietyMarkers(const WorkspaceQuery& query, const WorkspaceOutcome& outcome,
                                                   const std::string& base_frame, const ros::Time& stamp);

/// The markers of a finished trajectory job (query.domain == QueryDomain::Trajectory): a DELETEALL, the path
/// (kMarkerNsTrajectory), the witness, singular and sensitive markers and the label; positions of the query's frame
/// mapped to `base_frame` as above. @throws InvalidArgument if the query's trajectory was not validated.
visualization_msgs::MarkerArray makeTrajectoryMarkers(const WorkspaceQuery& query, const WorkspaceOutcome& outcome,
                                                      const std::string& base_frame, const ros::Time& stamp);

}  // namespace ros_layer
}  // namespace pkm_accuracy
