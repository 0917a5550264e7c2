// The accuracy_checker node: loads a Gough platform (parameters or URDF), describes it (~describe), publishes its
// anchors as static TF frames and answers /verify_workspace with the core verifier, publishing ~progress while a job
// runs and its result on ~verdict (latched) when it ends. The ROS layer only translates: every decision about
// accuracy is the core's, behind the seam verifyWorkspace().
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <ros/spinner.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include "pkm_accuracy/Cancel.h"
#include "pkm_accuracy/Describe.h"
#include "pkm_accuracy/VerifyWorkspace.h"
#include "pkm_accuracy/core/model/GoughGeometry.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/ros/CoreBridge.hpp"
#include "pkm_accuracy/ros/RobotLoader.hpp"
#include "pkm_accuracy/ros/WorkspaceQuery.hpp"

namespace pkm_accuracy {
namespace ros_layer {

/// Global names of the verification services (they do not move with the node's name or namespace).
constexpr const char* kVerifyWorkspaceService = "/verify_workspace";
constexpr const char* kVerifyTrajectoryService = "/verify_trajectory";  // reserved, not advertised yet

class AccuracyCheckerNode {
 public:
  /// @param nh  public node handle (services with global names)
  /// @param pnh private node handle ("~"): robot parameters, ~describe
  AccuracyCheckerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);
  ~AccuracyCheckerNode();

  /// Loads the robot (~robot_source = "yaml": loadGoughGeometry() on the private parameters; "urdf": the URDF in
  /// robot_description (searched from the private namespace up) + ~sensor_error), builds its model (once: every
  /// request uses it), then advertises the services and topics and publishes the anchor frames. Returns false, with
  /// `error` saying why, only if no robot could be loaded; then nothing is advertised.
  bool start(std::string& error);

  const model::GoughGeometry& robot() const { return robot_; }
  const UrdfAnchorNames& names() const { return names_; }
  const std::string& robotSource() const { return source_; }

  /// THE SEAM between the ROS layer and the core: verifies an already validated query on `model` (the node passes
  /// the model it built once in start()) with the core verifier (CoreBridge.hpp: WorkspaceQuery -> the core's
  /// workspace / options, verify::Verifier::run, the core's result -> WorkspaceOutcome). Translates, decides nothing.
  /// @throws InvalidArgument (naming the field) if the core refuses the query, or whatever else the core throws:
  ///         the service handler turns any exception into success=false.
  WorkspaceOutcome verifyWorkspace(const model::RobotModel& model, const WorkspaceQuery& query,
                                   const JobHooks& hooks) const;

 private:
  /// A running /verify_workspace job.
  struct Job {
    std::uint64_t id = 0;
    std::atomic<bool> cancel{false};
    ros::WallTime started;
  };

  bool loadRobot(std::string& error);
  bool onDescribe(Describe::Request& req, Describe::Response& res);
  bool onVerifyWorkspace(VerifyWorkspace::Request& req, VerifyWorkspace::Response& res);
  bool onCancel(Cancel::Request& req, Cancel::Response& res);
  /// Registers a new job, or returns null and explains in `refusal` (busy / shutting down).
  std::shared_ptr<Job> admit(WorkspaceOutcome& refusal);
  void finish(const std::shared_ptr<Job>& job);
  void publishAnchorFrames();
  void readDefaults();

  ros::NodeHandle nh_;
  ros::NodeHandle pnh_;
  model::GoughGeometry robot_;
  std::unique_ptr<const model::GoughPlatform> model_;  ///< built once from robot_ in start()
  UrdfAnchorNames names_;  ///< frames (base_link = base frame, platform_link = platform frame) and anchor names
  std::string source_;     ///< "yaml" | "urdf"
  QueryDefaults defaults_;
  int max_parallel_jobs_ = 1;       ///< ~max_parallel_jobs
  double progress_period_s_ = 0.5;  ///< 1 / ~progress_rate; 0 = no ~progress

  ros::ServiceServer describe_srv_;
  ros::ServiceServer cancel_srv_;
  ros::ServiceServer verify_workspace_srv_;
  ros::Publisher verdict_pub_;   ///< ~verdict (latched)
  ros::Publisher progress_pub_;  ///< ~progress
  // Verification requests may run for minutes: they get their own queue, served by max_parallel_jobs_ + 1 threads,
  // so ~describe and ~cancel (global queue) stay responsive, at most max_parallel_jobs_ jobs run at once, and one
  // thread is always free to answer "busy" to a request beyond that.
  ros::CallbackQueue verify_queue_;
  std::unique_ptr<ros::AsyncSpinner> verify_spinner_;
  std::mutex jobs_mutex_;
  std::map<std::uint64_t, std::shared_ptr<Job>> jobs_;  ///< running jobs by id
  std::uint64_t last_job_id_ = 0;
  bool shutting_down_ = false;
  std::unique_ptr<tf2_ros::StaticTransformBroadcaster> tf_broadcaster_;
};

}  // namespace ros_layer
}  // namespace pkm_accuracy
