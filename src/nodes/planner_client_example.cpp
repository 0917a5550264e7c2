// planner_client_example: how a motion planner uses the accuracy_checker node. Before "executing" a motion, it asks
// the node to certify that the worst-case pose error stays within the task's tolerances, waits for the verdict, and
// executes only when it is SAFE. UNSAFE (a pose provably violating a tolerance), UNDECIDED (e.g. the time budget ran
// out) and failures all mean "do not execute".
//
// ~mode "workspace" (default): the motion is described by the workspace its poses sweep, checked through the action
// ~verify_workspace (default; feedback while it runs, cancellable, here cancelled if no verdict arrives in time) or
// the service /verify_workspace (~use_action: false).
// ~mode "trajectory": the motion is the planned trajectory itself, timed waypoints checked through the service
// /verify_trajectory (every pose between the waypoints is verified, not only the waypoints).
// A "busy" answer (the node runs ~max_parallel_jobs jobs already) is retried until ~timeout.
//
// Parameters (private):
//   ~mode (string, "workspace" | "trajectory")    ~tolerances ([dx, dy, dz (m), drx, dry, drz (rad)]; default 1e-3 m,
//   1e-2 rad)    ~time_budget (s, 10)    ~timeout (s, 60: for the node to appear and answer)
//   ~frame_id (string, "": the robot's base frame): the frame of the workspace or of the waypoints (any tf2 frame)
//   workspace mode:
//     ~use_action (bool, true)    ~action (string, /pkm_accuracy/verify_workspace)    ~service (/verify_workspace)
//     ~box_min, ~box_max ([x, y, z], m; default a 2 cm box around [0, 0, 0.475])
//     ~angle_min, ~angle_max ([roll, pitch, yaw], rad; default +-0.01)
//   trajectory mode:
//     ~trajectory_service (string, /verify_trajectory)
//     ~waypoints (flat list, 7 numbers per waypoint: t (s), x, y, z (m, ~frame_id), roll, pitch, yaw (rad),
//       R = Rz(yaw) Ry(pitch) Rx(roll); default 3 waypoints over 3 s inside a 2 cm box around [0, 0, 0.475])
//     ~interpolation (string, "slerp" | "linear_rpy"; default slerp)
//   ~exit_when_done (bool, true): exit after the decision (status 0: executed, 1: not executed, 2: no answer or an
//     invalid parameter: a malformed list is an error, never replaced by the default);
//     false: keep running (the latched ~decision stays available)
// Topic: ~decision (std_msgs/String, latched): "executing" or "not executing: <why>".
//
//   rosparam set /planner_client_example/tolerances "[1.0e-4, 1.0e-4, 1.0e-4, 1.0e-3, 1.0e-3, 1.0e-3]"
//   rosrun pkm_accuracy planner_client_example        (lists cannot be given as _name:=value to a roscpp node)
//   rosrun pkm_accuracy planner_client_example _mode:=trajectory
#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include <actionlib/client/simple_action_client.h>
#include <ros/ros.h>
#include <std_msgs/String.h>

#include "pkm_accuracy/VerifyTrajectory.h"
#include "pkm_accuracy/VerifyWorkspace.h"
#include "pkm_accuracy/VerifyWorkspaceAction.h"
#include "pkm_accuracy/ros/RobotLoader.hpp"

namespace {

using pkm_accuracy::VerifyTrajectory;
using pkm_accuracy::VerifyWorkspace;
using pkm_accuracy::VerifyWorkspaceAction;
using pkm_accuracy::VerifyWorkspaceGoal;
using pkm_accuracy::VerifyWorkspaceResult;

/// What the planner needs from an answer (service response or action result: the same fields).
struct Verdict {
  bool answered = false;  ///< false: no answer at all (node missing, timeout)
  bool success = false;
  bool busy = false;
  std::string verdict, reason, message;
  bool has_witness = false;
  std::vector<double> witness_pose;
  int witness_component = -1;
  bool has_witness_t = false;  ///< trajectory mode: witness_t is set
  double witness_t = 0.0;      ///< s
};

template <class Answer>
Verdict fromAnswer(const Answer& a) {
  Verdict v;
  v.answered = true;
  v.success = a.success;
  v.busy = a.busy;
  v.verdict = a.verdict;
  v.reason = a.reason;
  v.message = a.message;
  v.has_witness = a.has_witness;
  v.witness_pose.assign(a.witness_pose.begin(), a.witness_pose.end());
  v.witness_component = a.witness_component;
  return v;
}

/// A list parameter of numbers (numeric strings such as "1e-6" included, as the node reads them:
/// pkm_accuracy::ros_layer::parameterNumber), or `fallback` if it is not set. `size` 0: any length. A malformed one is
/// an error: a planner must not fall back to other tolerances than those it was given.
std::vector<double> numberList(ros::NodeHandle& pnh, const std::string& key, const std::vector<double>& fallback,
                               std::size_t size, const std::string& expected) {
  if (!pnh.hasParam(key)) return fallback;
  XmlRpc::XmlRpcValue list;
  std::vector<double> v;
  bool ok = pnh.getParam(key, list) && list.getType() == XmlRpc::XmlRpcValue::TypeArray &&
            (size == 0 || static_cast<std::size_t>(list.size()) == size);
  for (int i = 0; ok && i < list.size(); ++i) {
    double x = 0.0;
    ok = pkm_accuracy::ros_layer::parameterNumber(list[i], x);
    v.push_back(x);
  }
  if (!ok) throw std::invalid_argument(pnh.resolveName(key) + ": expected " + expected);
  return v;
}

std::vector<double> param(ros::NodeHandle& pnh, const std::string& key, const std::vector<double>& fallback,
                          std::size_t size) {
  return numberList(pnh, key, fallback, size, "a list of " + std::to_string(size) + " numbers");
}

/// ~waypoints: a flat list of 7 numbers per waypoint (t, x, y, z, roll, pitch, yaw), at least two waypoints.
std::vector<double> waypointsParam(ros::NodeHandle& pnh) {
  const std::vector<double> fallback = {0.0, -0.01, 0.01,   0.47,  0.0,   -0.01, 0.005,  //
                                        1.0, 0.0,   -0.005, 0.475, 0.01,  0.0,   -0.01,  //
                                        3.0, 0.01,  -0.01,  0.48,  -0.01, 0.01,  0.0};
  const std::string expected =
      "a flat list of 7 numbers per waypoint (t, x, y, z, roll, pitch, yaw), at least two waypoints";
  const std::vector<double> v = numberList(pnh, "waypoints", fallback, 0, expected);
  if (v.size() < 14 || v.size() % 7 != 0)
    throw std::invalid_argument(pnh.resolveName("waypoints") + ": expected " + expected);
  return v;
}

/// The workspace the planned motion sweeps, and the task's tolerances (the goal and the request have the same
/// fields). @throws std::invalid_argument on a malformed parameter.
template <class Request>
void fill(ros::NodeHandle& pnh, Request& r) {
  const std::vector<double> box_min = param(pnh, "box_min", {-0.01, -0.01, 0.47}, 3);
  const std::vector<double> box_max = param(pnh, "box_max", {0.01, 0.01, 0.48}, 3);
  const std::vector<double> angle_min = param(pnh, "angle_min", {-0.01, -0.01, -0.01}, 3);
  const std::vector<double> angle_max = param(pnh, "angle_max", {0.01, 0.01, 0.01}, 3);
  const std::vector<double> tolerances = param(pnh, "tolerances", {1e-3, 1e-3, 1e-3, 1e-2, 1e-2, 1e-2}, 6);
  r.region_type = VerifyWorkspace::Request::REGION_BOX;
  for (std::size_t k = 0; k < 3; ++k) {
    r.box_min[k] = box_min[k];
    r.box_max[k] = box_max[k];
  }
  r.roll_min = angle_min[0];
  r.pitch_min = angle_min[1];
  r.yaw_min = angle_min[2];
  r.roll_max = angle_max[0];
  r.pitch_max = angle_max[1];
  r.yaw_max = angle_max[2];
  for (std::size_t k = 0; k < 6; ++k) r.thresholds[k] = tolerances[k];
  r.mode = VerifyWorkspace::Request::MODE_VERIFY;
  r.time_budget = pnh.param("time_budget", 10.0);
  r.frame_id = pnh.param<std::string>("frame_id", "");
}

/// The planned trajectory and the task's tolerances. @throws std::invalid_argument on a malformed parameter.
void fillTrajectory(ros::NodeHandle& pnh, VerifyTrajectory::Request& r) {
  const std::vector<double> w = waypointsParam(pnh);
  const std::vector<double> tolerances = param(pnh, "tolerances", {1e-3, 1e-3, 1e-3, 1e-2, 1e-2, 1e-2}, 6);
  std::vector<double>* columns[7] = {&r.times, &r.x, &r.y, &r.z, &r.roll, &r.pitch, &r.yaw};
  for (std::size_t i = 0; i < w.size(); ++i) columns[i % 7]->push_back(w[i]);
  r.interpolation = pnh.param<std::string>("interpolation", VerifyTrajectory::Request::INTERPOLATION_SLERP);
  for (std::size_t k = 0; k < 6; ++k) r.thresholds[k] = tolerances[k];
  r.mode = VerifyTrajectory::Request::MODE_VERIFY;
  r.time_budget = pnh.param("time_budget", 10.0);
  r.frame_id = pnh.param<std::string>("frame_id", "");
}

Verdict askForTrajectory(ros::NodeHandle& pnh, const ros::WallTime& deadline) {
  const std::string name = pnh.param<std::string>("trajectory_service", "/verify_trajectory");
  VerifyTrajectory srv;
  fillTrajectory(pnh, srv.request);
  if (!ros::service::waitForService(name, ros::Duration(std::max(0.0, (deadline - ros::WallTime::now()).toSec())))) {
    ROS_ERROR("no service %s", name.c_str());
    return Verdict();
  }
  while (ros::ok()) {
    ROS_INFO("asking %s to verify the trajectory (%zu waypoints)", name.c_str(), srv.request.times.size());
    if (!ros::service::call(name, srv)) {
      ROS_ERROR("calling %s failed", name.c_str());
      return Verdict();
    }
    Verdict v = fromAnswer(srv.response);
    v.has_witness_t = srv.response.has_witness;
    v.witness_t = srv.response.witness_t;
    if (!v.busy || ros::WallTime::now() > deadline) return v;
    ROS_INFO("the node is busy (%s); retrying", v.message.c_str());
    ros::WallDuration(0.2).sleep();
  }
  return Verdict();
}

Verdict askByAction(ros::NodeHandle& pnh, const ros::WallTime& deadline) {
  const std::string name = pnh.param<std::string>("action", "/pkm_accuracy/verify_workspace");
  VerifyWorkspaceGoal goal;
  fill(pnh, goal);
  actionlib::SimpleActionClient<VerifyWorkspaceAction> client(name, /*spin_thread=*/true);
  if (!client.waitForServer(ros::Duration(std::max(0.0, (deadline - ros::WallTime::now()).toSec())))) {
    ROS_ERROR("no action server %s", name.c_str());
    return Verdict();
  }
  while (ros::ok()) {
    ROS_INFO("asking %s to verify the workspace", name.c_str());
    client.sendGoal(goal, actionlib::SimpleActionClient<VerifyWorkspaceAction>::SimpleDoneCallback(),
                    actionlib::SimpleActionClient<VerifyWorkspaceAction>::SimpleActiveCallback(),
                    [](const pkm_accuracy::VerifyWorkspaceFeedbackConstPtr& f) {
                      ROS_INFO_THROTTLE(1.0, "job %lu: %lu boxes, %.0f %% proven safe after %.1f s",
                                        static_cast<unsigned long>(f->job_id), static_cast<unsigned long>(f->boxes),
                                        100.0 * f->safe_fraction, f->seconds);
                    });
    const double left = (deadline - ros::WallTime::now()).toSec();
    if (!client.waitForResult(ros::Duration(std::max(0.01, left)))) {
      ROS_ERROR("no verdict within ~timeout: cancelling the goal");
      client.cancelGoal();
      client.waitForResult(ros::Duration(5.0));
      return Verdict();
    }
    const Verdict v = fromAnswer(*client.getResult());
    if (!v.busy || ros::WallTime::now() > deadline) return v;
    ROS_INFO("the node is busy (%s); retrying", v.message.c_str());
    ros::WallDuration(0.2).sleep();
  }
  return Verdict();
}

Verdict askByService(ros::NodeHandle& pnh, const ros::WallTime& deadline) {
  const std::string name = pnh.param<std::string>("service", "/verify_workspace");
  VerifyWorkspace srv;
  fill(pnh, srv.request);
  if (!ros::service::waitForService(name, ros::Duration(std::max(0.0, (deadline - ros::WallTime::now()).toSec())))) {
    ROS_ERROR("no service %s", name.c_str());
    return Verdict();
  }
  while (ros::ok()) {
    ROS_INFO("asking %s to verify the workspace", name.c_str());
    if (!ros::service::call(name, srv)) {
      ROS_ERROR("calling %s failed", name.c_str());
      return Verdict();
    }
    const Verdict v = fromAnswer(srv.response);
    if (!v.busy || ros::WallTime::now() > deadline) return v;
    ROS_INFO("the node is busy (%s); retrying", v.message.c_str());
    ros::WallDuration(0.2).sleep();
  }
  return Verdict();
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "planner_client_example");
  ros::NodeHandle pnh("~");
  ros::Publisher decision = pnh.advertise<std_msgs::String>("decision", 1, /*latch=*/true);
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(pnh.param("timeout", 60.0));

  std_msgs::String msg;
  int status = 1;
  Verdict v;
  try {
    const std::string mode = pnh.param<std::string>("mode", "workspace");
    if (mode == "trajectory") {
      v = askForTrajectory(pnh, deadline);
    } else if (mode == "workspace") {
      v = pnh.param("use_action", true) ? askByAction(pnh, deadline) : askByService(pnh, deadline);
    } else {
      throw std::invalid_argument(pnh.resolveName("mode") + ": expected \"workspace\" or \"trajectory\", got \"" +
                                  mode + "\"");
    }
  } catch (const std::invalid_argument& e) {
    ROS_ERROR("%s", e.what());
    msg.data = std::string("not executing: invalid parameter: ") + e.what();
    status = 2;
  }
  if (status == 2) {
    // (invalid parameter, already said)
  } else if (!v.answered) {
    msg.data = "not executing: no verdict";
    status = 2;
  } else if (!v.success) {
    msg.data = "not executing: the check failed: " + v.message;
  } else if (v.verdict == VerifyWorkspace::Response::VERDICT_SAFE) {
    msg.data = "executing";
    status = 0;
  } else if (v.verdict == VerifyWorkspace::Response::VERDICT_UNSAFE && v.has_witness && v.witness_pose.size() == 6) {
    const char* names[6] = {"dx", "dy", "dz", "drx", "dry", "drz"};
    char when[64] = "";
    if (v.has_witness_t) std::snprintf(when, sizeof(when), "t=%.4f s, ", v.witness_t);
    char why[320];
    std::snprintf(why, sizeof(why),
                  "not executing: UNSAFE, the %s tolerance is exceeded at %sx=%.4f y=%.4f z=%.4f roll=%.4f "
                  "pitch=%.4f yaw=%.4f",
                  v.witness_component >= 0 && v.witness_component < 6 ? names[v.witness_component] : "?", when,
                  v.witness_pose[0], v.witness_pose[1], v.witness_pose[2], v.witness_pose[3], v.witness_pose[4],
                  v.witness_pose[5]);
    msg.data = why;
  } else {
    msg.data = "not executing: " + v.verdict + (v.reason.empty() ? "" : " (" + v.reason + ")") + ": " + v.message;
  }
  if (status == 0) {
    ROS_INFO("verdict SAFE: %s; executing", v.message.c_str());
  } else {
    ROS_WARN("%s", msg.data.c_str());
  }
  decision.publish(msg);

  if (!pnh.param("exit_when_done", true)) {
    ros::spin();
  } else {
    ros::WallDuration(0.5).sleep();  // let the latched ~decision reach subscribers that are already connected
  }
  return status;
}
