// Translation between srv/VerifyVariety.srv, action/VerifyVariety.action and the ROS-free WorkspaceQuery (domain
// Variety) / WorkspaceOutcome. Every check of a request happens here (each rejection names the field, e.g.
// "x[1].exponents[0]"), so the core only sees a valid variety.
#pragma once

#include <string>

#include "pkm_accuracy/VerifyVariety.h"
#include "pkm_accuracy/VerifyVarietyAction.h"
#include "pkm_accuracy/ros/WorkspaceQuery.hpp"

namespace pkm_accuracy {
namespace ros_layer {

/// Validates `req` and fills `out` (domain = QueryDomain::Variety; options left at 0 / "" get `defaults`).
/// `base_frame` is the robot's base frame: a frame_id equal to it becomes "" (any other frame is the node's to look
/// up in tf2).
/// @param error on failure: "<field>: expected ..., got ...", e.g. "yaw[0].exponents: expected 2 exponents (one per
///              parameter), got 3"
bool fromRequest(const VerifyVariety::Request& req, const std::string& base_frame, const QueryDefaults& defaults,
                 WorkspaceQuery& out, std::string& error);

/// Copies an outcome into a response.
void toResponse(const WorkspaceOutcome& outcome, VerifyVariety::Response& res);

/// The service request with the fields of an action goal (the goal is the request, field for field).
VerifyVariety::Request toRequest(const VerifyVarietyGoal& goal);

/// Copies an outcome into an action result (the result is the response, field for field).
void toResult(const WorkspaceOutcome& outcome, VerifyVarietyResult& result);

}  // namespace ros_layer
}  // namespace pkm_accuracy
