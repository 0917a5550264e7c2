// The accuracy_checker node: loads a Gough platform (parameters or URDF), describes it (~describe), publishes its
// anchors as static TF frames and answers /verify_workspace. The ROS layer only translates: every decision about
// accuracy is the core's, behind the seam verifyWorkspace().
#pragma once

#include <memory>
#include <string>

#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <ros/spinner.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include "pkm_accuracy/Describe.h"
#include "pkm_accuracy/VerifyWorkspace.h"
#include "pkm_accuracy/core/model/GoughGeometry.hpp"
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
  /// robot_description (searched from the private namespace up) + ~sensor_error), then advertises the services and
  /// publishes the anchor frames. Returns false, with `error` saying why, only if no robot could be loaded; then
  /// nothing is advertised.
  bool start(std::string& error);

  const model::GoughGeometry& robot() const { return robot_; }
  const UrdfAnchorNames& names() const { return names_; }
  const std::string& robotSource() const { return source_; }

  /// THE SEAM between the ROS layer and the core: verifies an already validated query on `robot`. This is where the
  /// core verifier is called (converting WorkspaceQuery to the core's workspace / thresholds / options structs and
  /// the core's result back to a WorkspaceOutcome). May throw: the service handler turns any exception into
  /// success=false. Until the core exists it answers success=false, "verifier not available yet".
  WorkspaceOutcome verifyWorkspace(const model::GoughGeometry& robot, const WorkspaceQuery& query) const;

 private:
  bool loadRobot(std::string& error);
  bool onDescribe(Describe::Request& req, Describe::Response& res);
  bool onVerifyWorkspace(VerifyWorkspace::Request& req, VerifyWorkspace::Response& res);
  void publishAnchorFrames();
  void readDefaults();

  ros::NodeHandle nh_;
  ros::NodeHandle pnh_;
  model::GoughGeometry robot_;
  UrdfAnchorNames names_;  ///< frames (base_link = base frame, platform_link = platform frame) and anchor names
  std::string source_;     ///< "yaml" | "urdf"
  QueryDefaults defaults_;

  ros::ServiceServer describe_srv_;
  ros::ServiceServer verify_workspace_srv_;
  // Verification requests may run for minutes: they get their own queue and thread, so ~describe stays responsive
  // and verifications run one at a time (each may use every core).
  ros::CallbackQueue verify_queue_;
  std::unique_ptr<ros::AsyncSpinner> verify_spinner_;
  std::unique_ptr<tf2_ros::StaticTransformBroadcaster> tf_broadcaster_;
};

}  // namespace ros_layer
}  // namespace pkm_accuracy
