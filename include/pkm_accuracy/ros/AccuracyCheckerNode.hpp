// The accuracy_checker node: loads a Gough platform (parameters or URDF), describes it (~describe), publishes its
// anchors as static TF frames and answers verify_workspace (service, in the node's namespace) and ~verify_workspace
// (actionlib action) with the core verifier, publishing ~progress while a job runs, and its result on ~verdict
// (latched) and its boxes on ~boxes (visualization_msgs/MarkerArray, latched) when it ends. verify_trajectory
// (service) and ~verify_trajectory (action) verify every pose of a trajectory (waypoints or polynomial segments)
// through the same jobs (limit, busy answer, ~progress, ~verdict; ~boxes draws its path), and verify_variety (service)
// every pose of a motion variety (a surface, volume, ... of poses polynomial in m parameters; ~boxes draws its
// parameter grid); the actions share one implementation (onGoal / runGoal, templates on the action type). A workspace
// or trajectory given in another frame than the base frame is looked up in tf2 before the job takes a slot and handed
// to the core as a domain::TransformedDomain. Jobs whose client is gone are cancelled (ClientLiveness.hpp); a
// client's new goal preempts its running goal on the same action. /diagnostics (diagnostic_updater) reports the
// robot, the jobs, the busy answers and the last verdict. The ROS layer only translates: every decision about
// accuracy is the core's, behind the seam verifyWorkspace().
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <actionlib/server/action_server.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <ros/service_callback_helper.h>
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

/// Names of the verification services, relative to the node's namespace: /verify_workspace for a node at the root,
/// /robot1/verify_workspace for a node in <group ns="robot1"> (remappable like any relative name).
constexpr const char* kVerifyWorkspaceService = "verify_workspace";
constexpr const char* kVerifyTrajectoryService = "verify_trajectory";
constexpr const char* kVerifyVarietyService = "verify_variety";
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

  /// @param nh  public node handle (the verification services, in its namespace)
  /// @param pnh private node handle ("~"): robot parameters, ~describe
  AccuracyCheckerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);
  ~AccuracyCheckerNode();

  /// Loads the robot (~robot_source = "yaml": loadGoughGeometry() on the private parameters; "urdf": the URDF in
  /// robot_description (searched from the private namespace up) + ~sensor_error), builds its model (once: every
  /// request uses it), logs the effective robot, then advertises the services, the actions and the topics and
  /// publishes the anchor frames. Returns false, with `error` saying why (naming the parameter), only if no robot
  /// could be loaded; then nothing is advertised.
  bool start(std::string& error);

  const model::GoughGeometry& robot() const { return robot_; }
  const UrdfAnchorNames& names() const { return names_; }
  const std::string& robotSource() const { return source_; }
  /// The tf name of the base frame: ~frame_prefix + the base link's name.
  const std::string& baseFrame() const { return base_frame_; }

  /// THE SEAM between the ROS layer and the core: verifies an already validated query on `model` (the node passes
  /// the model it built once in start()) with the core verifier (CoreBridge.hpp: WorkspaceQuery -> the core's
  /// domain (workspace, or transformed workspace for another frame) / options, verify::Verifier::run, the core's
  /// result -> WorkspaceOutcome). Translates, decides nothing.
  /// @throws InvalidArgument (naming the field) if the core refuses the query, or whatever else the core throws:
  ///         the callers turn any exception into success=false.
  WorkspaceOutcome verifyWorkspace(const model::RobotModel& model, const WorkspaceQuery& query,
                                   const JobHooks& hooks) const;

 private:
  /// Why a job stopped early, when it did (the outcome's reason is then the core's "cancelled").
  enum class StopCause { None, ClientCancel, Preempted, ClientGone, CancelService };
  /// A running job (service request or action goal).
  struct Job {
    std::uint64_t id = 0;
    std::atomic<bool> cancel{false};
    std::atomic<StopCause> cause{StopCause::None};  ///< set with cancel (the first cause wins)
    std::string goal_id;     ///< action goals: "<action name> <actionlib goal id>"; "" for service requests
    std::string action;      ///< action goals: the action's private name; "" for service requests
    std::string client;      ///< the caller's node name ("" if unknown)
    std::string client_uri;  ///< its XML-RPC URI from the master when the job started ("" = not watched)
    int gone_probes = 0;     ///< consecutive probes of client_uri that were refused (watch thread only)
    ros::WallTime started;
    /// Asks the job to stop for `why` (keeps the first cause).
    void stop(StopCause why) {
      StopCause none = StopCause::None;
      cause.compare_exchange_strong(none, why);
      cancel = true;
    }
  };
  /// For log lines: "preempted by a newer goal of the same client", ...; "" for None.
  static std::string stopCauseText(StopCause cause);
  /// The thread running an action goal.
  struct ActionThread {
    std::thread thread;
    std::shared_ptr<std::atomic<bool>> done;
  };
  template <class Srv>
  using Event = ros::ServiceEvent<typename Srv::Request, typename Srv::Response>;

  bool loadRobot(std::string& error);
  /// The effective robot as the verifier sees it, for the start-up log (type, dof, source and file, frames, sensor
  /// errors, tool point, uncertainty half-widths).
  std::string robotReport() const;
  /// Loads the libraries of ~plugins (robot types; io::loadModelPlugin).
  bool loadPlugins(std::string& error);
  /// A robot of another type than gough from the parameters (loadModelFromParameters); a type whose pose is not the
  /// rigid-body pose also brings its named workspaces (boxes of its pose coordinates) and sets the pose coordinates
  /// that requests name (QueryDefaults::pose).
  bool loadOtherRobot(std::string& error);
  bool onDescribe(Describe::Request& req, Describe::Response& res);
  bool onVerifyWorkspace(Event<VerifyWorkspace>& event);
  /// verify_trajectory: the same job admission (~max_parallel_jobs, busy), runJob(), ~progress and ~verdict as
  /// verify_workspace; only the translation differs (VerifyTrajectoryConversion.hpp).
  bool onVerifyTrajectory(Event<VerifyTrajectory>& event);
  /// verify_variety: likewise (VerifyVarietyConversion.hpp).
  bool onVerifyVariety(Event<VerifyVariety>& event);
  /// The three services' common handler: fromRequest(), the tf2 lookup of frame_id, admit() (watching the caller
  /// node), runJob(), toResponse(); never throws, never answers with a transport error (success false + message).
  template <class Srv>
  bool onVerify(Event<Srv>& event, const char* name);
  bool onCancel(Cancel::Request& req, Cancel::Response& res);
  /// A goal of either action (~verify_workspace, ~verify_trajectory, ~verify_variety; `name` = its private name):
  /// validated like the service request and its frame looked up in tf2 (REJECTED naming the field), then it
  /// preempts the running goals of the same client on the same action, is admitted under the same job limit
  /// (REJECTED, result.busy) and runs in its own thread by runGoal().
  template <class Action>
  void onGoal(actionlib::ServerGoalHandle<Action> gh, const char* name);
  /// Runs an accepted goal through runJob() (feedback = every ~progress snapshot) and ends it: SUCCEEDED (the
  /// verifier ran), PREEMPTED (cancelled by the client or preempted by its newer goal: partial result), ABORTED
  /// (failure, ~cancel, shutdown, client gone).
  template <class Action>
  void runGoal(const std::shared_ptr<Job>& job, const WorkspaceQuery& query, actionlib::ServerGoalHandle<Action> gh,
               const char* name);
  /// The client cancels the goal `goal_id` of the action `name`: its job stops promptly.
  void onGoalCancel(const std::string& goal_id, const char* name);
  /// Stops the running goals of `client` on the action `name` (StopCause::Preempted) and waits up to `timeout_s`
  /// for their jobs to release their slots. Returns how many it stopped.
  std::size_t preemptGoalsOf(const std::string& client, const char* name, double timeout_s);
  /// Creates, starts and returns the action server `name` on the verification queue.
  template <class Action>
  std::unique_ptr<actionlib::ActionServer<Action>> startActionServer(const char* name);
  /// Registers a new job, or returns null and explains in `refusal` (busy / shutting down). `client` (a node name)
  /// is looked up in the master and watched while the job runs (unless it is this node).
  std::shared_ptr<Job> admit(WorkspaceOutcome& refusal, const std::string& client, const std::string& goal_id = "",
                             const std::string& action = "");
  void finish(const std::shared_ptr<Job>& job, const WorkspaceOutcome& outcome);
  /// Runs an admitted job (its frame already resolved) to its end and releases it (finish()): runs the core through
  /// verifyWorkspace(), publishes ~progress while it runs (and hands every snapshot to `feedback` if set), then
  /// ~verdict, a last ~progress and ~boxes. Never throws: a failure is an outcome with success false.
  WorkspaceOutcome runJob(const std::shared_ptr<Job>& job, WorkspaceQuery query, const std::string& via,
                          const std::function<void(const Progress&)>& feedback);
  /// Fills the query's transform from tf2 (base frame <- frame_id, latest, waiting up to ~tf_timeout). Called before
  /// admission: a request waiting for its frame holds no job slot.
  bool resolveFrame(WorkspaceQuery& query, std::string& error);
  void publishAnchorFrames();
  /// Reads the node options (~default_*, ~progress_rate, ~tf_timeout, ~max_*): a value that is not a number, or
  /// out of range, is refused with a warning naming the parameter, and its default is used.
  void readDefaults();
  void reapActionThreads(bool all);
  /// The client watch thread: every ~client_check_period seconds, probes the XML-RPC address of every running
  /// job's client; two refusals in a row (the process is gone) stop the job (StopCause::ClientGone).
  void watchClients();
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);

  ros::NodeHandle nh_;
  ros::NodeHandle pnh_;
  model::GoughGeometry robot_;
  /// Built once in start(): a GoughPlatform from robot_ (type gough), or the registered type's model.
  std::shared_ptr<const model::RobotModel> model_;
  std::string robot_type_ = "gough";  ///< ~robot_type (default: the parameters' `type`, else gough)
  std::string robot_summary_;         ///< one line: the loaded robot
  std::vector<double> sensor_error_;  ///< per joint, in the joints' units
  UrdfAnchorNames names_;       ///< links (base_link = base frame, platform_link = platform frame) and anchor names
  std::string frame_prefix_;    ///< ~frame_prefix: prepended to every tf frame name the node uses
  std::string base_frame_;      ///< frame_prefix_ + names_.base_link: the tf name of the base frame
  std::string platform_frame_;  ///< frame_prefix_ + names_.platform_link
  std::string source_;          ///< "yaml" | "urdf"
  std::string robot_file_;      ///< ~robot_file: the file the robot came from (informational; the launch file sets it)
  QueryDefaults defaults_;
  int max_parallel_jobs_ = 1;           ///< ~max_parallel_jobs (service and action jobs together)
  double progress_period_s_ = 0.5;      ///< 1 / ~progress_rate; 0 = no ~progress
  double tf_timeout_s_ = 1.0;           ///< ~tf_timeout
  double client_check_period_s_ = 0.5;  ///< ~client_check_period; 0 = clients are not watched
  int max_box_markers_ = 500;           ///< ~max_box_markers
  int max_safe_box_markers_ = 2000;     ///< ~max_safe_box_markers

  ros::ServiceServer describe_srv_;
  ros::ServiceServer cancel_srv_;
  ros::ServiceServer verify_workspace_srv_;
  ros::ServiceServer verify_trajectory_srv_;
  ros::ServiceServer verify_variety_srv_;
  ros::Publisher verdict_pub_;   ///< ~verdict (latched)
  ros::Publisher progress_pub_;  ///< ~progress
  ros::Publisher boxes_pub_;     ///< ~boxes (latched)
  // Verification requests may run for a long time: they get their own queue, served by max_parallel_jobs_ + 1
  // threads, so ~describe and ~cancel (global queue) stay responsive, at most max_parallel_jobs_ jobs run at once,
  // and one thread is always free to answer "busy" to a request beyond that. The action server's callbacks (goal,
  // cancel) are served from the same queue and return at once: each accepted goal runs in its own thread.
  ros::CallbackQueue verify_queue_;
  std::unique_ptr<ros::AsyncSpinner> verify_spinner_;
  std::unique_ptr<WorkspaceActionServer> workspace_action_server_;
  std::unique_ptr<TrajectoryActionServer> trajectory_action_server_;
  std::unique_ptr<VarietyActionServer> variety_action_server_;
  std::mutex threads_mutex_;
  std::vector<ActionThread> action_threads_;
  std::mutex jobs_mutex_;
  std::condition_variable jobs_changed_;                ///< notified when a job ends and on shutdown
  std::map<std::uint64_t, std::shared_ptr<Job>> jobs_;  ///< running jobs by id
  std::uint64_t last_job_id_ = 0;
  bool shutting_down_ = false;
  /// A job ended since the last trim: once no job runs, the idle timer gives the heap's free memory back to the
  /// system (malloc_trim), so that the node returns to its baseline after a large job.
  bool trim_pending_ = false;
  ros::WallTimer idle_trim_timer_;
  void trimWhenIdle();
  std::thread client_watch_;
  // For /diagnostics (under jobs_mutex_).
  std::uint64_t busy_answers_ = 0;   ///< requests and goals refused because every slot was taken
  std::uint64_t busy_reported_ = 0;  ///< busy_answers_ at the last diagnostics update
  std::uint64_t jobs_finished_ = 0;
  std::uint64_t jobs_client_gone_ = 0;  ///< jobs stopped because their client was gone
  std::uint64_t goals_preempted_ = 0;   ///< goals preempted by a newer goal of the same client
  std::string last_verdict_;            ///< "" before the first job ends
  ros::WallTime last_verdict_time_;
  std::unique_ptr<diagnostic_updater::Updater> diagnostics_;
  ros::WallTimer diagnostics_timer_;
  std::unique_ptr<tf2_ros::StaticTransformBroadcaster> tf_broadcaster_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
};

}  // namespace ros_layer
}  // namespace pkm_accuracy
