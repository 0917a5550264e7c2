// ~boxes: a finished job drawn for RViz (visualization_msgs/MarkerArray, in the robot's base frame): the workspace
// (its region as a translucent shape and its bounding box as a wireframe), the recorded undecided boxes (position
// projection, orange cubes), the witness of an UNSAFE verdict (red sphere), the first uncertainty-sensitive pose and
// its region (yellow sphere and translucent cube) and a text label with the verdict. Only
// what the verifier reports is drawn: it records undecided boxes and the witness, not the boxes it proved safe.
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
constexpr const char* kMarkerNsWitness = "witness";          ///< id 0: SPHERE at the witness position (UNSAFE)
/// Anchor uncertainty, reason uncertainty_sensitive: id 0: SPHERE at the first uncertainty-sensitive pose's position,
/// id 1: CUBE, the position projection of the search box it was found in.
constexpr const char* kMarkerNsSensitive = "sensitive";
/// A certified singular pose (the response's `singular`): id 0: LINE_LIST, the segment between the positions of the
/// two poses of singular_poses, on which J^-1 is singular.
constexpr const char* kMarkerNsSingular = "singular";
constexpr const char* kMarkerNsLabel = "label";  ///< id 0: TEXT_VIEW_FACING, "job N: VERDICT ..."

/// The markers of a finished job: first a DELETEALL (clears the previous job's), then the markers above. Poses of
/// the query's frame are mapped to `base_frame` with the query's transform (poses only: display, not a proof).
/// At most `max_boxes` undecided boxes are drawn (distinct position projections, in the verifier's order).
visualization_msgs::MarkerArray makeJobMarkers(const WorkspaceQuery& query, const WorkspaceOutcome& outcome,
                                               const std::string& base_frame, const ros::Time& stamp,
                                               std::size_t max_boxes);

}  // namespace ros_layer
}  // namespace pkm_accuracy
