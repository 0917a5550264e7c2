// Translation between srv/VerifyTrajectory.srv, action/VerifyTrajectory.action and the ROS-free WorkspaceQuery
// (domain Trajectory) / WorkspaceOutcome. Every check of a request happens here (each rejection names the field), so
// the core only sees valid waypoints.
#pragma once

#include <string>

#include "pkm_accuracy/VerificationResult.h"
#include "pkm_accuracy/VerifyTrajectory.h"
#include "pkm_accuracy/VerifyTrajectoryAction.h"
#include "pkm_accuracy/ros/WorkspaceQuery.hpp"

namespace pkm_accuracy {
namespace ros_layer {

/// Validates `req` and fills `out` (domain = QueryDomain::Trajectory; options left at 0 / "" get `defaults`).
/// `base_frame` is the robot's base frame: a frame_id equal to it becomes "" (any other frame is the node's to look up
/// in tf2).
/// @param error on failure: "<field>: expected ..., got ...", e.g. "times[2]: expected a time greater than times[1]
///              = 1 s (strictly increasing), got 1"
bool fromRequest(const VerifyTrajectory::Request& req, const std::string& base_frame, const QueryDefaults& defaults,
                 WorkspaceQuery& out, std::string& error);

/// Copies an outcome into a response.
void toResponse(const WorkspaceOutcome& outcome, VerifyTrajectory::Response& res);

/// The service request with the fields of an action goal (the goal is the request, field for field).
VerifyTrajectory::Request toRequest(const VerifyTrajectoryGoal& goal);

/// Copies an outcome into an action result (the result is the response, field for field).
void toResult(const WorkspaceOutcome& outcome, VerifyTrajectoryResult& result);

}  // namespace ros_layer
}  // namespace pkm_accuracy
