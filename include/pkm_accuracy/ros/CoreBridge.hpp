// The seam's translation, ROS-free: WorkspaceQuery -> the core's domain::Workspace and verify::VerifierOptions, and
// the core's verify::VerifierResult -> WorkspaceOutcome. Nothing here decides anything about accuracy: verdicts,
// bounds and witnesses are the verifier's; this file only changes their representation.
#pragma once

#include <atomic>
#include <functional>
#include <memory>

#include "pkm_accuracy/core/domain/ParametricVariety.hpp"
#include "pkm_accuracy/core/domain/PiecewiseTrajectory.hpp"
#include "pkm_accuracy/core/domain/Workspace.hpp"
#include "pkm_accuracy/core/model/RobotModel.hpp"
#include "pkm_accuracy/core/verify/VerifierOptions.hpp"
#include "pkm_accuracy/core/verify/VerifierResult.hpp"
#include "pkm_accuracy/ros/WorkspaceQuery.hpp"

namespace pkm_accuracy {
namespace ros_layer {

/// What a running job is connected to (all optional).
struct JobHooks {
  const std::atomic<bool>* cancel = nullptr;              ///< set to true to stop the job promptly
  std::function<void(const verify::Progress&)> progress;  ///< called from a worker thread; keep it short
  double progress_period_s = 0.5;                         ///< at most one progress call per this many seconds
};

/// The workspace of a query. @throws InvalidArgument (naming the range) on a range the core refuses.
domain::Workspace toWorkspace(const WorkspaceSpec& spec);

/// The trajectory of a query (waypoints or polynomial segments), in its frame_id.
/// @throws InvalidArgument if the spec was not validated (fromRequest() of VerifyTrajectoryConversion.hpp checks it).
std::unique_ptr<domain::PiecewiseTrajectory> toTrajectory(const TrajectorySpec& spec);

/// The motion variety of a query, in its frame_id.
/// @throws InvalidArgument if the spec was not validated (fromRequest() of VerifyVarietyConversion.hpp checks it).
std::unique_ptr<domain::ParametricVariety> toVariety(const VarietySpec& spec);

/// The search domain of a query: its workspace (query.pose_domain for a robot whose pose is not the rigid-body pose),
/// trajectory or variety, or, when the query has a transform (frame_id other than the base frame), the core's
/// domain::TransformedDomain of it (which decides which transforms it supports).
/// @throws InvalidArgument as toWorkspace, or the core's refusal of the transform (prefixed with "frame_id \"F\": ").
std::shared_ptr<const domain::Domain> toDomain(const WorkspaceQuery& query);

/// The verifier options of a query: mode, thresholds (a threshold of +inf, "do not check", becomes the largest
/// finite double: every bounded error passes it, an unbounded one does not), alpha (relative), time limit, min width
/// (the same for every variable; 0 = the verifier's choice), threads, method ("" = the verifier's default), geometry
/// splitting ("never", "always", anything else: auto), hooks. The search's internal knobs (verify::SearchTuning) stay
/// at their defaults.
verify::VerifierOptions toVerifierOptions(const WorkspaceQuery& query, const JobHooks& hooks = JobHooks());

/// The outcome of a finished run (success = true). `model` is used only to evaluate the error at a max_error
/// witness (the verifier gives the witness but not its error vector in that mode).
WorkspaceOutcome toOutcome(const verify::VerifierResult& result, const WorkspaceQuery& query,
                           const model::RobotModel& model);

/// toDomain + toVerifierOptions + verify::Verifier::run + toOutcome.
/// @throws InvalidArgument (naming the field) if the core refuses the query; anything else the core throws.
WorkspaceOutcome runWorkspaceQuery(const model::RobotModel& model, const WorkspaceQuery& query,
                                   const JobHooks& hooks = JobHooks());

}  // namespace ros_layer
}  // namespace pkm_accuracy
