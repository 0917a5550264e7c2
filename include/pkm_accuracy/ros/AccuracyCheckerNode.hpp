// The accuracy_checker node: loads a Gough platform (parameters or URDF), describes it (~describe), publishes its
// anchors as static TF frames and answers /verify_workspace (service) and ~verify_workspace (actionlib action) with
// the core verifier, publishing ~progress while a job runs, and its result on ~verdict (latched) and its boxes on
// ~boxes (visualization_msgs/MarkerArray, latched) when it ends. /verify_trajectory (service) and ~verify_trajectory
// (action) verify every pose of a trajectory (waypoints or polynomial segments) through the same jobs (limit, busy
// answer, ~progress, ~verdict; ~boxes draws its path), and /verify_variety (service) every pose of a motion variety
// (a surface, volume, ... of poses polynomial in m parameters; ~boxes draws its parameter grid); both actions share one
// implementation (onGoal / runGoal, templates on the action type). A workspace or trajectory given in another frame
// than the base frame is looked up in tf2 at request time and handed to the core as a domain::TransformedDomain. The
// ROS layer only translates: every decision about accuracy is the core's, behind the seam verifyWorkspace().
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <actionlib/server/action_server.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <ros/spinner.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include "pkm_accuracy/Cancel.h"
#include "pkm_accuracy/Describe.h"
#include "pkm_accuracy/Progress.h"
#include "pkm_accuracy/VerifyTrajectory.h"
#include "pkm_accuracy/VerifyTrajectoryAction.h"
#include "pkm_accuracy/VerifyVariety.h"
#include "pkm_accuracy/VerifyVarietyAction.h"
#include "pkm_accuracy/VerifyWorkspace.h"
#include "pkm_accuracy/VerifyWorkspaceAction.h"
#include "pkm_accuracy/core/model/GoughGeometry.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/ros/CoreBridge.hpp"
#include "pkm_accuracy/ros/RobotLoader.hpp"
#include "pkm_accuracy/ros/WorkspaceQuery.hpp"

namespace pkm_accuracy {
namespace ros_layer {

/// Global names of the verification services (they do not move with the node's name or namespace).
constexpr const char* kVerifyWorkspaceService = "/verify_workspace";
constexpr const char* kVerifyTrajectoryService = "/verify_trajectory";
constexpr const char* kVerifyVarietyService = "/verify_variety";
/// Private names of the actions (~verify_workspace, i.e. /pkm_accuracy/verify_workspace with the launch file's name,
/// and ~verify_trajectory).
constexpr const char* kVerifyWorkspaceAction = "verify_workspace";
constexpr const char* kVerifyTrajectoryAction = "verify_trajectory";
constexpr const char* kVerifyVarietyAction = "verify_variety";

class AccuracyCheckerNode {
 public:
  using WorkspaceActionServer = actionlib::ActionServer<VerifyWorkspaceAction>;
  using TrajectoryActionServer = actionlib::ActionServer<VerifyTrajectoryAction>;
  using VarietyActionServer = actionlib::ActionServer<VerifyVarietyAction>;

  /// @param nh  public node handle (services with global names)
  /// @param pnh private node handle ("~"): robot parameters, ~describe
  AccuracyCheckerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);
  ~AccuracyCheckerNode();

  /// Loads the robot (~robot_source = "yaml": loadGoughGeometry() on the private parameters; "urdf": the URDF in
  /// robot_description (searched from the private namespace up) + ~sensor_error), builds its model (once: every
  /// request uses it), then advertises the services, the actions and the topics and publishes the anchor frames.
  /// Returns false, with `error` saying why, only if no robot could be loaded; then nothing is advertised.
  bool start(std::string& error);

  const model::GoughGeometry& robot() const { return robot_; }
  const UrdfAnchorNames& names() const { return names_; }
  const std::string& robotSource() const { return source_; }

  /// THE SEAM between the ROS layer and the core: verifies an already validated query on `model` (the node passes
  /// the model it built once in start()) with the core verifier (CoreBridge.hpp: WorkspaceQuery -> the core's
  /// domain (workspace, or transformed workspace for another frame) / options, verify::Verifier::run, the core's
  /// result -> WorkspaceOutcome). Translates, decides nothing.
  /// @throws InvalidArgument (naming the field) if the core refuses the query, or whatever else the core throws:
  ///         the callers turn any exception into success=false.
  WorkspaceOutcome verifyWorkspace(const model::RobotModel& model, const WorkspaceQuery& query,
                                   const JobHooks& hooks) const;

 private:
  /// A running job (service request or action goal).
  struct Job {
    std::uint64_t id = 0;
    std::atomic<bool> cancel{false};
    std::atomic<bool> client_cancel{false};  ///< the action client cancelled the goal (vs ~cancel / shutdown)
    std::string goal_id;  ///< action goals: "<action name> <actionlib goal id>"; "" for service requests
    ros::WallTime started;
  };
  /// The thread running an action goal.
  struct ActionThread {
    std::thread thread;
    std::shared_ptr<std::atomic<bool>> done;
  };

  bool loadRobot(std::string& error);
  bool onDescribe(Describe::Request& req, Describe::Response& res);
  bool onVerifyWorkspace(VerifyWorkspace::Request& req, VerifyWorkspace::Response& res);
  /// /verify_trajectory: the same job admission (~max_parallel_jobs, busy), runJob(), ~progress and ~verdict as
  /// /verify_workspace; only the translation differs (VerifyTrajectoryConversion.hpp).
  bool onVerifyTrajectory(VerifyTrajectory::Request& req, VerifyTrajectory::Response& res);
  /// /verify_variety: likewise (VerifyVarietyConversion.hpp).
  bool onVerifyVariety(VerifyVariety::Request& req, VerifyVariety::Response& res);
  /// The three services' common handler: fromRequest(), admit(), runJob(), toResponse(); never throws, never
  /// answers with a transport error (success false + message instead).
  template <class Srv>
  bool onVerify(typename Srv::Request& req, typename Srv::Response& res, const char* name);
  bool onCancel(Cancel::Request& req, Cancel::Response& res);
  /// A goal of either action (~verify_workspace, ~verify_trajectory; `name` = its private name): validated like the
  /// service request (REJECTED naming the field), admitted under the same job limit (REJECTED, result.busy) and run
  /// in its own thread by runGoal().
  template <class Action>
  void onGoal(actionlib::ServerGoalHandle<Action> gh, const char* name);
  /// Runs an accepted goal through runJob() (feedback = every ~progress snapshot) and ends it: SUCCEEDED (the
  /// verifier ran), PREEMPTED (cancelled by the client, partial result), ABORTED (failure, ~cancel, shutdown).
  template <class Action>
  void runGoal(const std::shared_ptr<Job>& job, const WorkspaceQuery& query, actionlib::ServerGoalHandle<Action> gh,
               const char* name);
  /// The client cancels the goal `goal_id` of the action `name`: its job stops promptly.
  void onGoalCancel(const std::string& goal_id, const char* name);
  /// Creates, starts and returns the action server `name` on the verification queue.
  template <class Action>
  std::unique_ptr<actionlib::ActionServer<Action>> startActionServer(const char* name);
  /// Registers a new job, or returns null and explains in `refusal` (busy / shutting down).
  std::shared_ptr<Job> admit(WorkspaceOutcome& refusal, const std::string& goal_id = "");
  void finish(const std::shared_ptr<Job>& job);
  /// Runs an admitted job to its end and releases it (finish()): looks frame_id up in tf2, runs the core through
  /// verifyWorkspace(), publishes ~progress while it runs (and hands every snapshot to `feedback` if set), then
  /// ~verdict, a last ~progress and ~boxes. Never throws: a failure is an outcome with success false.
  WorkspaceOutcome runJob(const std::shared_ptr<Job>& job, WorkspaceQuery query, const std::string& via,
                          const std::function<void(const Progress&)>& feedback);
  /// Fills the query's transform from tf2 (base frame <- frame_id, latest, waiting up to ~tf_timeout).
  bool resolveFrame(WorkspaceQuery& query, std::string& error);
  void publishAnchorFrames();
  void readDefaults();
  void reapActionThreads(bool all);

  ros::NodeHandle nh_;
  ros::NodeHandle pnh_;
  model::GoughGeometry robot_;
  std::unique_ptr<const model::GoughPlatform> model_;  ///< built once from robot_ in start()
  UrdfAnchorNames names_;  ///< frames (base_link = base frame, platform_link = platform frame) and anchor names
  std::string source_;     ///< "yaml" | "urdf"
  QueryDefaults defaults_;
  int max_parallel_jobs_ = 1;        ///< ~max_parallel_jobs (service and action jobs together)
  double progress_period_s_ = 0.5;   ///< 1 / ~progress_rate; 0 = no ~progress
  double tf_timeout_s_ = 1.0;        ///< ~tf_timeout
  int max_box_markers_ = 500;        ///< ~max_box_markers
  int max_safe_box_markers_ = 2000;  ///< ~max_safe_box_markers

  ros::ServiceServer describe_srv_;
  ros::ServiceServer cancel_srv_;
  ros::ServiceServer verify_workspace_srv_;
  ros::ServiceServer verify_trajectory_srv_;
  ros::ServiceServer verify_variety_srv_;
  ros::Publisher verdict_pub_;   ///< ~verdict (latched)
  ros::Publisher progress_pub_;  ///< ~progress
  ros::Publisher boxes_pub_;     ///< ~boxes (latched)
  // Verification requests may run for minutes: they get their own queue, served by max_parallel_jobs_ + 1 threads,
  // so ~describe and ~cancel (global queue) stay responsive, at most max_parallel_jobs_ jobs run at once, and one
  // thread is always free to answer "busy" to a request beyond that. The action server's callbacks (goal, cancel)
  // are served from the same queue and return at once: each accepted goal runs in its own thread.
  ros::CallbackQueue verify_queue_;
  std::unique_ptr<ros::AsyncSpinner> verify_spinner_;
  std::unique_ptr<WorkspaceActionServer> workspace_action_server_;
  std::unique_ptr<TrajectoryActionServer> trajectory_action_server_;
  std::unique_ptr<VarietyActionServer> variety_action_server_;
  std::mutex threads_mutex_;
  std::vector<ActionThread> action_threads_;
  std::mutex jobs_mutex_;
  std::map<std::uint64_t, std::shared_ptr<Job>> jobs_;  ///< running jobs by id
  std::uint64_t last_job_id_ = 0;
  bool shutting_down_ = false;
  /// A job ended since the last trim: once no job runs, the idle timer gives the heap's free memory back to the
  /// system (malloc_trim), so that the node returns to its baseline after a large job.
  bool trim_pending_ = false;
  ros::WallTimer idle_trim_timer_;
  void trimWhenIdle();
  std::unique_ptr<tf2_ros::StaticTransformBroadcaster> tf_broadcaster_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
};

}  // namespace ros_layer
}  // namespace pkm_accuracy
