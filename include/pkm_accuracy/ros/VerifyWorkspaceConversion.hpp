// Translation between srv/VerifyWorkspace.srv, action/VerifyWorkspace.action (and msg/VerificationResult.msg) and the
// ROS-free WorkspaceQuery / WorkspaceOutcome. Every check of a request happens here, so that the verifier only ever
// sees valid input and every rejection names the field.
#pragma once

#include <string>

#include "pkm_accuracy/VerificationResult.h"
#include "pkm_accuracy/VerifyWorkspace.h"
#include "pkm_accuracy/VerifyWorkspaceAction.h"
#include "pkm_accuracy/ros/WorkspaceQuery.hpp"

namespace pkm_accuracy {
namespace ros_layer {

/// Validates `req` and fills `out` (options left at 0 / "" get `defaults`). `base_frame` is the robot's base frame: a
/// frame_id equal to it becomes "" in `out` (no transform); any other frame_id is kept for the node to look up.
/// @param error on failure: "<field>: expected ..., got ...", e.g. "region_type: expected one of box, cylinder,
///              sphere, polyhedron, got \"cube\""
bool fromRequest(const VerifyWorkspace::Request& req, const std::string& base_frame, const QueryDefaults& defaults,
                 WorkspaceQuery& out, std::string& error);

/// Copies an outcome into a response.
void toResponse(const WorkspaceOutcome& outcome, VerifyWorkspace::Response& res);

/// The service request with the fields of an action goal (the goal is the request, field for field).
VerifyWorkspace::Request toRequest(const VerifyWorkspaceGoal& goal);

/// Copies an outcome into an action result (the result is the response, field for field).
void toResult(const WorkspaceOutcome& outcome, VerifyWorkspaceResult& result);

/// The request's region_type string of a region type.
std::string toString(PositionRegion::Type type);

/// Fills everything but the header of a ~verdict message from a job's query, the enclosure method it used and its
/// outcome. A trajectory query (/verify_trajectory) has region_type "trajectory" and, as workspace_min / max, the
/// bounding box of its waypoints.
void toResultMessage(const WorkspaceQuery& query, const std::string& method, const WorkspaceOutcome& outcome,
                     VerificationResult& msg);

}  // namespace ros_layer
}  // namespace pkm_accuracy
