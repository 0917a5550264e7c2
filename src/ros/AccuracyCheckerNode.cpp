#include "pkm_accuracy/ros/AccuracyCheckerNode.hpp"

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <iomanip>
#include <sstream>
#include <vector>

#include <actionlib_msgs/GoalStatus.h>
#include <geometry_msgs/TransformStamped.h>
#include <tf2/exceptions.h>
#include <urdf/model.h>
#include <visualization_msgs/MarkerArray.h>
#include <Eigen/Geometry>

#include "pkm_accuracy/Progress.h"
#include "pkm_accuracy/VerificationResult.h"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/Version.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/model/ModelRegistry.hpp"
#include "pkm_accuracy/io/ModelPlugin.hpp"
#include "pkm_accuracy/ros/BoxMarkers.hpp"
#include "pkm_accuracy/ros/ClientLiveness.hpp"
#include "pkm_accuracy/ros/VerifyTrajectoryConversion.hpp"
#include "pkm_accuracy/ros/VerifyVarietyConversion.hpp"
#include "pkm_accuracy/ros/VerifyWorkspaceConversion.hpp"

namespace pkm_accuracy {
namespace ros_layer {
namespace {

geometry_msgs::Point toPoint(const Eigen::Vector3d& v) {
  geometry_msgs::Point p;
  p.x = v.x();
  p.y = v.y();
  p.z = v.z();
  return p;
}

geometry_msgs::Vector3 toVector3(const Eigen::Vector3d& v) {
  geometry_msgs::Vector3 p;
  p.x = v.x();
  p.y = v.y();
  p.z = v.z();
  return p;
}

const char* modeName(QueryMode m) {
  return m == QueryMode::MaxError ? VerifyWorkspace::Request::MODE_MAX_ERROR.c_str()
                                  : VerifyWorkspace::Request::MODE_VERIFY.c_str();
}

std::string seconds(double s) {
  std::ostringstream os;
  os << s;
  return os.str();
}

// The feedback of both actions has the fields of ~progress (without its header).
template <class Feedback>
void toFeedback(const Progress& p, Feedback& f) {
  f.job_id = p.job_id;
  f.mode = p.mode;
  f.boxes = p.boxes;
  f.max_depth = p.max_depth;
  f.threads = p.threads;
  f.seconds = p.seconds;
  f.time_budget = p.time_budget;
  f.safe_fraction = p.safe_fraction;
  f.unsafe_fraction = p.unsafe_fraction;
  f.undecided_fraction = p.undecided_fraction;
  f.outside_fraction = p.outside_fraction;
  f.lower = p.lower;
  f.upper = p.upper;
}

void fillProgressStats(const verify::Statistics& s, Progress& msg) {
  msg.boxes = s.boxes;
  msg.max_depth = static_cast<std::uint32_t>(std::max(0, s.max_depth));
  msg.threads = static_cast<std::uint32_t>(std::max(0, s.threads));
  msg.seconds = s.seconds;
  msg.safe_fraction = s.safe_fraction;
  msg.unsafe_fraction = s.unsafe_fraction;
  msg.undecided_fraction = s.undecided_fraction;
  msg.outside_fraction = s.outside_fraction;
}

std::string vec3(const Eigen::Vector3d& v) {
  std::ostringstream os;
  os.precision(6);
  os << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return os.str();
}

/// "[a, b, ...]", or "a (all N)" when every entry is the same.
std::string list(const std::vector<double>& v) {
  std::ostringstream os;
  os.precision(6);
  if (!v.empty() && std::all_of(v.begin(), v.end(), [&](double x) { return x == v.front(); })) {
    os << v.front() << " (all " << v.size() << ")";
    return os.str();
  }
  os << "[";
  for (std::size_t i = 0; i < v.size(); ++i) os << (i ? ", " : "") << v[i];
  os << "]";
  return os.str();
}

/// Anchor half-widths: "none", "h on every coordinate", or one triple per anchor.
std::string halfwidths(const std::vector<Eigen::Vector3d>& h) {
  if (h.empty() || std::all_of(h.begin(), h.end(), [](const Eigen::Vector3d& v) { return v.isZero(); })) {
    return "none";
  }
  const double first = h.front().x();
  if (std::all_of(h.begin(), h.end(), [&](const Eigen::Vector3d& v) { return (v.array() == first).all(); })) {
    std::ostringstream os;
    os.precision(6);
    os << "+-" << first << " m on every coordinate";
    return os.str();
  }
  std::string out;
  for (const auto& v : h) out += (out.empty() ? "+-" : ", +-") + vec3(v);
  return out + " m";
}

}  // namespace

std::string AccuracyCheckerNode::stopCauseText(StopCause cause) {
  switch (cause) {
    case StopCause::ClientCancel:
      return "cancelled by the client";
    case StopCause::Preempted:
      return "preempted by a newer goal of the same client";
    case StopCause::ClientGone:
      return "its client is gone";
    case StopCause::CancelService:
      return "stopped by ~cancel or the node's shutdown";
    case StopCause::None:
      break;
  }
  return "";
}

AccuracyCheckerNode::AccuracyCheckerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh) : nh_(nh), pnh_(pnh) {}

AccuracyCheckerNode::~AccuracyCheckerNode() {
  {
    // Running jobs stop promptly (they answer UNDECIDED, reason "cancelled"); no new job starts.
    std::lock_guard<std::mutex> lock(jobs_mutex_);
    shutting_down_ = true;
    for (auto& j : jobs_) j.second->stop(StopCause::CancelService);
  }
  jobs_changed_.notify_all();
  if (client_watch_.joinable()) client_watch_.join();
  diagnostics_timer_.stop();
  // Service jobs and goal callbacks return (no new goal thread can start after this), then the goals' threads end
  // (cancelled jobs; at most ~tf_timeout in a tf2 lookup) before the action server goes.
  if (verify_spinner_) verify_spinner_->stop();
  reapActionThreads(true);
  workspace_action_server_.reset();
  trajectory_action_server_.reset();
  variety_action_server_.reset();
  verify_workspace_srv_.shutdown();
  verify_trajectory_srv_.shutdown();
  verify_variety_srv_.shutdown();
  cancel_srv_.shutdown();
  describe_srv_.shutdown();
}

bool AccuracyCheckerNode::loadRobot(std::string& error) {
  source_ = pnh_.param<std::string>("robot_source", "yaml");
  if (!loadUrdfAnchorNames(pnh_, names_, error)) return false;
  if (source_ == "yaml") {
    return loadGoughGeometry(pnh_, robot_, error);
  }
  if (source_ != "urdf") {
    error = pnh_.resolveName("robot_source") + ": expected \"yaml\" or \"urdf\", got \"" + source_ + "\"";
    return false;
  }
  std::string key;
  std::string xml;
  if (!pnh_.searchParam("robot_description", key) || !pnh_.getParam(key, xml)) {
    error = "robot_description: expected a URDF string (searched from " + pnh_.getNamespace() + " up) because " +
            pnh_.resolveName("robot_source") + " is \"urdf\", got nothing (parameter not set)";
    return false;
  }
  urdf::Model urdf;
  if (!urdf.initString(xml)) {
    error = key + ": expected a valid URDF, got a string that urdf::Model cannot parse (see the messages above)";
    return false;
  }
  model::GoughGeometry g;
  if (!loadGoughGeometryFromUrdf(urdf, names_, g, error)) {
    // Name the parameters that chose the links, not only the URDF they were looked for in.
    std::string params;
    if (error.find("base link") != std::string::npos) {
      params = pnh_.resolveName("base_frame") + " = \"" + names_.base_link + "\"";
    } else if (error.find("platform link") != std::string::npos) {
      params = pnh_.resolveName("platform_frame") + " = \"" + names_.platform_link + "\"";
    } else if (error.find("base anchor") != std::string::npos || error.find("platform anchor") != std::string::npos) {
      const bool base = error.find("base anchor") != std::string::npos;
      params = pnh_.resolveName(base ? "base_anchor_pattern" : "platform_anchor_pattern") + " = \"" +
               (base ? names_.base_anchor_pattern : names_.platform_anchor_pattern) + "\", " +
               pnh_.resolveName("anchor_first_index") + " = " + std::to_string(names_.first_index) + ", " +
               pnh_.resolveName(base ? "base_frame" : "platform_frame") + " = \"" +
               (base ? names_.base_link : names_.platform_link) + "\"";
    }
    error = (params.empty() ? "" : params + ": ") + error + " (URDF from " + key + ")";
    return false;
  }
  if (!loadSensorParameters(pnh_, g, error)) return false;
  robot_ = g;
  return true;
}

void AccuracyCheckerNode::readDefaults() {
  const QueryDefaults builtin;
  // zero_ok: 0 is allowed (otherwise the value must be > 0).
  auto read = [&](const char* key, double fallback, bool zero_ok) {
    double v = fallback;
    std::string error;
    if (!readOptionalNumber(pnh_, key, v, error)) {
      ROS_WARN("%s; using %g", error.c_str(), fallback);
      return fallback;
    }
    if (!std::isfinite(v) || v < 0.0 || (v == 0.0 && !zero_ok)) {
      ROS_WARN("%s: expected a finite number %s, got %g; using %g", pnh_.resolveName(key).c_str(),
               zero_ok ? ">= 0" : "> 0", v, fallback);
      v = fallback;
    }
    return v;
  };
  auto readInt = [&](const char* key, int fallback, int lo, int hi) {
    int v = fallback;
    std::string error;
    if (!readOptionalInteger(pnh_, key, v, error)) {
      ROS_WARN("%s; using %d", error.c_str(), fallback);
      return fallback;
    }
    if (v < lo || v > hi) {
      ROS_WARN("%s: expected an integer from %d to %d, got %d; using %d", pnh_.resolveName(key).c_str(), lo, hi, v,
               fallback);
      v = fallback;
    }
    return v;
  };
  defaults_.alpha = read("default_alpha", builtin.alpha, false);
  defaults_.time_budget = read("default_time_budget", builtin.time_budget, false);
  defaults_.min_width = read("default_min_width", builtin.min_width, true);
  const double rate = read("progress_rate", 2.0, true);
  progress_period_s_ = rate > 0.0 ? 1.0 / rate : 0.0;

  defaults_.method = pnh_.param<std::string>("default_method", builtin.method);
  const std::vector<std::string> methods = enclosure::enclosureNames();
  if (!defaults_.method.empty() && std::find(methods.begin(), methods.end(), defaults_.method) == methods.end()) {
    std::string names;
    for (const auto& m : methods) names += (names.empty() ? "" : ", ") + m;
    ROS_WARN("%s: expected one of %s or \"\", got \"%s\"; using the verifier's default",
             pnh_.resolveName("default_method").c_str(), names.c_str(), defaults_.method.c_str());
    defaults_.method = builtin.method;
  }

  tf_timeout_s_ = read("tf_timeout", 1.0, true);
  client_check_period_s_ = read("client_check_period", 0.5, true);
  max_box_markers_ = readInt("max_box_markers", 500, 0, 1000000000);
  max_safe_box_markers_ = readInt("max_safe_box_markers", 2000, 0, 1000000000);
  max_parallel_jobs_ = readInt("max_parallel_jobs", 1, 1, 64);
}

bool AccuracyCheckerNode::loadPlugins(std::string& error) {
  std::vector<std::string> plugins;
  if (pnh_.hasParam("plugins") && !pnh_.getParam("plugins", plugins)) {
    error = pnh_.resolveName("plugins") + ": expected a list of shared library paths";
    return false;
  }
  for (const std::string& path : plugins) {
    try {
      io::loadModelPlugin(path, model::ModelRegistry::global());
    } catch (const std::exception& e) {
      error = pnh_.resolveName("plugins") + ": " + e.what();
      return false;
    }
  }
  return true;
}

bool AccuracyCheckerNode::loadOtherRobot(std::string& error) {
  source_ = "yaml";
  if (!loadUrdfAnchorNames(pnh_, names_, error)) return false;  // (the base and platform frame names)
  io::ModelFile file;
  if (!loadModelFromParameters(pnh_, robot_type_, file, error)) return false;
  // A robot whose pose is not the rigid-body pose (x, y, z, roll, pitch, yaw): requests name its own pose
  // coordinates, and its named workspaces are the file reader's boxes of them.
  defaults_.pose = file.description.pose;
  if (!defaults_.rigidBodyPose()) {
    for (const auto& [name, domain] : file.workspaces) defaults_.workspaces[name].domain = domain;
  }
  model_ = file.model;
  sensor_error_ = file.description.sensor_error;
  robot_summary_ = robot_type_ + ": " + model::ModelRegistry::global().find(robot_type_)->summary + ", " +
                   std::to_string(model_->geometryParameterCount()) + " uncertain geometry values";
  return true;
}

std::string AccuracyCheckerNode::robotReport() const {
  std::ostringstream os;
  if (robot_type_ != "gough") {
    os << "type " << robot_summary_ << "; from the parameters in " << pnh_.getNamespace()
       << (robot_file_.empty() ? "" : " (file " + robot_file_ + ")") << "; frames: base " << base_frame_
       << ", platform " << platform_frame_ << "; sensor errors " << list(sensor_error_) << " (joints";
    for (int j = 0; j < model_->dof(); ++j) os << " " << model_->jointName(j);
    os << ")";
    return os.str();
  }
  os << "type gough (6-UPS Gough platform), 6 dof (x, y, z, roll, pitch, yaw), " << robot_.legCount() << " legs; from "
     << (source_ == "yaml" ? "the parameters in " + pnh_.getNamespace() : "the URDF in robot_description")
     << (robot_file_.empty() ? "" : " (file " + robot_file_ + ")") << "; frames: base " << base_frame_ << ", platform "
     << platform_frame_ << "; sensor errors " << list(robot_.sensor_error) << " m; tool point "
     << vec3(robot_.tool_point) << " m";
  if (!robot_.tool_point_halfwidth.isZero()) os << " +-" << vec3(robot_.tool_point_halfwidth) << " m";
  os << "; uncertainty half-widths: base anchors " << halfwidths(robot_.base_anchor_halfwidth) << ", platform anchors "
     << halfwidths(robot_.platform_anchor_halfwidth);
  return os.str();
}

bool AccuracyCheckerNode::start(std::string& error) {
  robot_file_ = pnh_.param<std::string>("robot_file", "");
  frame_prefix_ = pnh_.param<std::string>("frame_prefix", "");
  while (!frame_prefix_.empty() && frame_prefix_.front() == '/') frame_prefix_.erase(0, 1);  // (as tf2 names)
  if (!loadPlugins(error)) return false;
  robot_type_ = pnh_.param<std::string>("robot_type", pnh_.param<std::string>("type", "gough"));
  if (robot_type_ == "gough") {
    if (!loadRobot(error)) return false;
    try {
      model_ = std::make_shared<model::GoughPlatform>(robot_);
    } catch (const std::exception& e) {
      error = std::string("robot: ") + e.what();
      return false;
    }
    sensor_error_ = robot_.sensor_error;
    robot_summary_ = "gough: " + robot_.summary();
  } else if (!loadOtherRobot(error)) {
    return false;
  }
  base_frame_ = frame_prefix_ + names_.base_link;
  platform_frame_ = frame_prefix_ + names_.platform_link;
  readDefaults();
  defaults_.robot_type = robot_type_;
  if (defaults_.rigidBodyPose() && !loadNamedWorkspaces(pnh_, defaults_.workspaces, error)) return false;
  ROS_INFO("Robot: %s", robotReport().c_str());

  tf_buffer_.reset(new tf2_ros::Buffer());
  tf_listener_.reset(new tf2_ros::TransformListener(*tf_buffer_, nh_, /*spin_thread=*/true));
  verdict_pub_ = pnh_.advertise<VerificationResult>("verdict", 1, /*latch=*/true);
  progress_pub_ = pnh_.advertise<Progress>("progress", 10);
  boxes_pub_ = pnh_.advertise<visualization_msgs::MarkerArray>("boxes", 1, /*latch=*/true);
  describe_srv_ = pnh_.advertiseService("describe", &AccuracyCheckerNode::onDescribe, this);
  cancel_srv_ = pnh_.advertiseService("cancel", &AccuracyCheckerNode::onCancel, this);
  idle_trim_timer_ =
      pnh_.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { trimWhenIdle(); });

  // /diagnostics (diagnostic_updater: ~diagnostic_period, default 1 s).
  diagnostics_.reset(new diagnostic_updater::Updater(nh_, pnh_));
  diagnostics_->setHardwareID(robot_type_ + " robot from " + (robot_file_.empty() ? pnh_.getNamespace() : robot_file_));
  diagnostics_->add("verification jobs", this, &AccuracyCheckerNode::diagnose);
  diagnostics_timer_ =
      pnh_.createWallTimer(ros::WallDuration(0.25), [this](const ros::WallTimerEvent&) { diagnostics_->update(); });

  ros::NodeHandle verify_nh(nh_);
  verify_nh.setCallbackQueue(&verify_queue_);
  verify_workspace_srv_ =
      verify_nh.advertiseService(kVerifyWorkspaceService, &AccuracyCheckerNode::onVerifyWorkspace, this);
  verify_trajectory_srv_ =
      verify_nh.advertiseService(kVerifyTrajectoryService, &AccuracyCheckerNode::onVerifyTrajectory, this);
  verify_variety_srv_ = verify_nh.advertiseService(kVerifyVarietyService, &AccuracyCheckerNode::onVerifyVariety, this);
  workspace_action_server_ = startActionServer<VerifyWorkspaceAction>(kVerifyWorkspaceAction);
  trajectory_action_server_ = startActionServer<VerifyTrajectoryAction>(kVerifyTrajectoryAction);
  variety_action_server_ = startActionServer<VerifyVarietyAction>(kVerifyVarietyAction);
  verify_spinner_.reset(new ros::AsyncSpinner(static_cast<std::uint32_t>(max_parallel_jobs_ + 1), &verify_queue_));
  verify_spinner_->start();
  if (client_check_period_s_ > 0.0) client_watch_ = std::thread([this] { watchClients(); });

  if (pnh_.param("publish_anchor_frames", true)) publishAnchorFrames();
  ROS_INFO(
      "Services: %s, %s, %s, %s, %s; actions: %s, %s, %s; topics: %s, %s, %s (at most %d job(s) at once, "
      "default time budget %g s)",
      describe_srv_.getService().c_str(), cancel_srv_.getService().c_str(), verify_workspace_srv_.getService().c_str(),
      verify_trajectory_srv_.getService().c_str(), verify_variety_srv_.getService().c_str(),
      pnh_.resolveName(kVerifyWorkspaceAction).c_str(), pnh_.resolveName(kVerifyTrajectoryAction).c_str(),
      pnh_.resolveName(kVerifyVarietyAction).c_str(), verdict_pub_.getTopic().c_str(), progress_pub_.getTopic().c_str(),
      boxes_pub_.getTopic().c_str(), max_parallel_jobs_, defaults_.time_budget);
  return true;
}

void AccuracyCheckerNode::publishAnchorFrames() {
  std::vector<geometry_msgs::TransformStamped> transforms;
  const ros::Time now = ros::Time::now();
  auto add = [&](const std::string& parent, const std::string& child, const Eigen::Vector3d& p) {
    geometry_msgs::TransformStamped t;
    t.header.stamp = now;
    t.header.frame_id = parent;
    t.child_frame_id = child;
    t.transform.translation.x = p.x();
    t.transform.translation.y = p.y();
    t.transform.translation.z = p.z();
    t.transform.rotation.w = 1.0;
    transforms.push_back(t);
  };
  for (std::size_t i = 0; i < robot_.legCount(); ++i) {
    const int index = names_.first_index + static_cast<int>(i);
    add(base_frame_, frame_prefix_ + formatAnchorName(names_.base_anchor_pattern, index), robot_.base_anchors[i]);
    add(platform_frame_, frame_prefix_ + formatAnchorName(names_.platform_anchor_pattern, index),
        robot_.platform_anchors[i]);
  }
  tf_broadcaster_.reset(new tf2_ros::StaticTransformBroadcaster());
  tf_broadcaster_->sendTransform(transforms);
}

bool AccuracyCheckerNode::onDescribe(Describe::Request& /*req*/, Describe::Response& res) {
  try {
    res = Describe::Response();
    res.version = pkm_accuracy::version();
    res.robot_source = source_;
    res.robot_type = robot_type_;
    if (model_) {
      res.dof = static_cast<std::uint32_t>(model_->dof());
      for (int j = 0; j < model_->dof(); ++j) res.joints.push_back(model_->jointName(j));
    }
    for (const model::PoseComponent& c : defaults_.pose) {
      res.pose_components.push_back(c.name + " [" + c.unit + "]");
      res.error_components.push_back(c.errorName() + " [" + c.unit + "]");
    }
    res.rigid_body_pose = defaults_.rigidBodyPose();
    res.base_frame = base_frame_;
    res.platform_frame = platform_frame_;
    for (const auto& a : robot_.base_anchors) res.base_anchors.push_back(toPoint(a));
    for (const auto& b : robot_.platform_anchors) res.platform_anchors.push_back(toPoint(b));
    res.sensor_error = sensor_error_;
    res.tool_point = toPoint(robot_.tool_point);
    for (const auto& h : robot_.base_anchor_halfwidth) res.base_anchor_halfwidth.push_back(toVector3(h));
    for (const auto& h : robot_.platform_anchor_halfwidth) res.platform_anchor_halfwidth.push_back(toVector3(h));
    res.tool_point_halfwidth = toVector3(robot_.tool_point_halfwidth);
    if (model_) {
      for (int p = 0; p < model_->geometryParameterCount(); ++p) {
        res.geometry_parameters.push_back(model_->geometryParameterName(p));
      }
    }
    for (const auto& w : defaults_.workspaces) res.workspaces.push_back(w.first);  // (a std::map: sorted)
    res.message = robot_summary_;
    res.success = true;
  } catch (const std::exception& e) {
    res = Describe::Response();
    res.message = std::string("describe failed: ") + e.what();
  } catch (...) {
    res = Describe::Response();
    res.message = "describe failed: unknown exception";
  }
  return true;
}

std::shared_ptr<AccuracyCheckerNode::Job> AccuracyCheckerNode::admit(WorkspaceOutcome& refusal,
                                                                     const std::string& client,
                                                                     const std::string& goal_id,
                                                                     const std::string& action) {
  // The caller's address, looked up before taking the lock (a master round trip); not for this node's own calls.
  const std::string uri =
      client_check_period_s_ > 0.0 && client != ros::this_node::getName() ? lookupNodeUri(client) : std::string();
  std::lock_guard<std::mutex> lock(jobs_mutex_);
  if (shutting_down_) {
    refusal.message = "the node is shutting down";
    return nullptr;
  }
  if (static_cast<int>(jobs_.size()) >= max_parallel_jobs_) {
    std::ostringstream os;
    os.precision(3);
    os << "busy: " << jobs_.size() << " verification job(s) running (~max_parallel_jobs = " << max_parallel_jobs_
       << "):";
    const ros::WallTime now = ros::WallTime::now();
    for (const auto& j : jobs_) {
      os << " job " << j.first << (j.second->goal_id.empty() ? "" : " (action goal)")
         << (j.second->client.empty() ? "" : " of " + j.second->client) << " for " << (now - j.second->started).toSec()
         << " s;";
    }
    os << " retry later, or stop them with " << pnh_.resolveName("cancel");
    refusal.busy = true;
    refusal.message = os.str();
    ++busy_answers_;
    return nullptr;
  }
  auto job = std::make_shared<Job>();
  job->id = ++last_job_id_;
  job->goal_id = goal_id;
  job->action = action;
  job->client = client;
  job->client_uri = uri;
  job->started = ros::WallTime::now();
  jobs_[job->id] = job;
  return job;
}

void AccuracyCheckerNode::finish(const std::shared_ptr<Job>& job, const WorkspaceOutcome& outcome) {
  {
    std::lock_guard<std::mutex> lock(jobs_mutex_);
    jobs_.erase(job->id);
    trim_pending_ = true;
    ++jobs_finished_;
    last_verdict_ = outcome.success ? outcome.verdict + (outcome.reason.empty() ? "" : " (" + outcome.reason + ")")
                                    : "failed: " + outcome.message;
    last_verdict_time_ = ros::WallTime::now();
  }
  jobs_changed_.notify_all();
}

void AccuracyCheckerNode::trimWhenIdle() {
  {
    std::lock_guard<std::mutex> lock(jobs_mutex_);
    if (!trim_pending_ || !jobs_.empty()) return;
    trim_pending_ = false;
  }
  // (glibc keeps freed memory in its arenas, one per thread that allocated; the job's request, domain and search
  // are freed by now, and the answer was sent on return from the handler.)
  malloc_trim(0);
}

void AccuracyCheckerNode::watchClients() {
  const auto period = std::chrono::duration<double>(client_check_period_s_);
  std::unique_lock<std::mutex> lock(jobs_mutex_);
  while (!shutting_down_) {
    jobs_changed_.wait_for(lock, period);
    if (shutting_down_) break;
    std::vector<std::shared_ptr<Job>> watched;
    for (const auto& j : jobs_) {
      if (!j.second->client_uri.empty() && !j.second->cancel) watched.push_back(j.second);
    }
    lock.unlock();
    for (const auto& job : watched) {
      const Liveness l = probeUri(job->client_uri, 0.2);
      job->gone_probes = l == Liveness::Gone ? job->gone_probes + 1 : 0;
      if (job->gone_probes >= 2) {
        job->stop(StopCause::ClientGone);
        ROS_WARN("job %lu: its client %s is gone (%s refuses connections): stopping it",
                 static_cast<unsigned long>(job->id), job->client.c_str(), job->client_uri.c_str());
        std::lock_guard<std::mutex> relock(jobs_mutex_);
        ++jobs_client_gone_;
      }
    }
    lock.lock();
  }
}

void AccuracyCheckerNode::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lock(jobs_mutex_);
  const std::uint64_t busy_since = busy_answers_ - busy_reported_;
  busy_reported_ = busy_answers_;
  if (busy_since > 0) {
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                  "%lu request(s) refused busy since the last report; %lu of %d job slot(s) in use",
                  static_cast<unsigned long>(busy_since), static_cast<unsigned long>(jobs_.size()), max_parallel_jobs_);
  } else {
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::OK, "robot loaded; %lu of %d job slot(s) in use",
                  static_cast<unsigned long>(jobs_.size()), max_parallel_jobs_);
  }
  stat.add("robot loaded", "true");
  stat.add("robot", robot_summary_);
  stat.add("robot source", source_);
  stat.add("robot file", robot_file_);
  stat.add("base frame", base_frame_);
  stat.add("jobs running", jobs_.size());
  stat.add("job slots", max_parallel_jobs_);
  stat.add("jobs finished", jobs_finished_);
  stat.add("busy answers", busy_answers_);
  stat.add("jobs stopped, client gone", jobs_client_gone_);
  stat.add("goals preempted", goals_preempted_);
  stat.add("default time budget (s)", defaults_.time_budget);
  stat.add("last verdict", last_verdict_);
  if (last_verdict_.empty()) {
    stat.add("last verdict age (s)", "");
  } else {
    std::ostringstream os;
    os << std::fixed << std::setprecision(3) << (ros::WallTime::now() - last_verdict_time_).toSec();
    stat.add("last verdict age (s)", os.str());
  }
}

bool AccuracyCheckerNode::resolveFrame(WorkspaceQuery& query, std::string& error) {
  query.has_transform = false;
  if (query.frame_id.empty()) return true;
  geometry_msgs::TransformStamped t;
  try {
    t = tf_buffer_->lookupTransform(base_frame_, query.frame_id, ros::Time(0), ros::Duration(tf_timeout_s_));
  } catch (const tf2::TransformException& e) {
    error = "frame_id: no transform from frame \"" + query.frame_id + "\" to the base frame \"" + base_frame_ +
            "\" within " + seconds(tf_timeout_s_) + " s (~tf_timeout); tf2 says: " + e.what();
    return false;
  }
  const auto& r = t.transform.rotation;
  const auto& p = t.transform.translation;
  const Eigen::Quaterniond q(r.w, r.x, r.y, r.z);
  const Eigen::Vector3d translation(p.x, p.y, p.z);
  if (!q.coeffs().allFinite() || q.norm() == 0.0 || !translation.allFinite()) {
    error = "frame_id: the transform from frame \"" + query.frame_id + "\" to \"" + base_frame_ +
            "\" in tf2 is not finite or has a zero quaternion";
    return false;
  }
  query.rotation = q.normalized().toRotationMatrix();
  query.translation = translation;
  query.has_transform = true;
  return true;
}

WorkspaceOutcome AccuracyCheckerNode::runJob(const std::shared_ptr<Job>& job, WorkspaceQuery query,
                                             const std::string& via,
                                             const std::function<void(const Progress&)>& feedback) {
  const std::uint64_t id = job->id;
  WorkspaceOutcome outcome;
  try {
    const std::string mode = modeName(query.mode);
    const std::string frame = query.frame_id.empty() ? base_frame_ : query.frame_id;
    if (query.domain == QueryDomain::Variety) {
      std::size_t terms = 0;
      for (const auto& c : query.variety.coordinates) terms += c.size();
      ROS_INFO("%s: job %lu started (%s, variety of %d parameter(s), %lu monomials, in frame %s)", via.c_str(),
               static_cast<unsigned long>(id), mode.c_str(), query.variety.parameters,
               static_cast<unsigned long>(terms), frame.c_str());
    } else if (query.domain == QueryDomain::Trajectory) {
      const bool segments = !query.trajectory.segments.empty();
      ROS_INFO("%s: job %lu started (%s, trajectory of %lu %s over [%g, %g] s in frame %s)", via.c_str(),
               static_cast<unsigned long>(id), mode.c_str(),
               static_cast<unsigned long>(segments ? query.trajectory.segments.size() : query.trajectory.times.size()),
               segments ? "polynomial segments" : "waypoints", query.trajectory.times.front(),
               query.trajectory.times.back(), frame.c_str());
    } else {
      const std::string what = query.pose_domain ? std::string("box of the robot's pose coordinates")
                                                 : toString(query.workspace.position.type) + " region";
      ROS_INFO("%s: job %lu started (%s, %s in frame %s)", via.c_str(), static_cast<unsigned long>(id), mode.c_str(),
               what.c_str(), frame.c_str());
    }

    query.record_safe_boxes = static_cast<std::size_t>(max_safe_box_markers_);  // (for ~boxes)
    {
      JobHooks hooks;
      hooks.cancel = &job->cancel;
      const bool publish_progress = progress_period_s_ > 0.0;
      if (publish_progress || feedback) {
        hooks.progress_period_s = publish_progress ? progress_period_s_ : 0.5;
        hooks.progress = [this, id, mode, &query, publish_progress, &feedback](const verify::Progress& p) {
          Progress msg;
          msg.header.stamp = ros::Time::now();
          msg.header.frame_id = base_frame_;
          msg.job_id = id;
          msg.mode = mode;
          msg.time_budget = query.time_budget;
          fillProgressStats(p.stats, msg);
          for (int k = 0; k < p.lower.size(); ++k) msg.lower.push_back(p.lower[k]);
          for (int k = 0; k < p.upper.size(); ++k) msg.upper.push_back(p.upper[k]);
          if (publish_progress) progress_pub_.publish(msg);
          if (feedback) feedback(msg);
        };
      }
      try {
        outcome = verifyWorkspace(*model_, query, hooks);
      } catch (const InvalidArgument& e) {
        outcome = WorkspaceOutcome();
        outcome.message = std::string("invalid request: ") + e.what();
      } catch (const std::exception& e) {
        outcome = WorkspaceOutcome();
        outcome.message = std::string("verification failed: ") + e.what();
      }
    }
    outcome.job_id = id;

    // ~verdict (latched) after every job, a last ~progress with the final statistics, ~boxes.
    VerificationResult result;
    result.header.stamp = ros::Time::now();
    result.header.frame_id = frame;
    toResultMessage(query, toVerifierOptions(query).method, outcome, result);
    verdict_pub_.publish(result);
    if (progress_period_s_ > 0.0 && outcome.success) {
      Progress last;
      last.header.stamp = result.header.stamp;
      last.header.frame_id = base_frame_;
      last.job_id = id;
      last.mode = mode;
      last.time_budget = query.time_budget;
      last.boxes = outcome.boxes;
      last.max_depth = outcome.max_depth;
      last.threads = outcome.threads;
      last.seconds = outcome.seconds;
      last.safe_fraction = outcome.safe_fraction;
      last.unsafe_fraction = outcome.unsafe_fraction;
      last.undecided_fraction = outcome.undecided_fraction;
      last.outside_fraction = outcome.outside_fraction;
      if (query.mode == QueryMode::MaxError) {  // (the robot's components, as the verifier's snapshots)
        const auto n = static_cast<std::ptrdiff_t>(std::min(query.components, 6));
        last.lower.assign(outcome.lower_bound.begin(), outcome.lower_bound.begin() + n);
        last.upper.assign(outcome.upper_bound.begin(), outcome.upper_bound.begin() + n);
      }
      progress_pub_.publish(last);
    }
    if (outcome.success) {
      // ~boxes: a workspace's region and undecided boxes, a trajectory's path (its boxes are time intervals) or a
      // variety's parameter grid (its boxes are parameter boxes).
      const ros::Time& stamp = result.header.stamp;
      boxes_pub_.publish(
          query.domain == QueryDomain::Trajectory ? makeTrajectoryMarkers(query, outcome, base_frame_, stamp)
          : query.domain == QueryDomain::Variety
              ? makeVarietyMarkers(query, outcome, base_frame_, stamp)
              : makeJobMarkers(query, outcome, base_frame_, stamp, static_cast<std::size_t>(max_box_markers_)));
      const std::string cause = stopCauseText(job->cause);
      ROS_INFO("%s: job %lu: %s%s%s in %.3f s, %lu boxes: %s%s", via.c_str(), static_cast<unsigned long>(id),
               outcome.verdict.c_str(), outcome.reason.empty() ? "" : " ", outcome.reason.c_str(), outcome.seconds,
               static_cast<unsigned long>(outcome.boxes), outcome.message.c_str(),
               cause.empty() ? "" : (" (" + cause + ")").c_str());
    } else {
      ROS_WARN("%s: job %lu: %s", via.c_str(), static_cast<unsigned long>(id), outcome.message.c_str());
    }
  } catch (const std::exception& e) {
    outcome = WorkspaceOutcome();
    outcome.job_id = id;
    outcome.message = std::string("verification failed: ") + e.what();
    ROS_ERROR("%s: %s", via.c_str(), outcome.message.c_str());
  } catch (...) {
    outcome = WorkspaceOutcome();
    outcome.job_id = id;
    outcome.message = "verification failed: unknown exception";
    ROS_ERROR("%s: %s", via.c_str(), outcome.message.c_str());
  }
  finish(job, outcome);
  return outcome;
}

template <class Srv>
bool AccuracyCheckerNode::onVerify(Event<Srv>& event, const char* name) {
  typename Srv::Response& res = event.getResponse();
  const std::string via = nh_.resolveName(name);
  try {
    res = typename Srv::Response();
    WorkspaceQuery query;
    std::string error;
    if (!fromRequest(event.getRequest(), base_frame_, defaults_, query, error)) {
      res.message = "invalid request: " + error;
      ROS_WARN("%s: %s", via.c_str(), res.message.c_str());
      return true;
    }
    if (!resolveFrame(query, error)) {  // (before admission: the tf2 wait holds no slot)
      res.message = error;
      ROS_WARN("%s: %s", via.c_str(), res.message.c_str());
      return true;
    }
    WorkspaceOutcome outcome;
    const std::shared_ptr<Job> job = admit(outcome, event.getCallerName());
    if (!job) {
      toResponse(outcome, res);
      ROS_WARN("%s: %s", via.c_str(), res.message.c_str());
      return true;
    }
    toResponse(runJob(job, query, via, nullptr), res);
    if (job->cause == StopCause::ClientGone) {
      ROS_WARN("%s: job %lu stopped because its client %s is gone; nobody receives its answer", via.c_str(),
               static_cast<unsigned long>(job->id), job->client.c_str());
    }
  } catch (const std::exception& e) {
    res = typename Srv::Response();
    res.message = std::string("verification failed: ") + e.what();
    ROS_ERROR("%s: %s", via.c_str(), res.message.c_str());
  } catch (...) {
    res = typename Srv::Response();
    res.message = "verification failed: unknown exception";
    ROS_ERROR("%s: %s", via.c_str(), res.message.c_str());
  }
  return true;  // the answer is in success/message; never make the client see a transport error
}

bool AccuracyCheckerNode::onVerifyWorkspace(Event<VerifyWorkspace>& event) {
  return onVerify<VerifyWorkspace>(event, kVerifyWorkspaceService);
}

bool AccuracyCheckerNode::onVerifyTrajectory(Event<VerifyTrajectory>& event) {
  return onVerify<VerifyTrajectory>(event, kVerifyTrajectoryService);
}

bool AccuracyCheckerNode::onVerifyVariety(Event<VerifyVariety>& event) {
  return onVerify<VerifyVariety>(event, kVerifyVarietyService);
}

bool AccuracyCheckerNode::onCancel(Cancel::Request& req, Cancel::Response& res) {
  res = Cancel::Response();
  std::lock_guard<std::mutex> lock(jobs_mutex_);
  for (auto& j : jobs_) {
    if (req.job_id != 0 && j.first != req.job_id) continue;
    j.second->stop(StopCause::CancelService);
    res.cancelled.push_back(j.first);
  }
  res.success = !res.cancelled.empty();
  if (res.success) {
    std::ostringstream os;
    os << "asked job(s)";
    for (auto id : res.cancelled) os << " " << id;
    os << " to stop";
    res.message = os.str();
    ROS_INFO("%s: %s", cancel_srv_.getService().c_str(), res.message.c_str());
  } else {
    res.message = req.job_id == 0 ? "no job is running" : "job " + std::to_string(req.job_id) + " is not running";
  }
  return true;
}

template <class Action>
std::unique_ptr<actionlib::ActionServer<Action>> AccuracyCheckerNode::startActionServer(const char* name) {
  using GoalHandle = actionlib::ServerGoalHandle<Action>;
  ros::NodeHandle action_nh(pnh_);
  action_nh.setCallbackQueue(&verify_queue_);
  std::unique_ptr<actionlib::ActionServer<Action>> server(new actionlib::ActionServer<Action>(
      action_nh, name, [this, name](GoalHandle gh) { onGoal<Action>(gh, name); },
      [this, name](GoalHandle gh) { onGoalCancel(gh.getGoalID().id, name); }, /*auto_start=*/false));
  server->start();
  return server;
}

std::size_t AccuracyCheckerNode::preemptGoalsOf(const std::string& client, const char* name, double timeout_s) {
  std::unique_lock<std::mutex> lock(jobs_mutex_);
  std::vector<std::uint64_t> stopped;
  for (auto& j : jobs_) {
    if (j.second->action != name || j.second->client != client) continue;
    j.second->stop(StopCause::Preempted);
    stopped.push_back(j.first);
  }
  goals_preempted_ += stopped.size();
  if (stopped.empty()) return 0;
  ROS_INFO("%s: a new goal of %s preempts its running goal(s) (job %lu%s)", pnh_.resolveName(name).c_str(),
           client.c_str(), static_cast<unsigned long>(stopped.front()), stopped.size() > 1 ? ", ..." : "");
  // A cancelled job ends within milliseconds; wait for its slot so that the new goal is not refused busy.
  jobs_changed_.wait_for(lock, std::chrono::duration<double>(timeout_s), [&] {
    return shutting_down_ ||
           std::none_of(stopped.begin(), stopped.end(), [&](std::uint64_t id) { return jobs_.count(id) > 0; });
  });
  return stopped.size();
}

template <class Action>
void AccuracyCheckerNode::onGoal(actionlib::ServerGoalHandle<Action> gh, const char* name) {
  using Result = typename Action::_action_result_type::_result_type;
  const std::string via = pnh_.resolveName(name);
  Result result;
  try {
    WorkspaceQuery query;
    std::string error;
    if (!fromRequest(toRequest(*gh.getGoal()), base_frame_, defaults_, query, error)) {
      result.message = "invalid request: " + error;
      ROS_WARN("%s: goal rejected: %s", via.c_str(), result.message.c_str());
      gh.setRejected(result, result.message);
      return;
    }
    if (!resolveFrame(query, error)) {  // (before admission: the tf2 wait holds no slot)
      result.message = error;
      ROS_WARN("%s: goal rejected: %s", via.c_str(), result.message.c_str());
      gh.setRejected(result, result.message);
      return;
    }
    // The SimpleActionServer habit, per client: a client's new goal replaces its running goal on this action (a
    // SimpleActionClient that sends a new goal has dropped the old one). Goals of other clients are not touched.
    // (A goal sent without an id gets one from this server, with this node's name: it has no known client.)
    std::string client = goalClient(gh.getGoalID().id);
    if (client == ros::this_node::getName()) client.clear();
    if (!client.empty()) preemptGoalsOf(client, name, 5.0);
    WorkspaceOutcome refusal;
    const std::shared_ptr<Job> job = admit(refusal, client, std::string(name) + " " + gh.getGoalID().id, name);
    if (!job) {
      toResult(refusal, result);
      ROS_WARN("%s: goal rejected: %s", via.c_str(), result.message.c_str());
      gh.setRejected(result, result.message);
      return;
    }
    gh.setAccepted("job " + std::to_string(job->id));
    // A goal cancelled before it was accepted is now PREEMPTING: it stops at once with the partial result.
    if (gh.getGoalStatus().status == actionlib_msgs::GoalStatus::PREEMPTING) job->stop(StopCause::ClientCancel);
    reapActionThreads(false);
    auto done = std::make_shared<std::atomic<bool>>(false);
    std::lock_guard<std::mutex> lock(threads_mutex_);
    action_threads_.push_back(ActionThread{std::thread([this, job, query, gh, name, done] {
                                             runGoal<Action>(job, query, gh, name);
                                             *done = true;
                                           }),
                                           done});
  } catch (const std::exception& e) {
    result = Result();
    result.message = std::string("verification failed: ") + e.what();
    ROS_ERROR("%s: %s", via.c_str(), result.message.c_str());
    gh.setRejected(result, result.message);
  }
}

template <class Action>
void AccuracyCheckerNode::runGoal(const std::shared_ptr<Job>& job, const WorkspaceQuery& query,
                                  actionlib::ServerGoalHandle<Action> gh, const char* name) {
  using Result = typename Action::_action_result_type::_result_type;
  using Feedback = typename Action::_action_feedback_type::_feedback_type;
  const std::string via = pnh_.resolveName(name);
  std::mutex feedback_mutex;
  const WorkspaceOutcome outcome = runJob(job, query, via, [&](const Progress& p) {
    Feedback f;
    toFeedback(p, f);
    std::lock_guard<std::mutex> lock(feedback_mutex);
    gh.publishFeedback(f);
  });
  Result result;
  toResult(outcome, result);
  const StopCause cause = job->cause;
  if (outcome.success && outcome.reason == verify::toString(verify::UndecidedReason::Cancelled)) {
    switch (cause) {
      case StopCause::ClientCancel:
        gh.setCanceled(result, "cancelled by the client: " + outcome.message);
        break;
      case StopCause::Preempted:
        gh.setCanceled(result, "preempted by a newer goal of the same client: " + outcome.message);
        break;
      case StopCause::ClientGone:
        gh.setAborted(result, "the client " + job->client + " is gone: " + outcome.message);
        break;
      default:
        gh.setAborted(result,
                      "stopped by " + pnh_.resolveName("cancel") + " or the node's shutdown: " + outcome.message);
        break;
    }
  } else if (outcome.success) {
    gh.setSucceeded(result, outcome.verdict + ": " + outcome.message);
  } else {
    gh.setAborted(result, outcome.message);
  }
}

void AccuracyCheckerNode::onGoalCancel(const std::string& goal_id, const char* name) {
  const std::string key = std::string(name) + " " + goal_id;
  std::lock_guard<std::mutex> lock(jobs_mutex_);
  for (auto& j : jobs_) {
    if (j.second->goal_id != key) continue;
    j.second->stop(StopCause::ClientCancel);
    ROS_INFO("%s: the client cancels job %lu", pnh_.resolveName(name).c_str(), static_cast<unsigned long>(j.first));
  }
}

void AccuracyCheckerNode::reapActionThreads(bool all) {
  std::vector<std::thread> finished;
  {
    std::lock_guard<std::mutex> lock(threads_mutex_);
    for (auto it = action_threads_.begin(); it != action_threads_.end();) {
      if (all || *it->done) {
        finished.push_back(std::move(it->thread));
        it = action_threads_.erase(it);
      } else {
        ++it;
      }
    }
  }
  for (auto& t : finished) {
    if (t.joinable()) t.join();
  }
}

WorkspaceOutcome AccuracyCheckerNode::verifyWorkspace(const model::RobotModel& model, const WorkspaceQuery& query,
                                                      const JobHooks& hooks) const {
  return runWorkspaceQuery(model, query, hooks);
}

}  // namespace ros_layer
}  // namespace pkm_accuracy
