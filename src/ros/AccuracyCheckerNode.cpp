#include "pkm_accuracy/ros/AccuracyCheckerNode.hpp"

#include <malloc.h>

#include <algorithm>
#include <cmath>
#include <exception>
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
#include "pkm_accuracy/ros/BoxMarkers.hpp"
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

}  // namespace

AccuracyCheckerNode::AccuracyCheckerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh) : nh_(nh), pnh_(pnh) {}

AccuracyCheckerNode::~AccuracyCheckerNode() {
  {
    // Running jobs stop promptly (they answer UNDECIDED, reason "cancelled"); no new job starts.
    std::lock_guard<std::mutex> lock(jobs_mutex_);
    shutting_down_ = true;
    for (auto& j : jobs_) j.second->cancel = true;
  }
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
    error = key + ": " + error;
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
    double v = pnh_.param(key, fallback);
    if (!std::isfinite(v) || v < 0.0 || (v == 0.0 && !zero_ok)) {
      ROS_WARN("%s: expected a finite number %s, got %g; using %g", pnh_.resolveName(key).c_str(),
               zero_ok ? ">= 0" : "> 0", v, fallback);
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
    std::string list;
    for (const auto& m : methods) list += (list.empty() ? "" : ", ") + m;
    ROS_WARN("%s: expected one of %s or \"\", got \"%s\"; using the verifier's default",
             pnh_.resolveName("default_method").c_str(), list.c_str(), defaults_.method.c_str());
    defaults_.method = builtin.method;
  }

  tf_timeout_s_ = read("tf_timeout", 1.0, true);
  max_box_markers_ = pnh_.param("max_box_markers", 500);
  if (max_box_markers_ < 0) {
    ROS_WARN("%s: expected an integer >= 0, got %d; using 500", pnh_.resolveName("max_box_markers").c_str(),
             max_box_markers_);
    max_box_markers_ = 500;
  }
  max_safe_box_markers_ = pnh_.param("max_safe_box_markers", 2000);
  if (max_safe_box_markers_ < 0) {
    ROS_WARN("%s: expected an integer >= 0, got %d; using 2000", pnh_.resolveName("max_safe_box_markers").c_str(),
             max_safe_box_markers_);
    max_safe_box_markers_ = 2000;
  }

  max_parallel_jobs_ = pnh_.param("max_parallel_jobs", 1);
  if (max_parallel_jobs_ < 1 || max_parallel_jobs_ > 64) {
    ROS_WARN("%s: expected an integer from 1 to 64, got %d; using 1", pnh_.resolveName("max_parallel_jobs").c_str(),
             max_parallel_jobs_);
    max_parallel_jobs_ = 1;
  }
}

bool AccuracyCheckerNode::start(std::string& error) {
  if (!loadRobot(error)) return false;
  try {
    model_.reset(new model::GoughPlatform(robot_));
  } catch (const std::exception& e) {
    error = std::string("robot: ") + e.what();
    return false;
  }
  readDefaults();
  if (!loadNamedWorkspaces(pnh_, defaults_.workspaces, error)) return false;
  ROS_INFO("Loaded robot from %s: %s", source_ == "yaml" ? ("parameters in " + pnh_.getNamespace()).c_str() : "URDF",
           robot_.summary().c_str());

  tf_buffer_.reset(new tf2_ros::Buffer());
  tf_listener_.reset(new tf2_ros::TransformListener(*tf_buffer_, nh_, /*spin_thread=*/true));
  verdict_pub_ = pnh_.advertise<VerificationResult>("verdict", 1, /*latch=*/true);
  progress_pub_ = pnh_.advertise<Progress>("progress", 10);
  boxes_pub_ = pnh_.advertise<visualization_msgs::MarkerArray>("boxes", 1, /*latch=*/true);
  describe_srv_ = pnh_.advertiseService("describe", &AccuracyCheckerNode::onDescribe, this);
  cancel_srv_ = pnh_.advertiseService("cancel", &AccuracyCheckerNode::onCancel, this);
  idle_trim_timer_ =
      pnh_.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { trimWhenIdle(); });

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

  if (pnh_.param("publish_anchor_frames", true)) publishAnchorFrames();
  ROS_INFO("Services: %s, %s, %s, %s, %s; actions: %s, %s, %s; topics: %s, %s, %s (at most %d job(s) at once)",
           describe_srv_.getService().c_str(), cancel_srv_.getService().c_str(),
           verify_workspace_srv_.getService().c_str(), verify_trajectory_srv_.getService().c_str(),
           verify_variety_srv_.getService().c_str(), pnh_.resolveName(kVerifyWorkspaceAction).c_str(),
           pnh_.resolveName(kVerifyTrajectoryAction).c_str(), pnh_.resolveName(kVerifyVarietyAction).c_str(),
           verdict_pub_.getTopic().c_str(), progress_pub_.getTopic().c_str(), boxes_pub_.getTopic().c_str(),
           max_parallel_jobs_);
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
    add(names_.base_link, formatAnchorName(names_.base_anchor_pattern, index), robot_.base_anchors[i]);
    add(names_.platform_link, formatAnchorName(names_.platform_anchor_pattern, index), robot_.platform_anchors[i]);
  }
  tf_broadcaster_.reset(new tf2_ros::StaticTransformBroadcaster());
  tf_broadcaster_->sendTransform(transforms);
}

bool AccuracyCheckerNode::onDescribe(Describe::Request& /*req*/, Describe::Response& res) {
  try {
    res = Describe::Response();
    res.version = pkm_accuracy::version();
    res.robot_source = source_;
    res.base_frame = names_.base_link;
    res.platform_frame = names_.platform_link;
    for (const auto& a : robot_.base_anchors) res.base_anchors.push_back(toPoint(a));
    for (const auto& b : robot_.platform_anchors) res.platform_anchors.push_back(toPoint(b));
    res.sensor_error = robot_.sensor_error;
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
    res.message = robot_.summary();
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
                                                                     const std::string& goal_id) {
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
      os << " job " << j.first << (j.second->goal_id.empty() ? "" : " (action goal)") << " for "
         << (now - j.second->started).toSec() << " s;";
    }
    os << " retry later, or stop them with " << pnh_.resolveName("cancel");
    refusal.busy = true;
    refusal.message = os.str();
    return nullptr;
  }
  auto job = std::make_shared<Job>();
  job->id = ++last_job_id_;
  job->goal_id = goal_id;
  job->started = ros::WallTime::now();
  jobs_[job->id] = job;
  return job;
}

void AccuracyCheckerNode::finish(const std::shared_ptr<Job>& job) {
  std::lock_guard<std::mutex> lock(jobs_mutex_);
  jobs_.erase(job->id);
  trim_pending_ = true;
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

bool AccuracyCheckerNode::resolveFrame(WorkspaceQuery& query, std::string& error) {
  query.has_transform = false;
  if (query.frame_id.empty()) return true;
  geometry_msgs::TransformStamped t;
  try {
    t = tf_buffer_->lookupTransform(names_.base_link, query.frame_id, ros::Time(0), ros::Duration(tf_timeout_s_));
  } catch (const tf2::TransformException& e) {
    error = "frame_id: no transform from frame \"" + query.frame_id + "\" to the base frame \"" + names_.base_link +
            "\" within " + seconds(tf_timeout_s_) + " s (~tf_timeout); tf2 says: " + e.what();
    return false;
  }
  const auto& r = t.transform.rotation;
  const auto& p = t.transform.translation;
  const Eigen::Quaterniond q(r.w, r.x, r.y, r.z);
  const Eigen::Vector3d translation(p.x, p.y, p.z);
  if (!q.coeffs().allFinite() || q.norm() == 0.0 || !translation.allFinite()) {
    error = "frame_id: the transform from frame \"" + query.frame_id + "\" to \"" + names_.base_link +
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
    const std::string frame = query.frame_id.empty() ? names_.base_link : query.frame_id;
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
      ROS_INFO("%s: job %lu started (%s, %s region in frame %s)", via.c_str(), static_cast<unsigned long>(id),
               mode.c_str(), toString(query.workspace.position.type).c_str(), frame.c_str());
    }

    std::string error;
    query.record_safe_boxes = static_cast<std::size_t>(max_safe_box_markers_);  // (for ~boxes)
    if (!resolveFrame(query, error)) {
      outcome.message = error;
    } else {
      JobHooks hooks;
      hooks.cancel = &job->cancel;
      const bool publish_progress = progress_period_s_ > 0.0;
      if (publish_progress || feedback) {
        hooks.progress_period_s = publish_progress ? progress_period_s_ : 0.5;
        hooks.progress = [this, id, mode, &query, publish_progress, &feedback](const verify::Progress& p) {
          Progress msg;
          msg.header.stamp = ros::Time::now();
          msg.header.frame_id = names_.base_link;
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
      last.header.frame_id = names_.base_link;
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
      if (query.mode == QueryMode::MaxError) {
        last.lower.assign(outcome.lower_bound.begin(), outcome.lower_bound.end());
        last.upper.assign(outcome.upper_bound.begin(), outcome.upper_bound.end());
      }
      progress_pub_.publish(last);
    }
    if (outcome.success) {
      // ~boxes: a workspace's region and undecided boxes, a trajectory's path (its boxes are time intervals) or a
      // variety's parameter grid (its boxes are parameter boxes).
      const ros::Time& stamp = result.header.stamp;
      boxes_pub_.publish(
          query.domain == QueryDomain::Trajectory ? makeTrajectoryMarkers(query, outcome, names_.base_link, stamp)
          : query.domain == QueryDomain::Variety
              ? makeVarietyMarkers(query, outcome, names_.base_link, stamp)
              : makeJobMarkers(query, outcome, names_.base_link, stamp, static_cast<std::size_t>(max_box_markers_)));
      ROS_INFO("%s: job %lu: %s%s%s in %.3f s, %lu boxes: %s", via.c_str(), static_cast<unsigned long>(id),
               outcome.verdict.c_str(), outcome.reason.empty() ? "" : " ", outcome.reason.c_str(), outcome.seconds,
               static_cast<unsigned long>(outcome.boxes), outcome.message.c_str());
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
  finish(job);
  return outcome;
}

template <class Srv>
bool AccuracyCheckerNode::onVerify(typename Srv::Request& req, typename Srv::Response& res, const char* name) {
  try {
    res = typename Srv::Response();
    WorkspaceQuery query;
    std::string error;
    if (!fromRequest(req, names_.base_link, defaults_, query, error)) {
      res.message = "invalid request: " + error;
      ROS_WARN("%s: %s", name, res.message.c_str());
      return true;
    }
    WorkspaceOutcome outcome;
    const std::shared_ptr<Job> job = admit(outcome);
    if (!job) {
      toResponse(outcome, res);
      ROS_WARN("%s: %s", name, res.message.c_str());
      return true;
    }
    toResponse(runJob(job, query, name, nullptr), res);
  } catch (const std::exception& e) {
    res = typename Srv::Response();
    res.message = std::string("verification failed: ") + e.what();
    ROS_ERROR("%s: %s", name, res.message.c_str());
  } catch (...) {
    res = typename Srv::Response();
    res.message = "verification failed: unknown exception";
    ROS_ERROR("%s: %s", name, res.message.c_str());
  }
  return true;  // the answer is in success/message; never make the client see a transport error
}

bool AccuracyCheckerNode::onVerifyWorkspace(VerifyWorkspace::Request& req, VerifyWorkspace::Response& res) {
  return onVerify<VerifyWorkspace>(req, res, kVerifyWorkspaceService);
}

bool AccuracyCheckerNode::onVerifyTrajectory(VerifyTrajectory::Request& req, VerifyTrajectory::Response& res) {
  return onVerify<VerifyTrajectory>(req, res, kVerifyTrajectoryService);
}

bool AccuracyCheckerNode::onVerifyVariety(VerifyVariety::Request& req, VerifyVariety::Response& res) {
  return onVerify<VerifyVariety>(req, res, kVerifyVarietyService);
}

bool AccuracyCheckerNode::onCancel(Cancel::Request& req, Cancel::Response& res) {
  res = Cancel::Response();
  std::lock_guard<std::mutex> lock(jobs_mutex_);
  for (auto& j : jobs_) {
    if (req.job_id != 0 && j.first != req.job_id) continue;
    j.second->cancel = true;
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

template <class Action>
void AccuracyCheckerNode::onGoal(actionlib::ServerGoalHandle<Action> gh, const char* name) {
  using Result = typename Action::_action_result_type::_result_type;
  const std::string via = pnh_.resolveName(name);
  Result result;
  try {
    WorkspaceQuery query;
    std::string error;
    if (!fromRequest(toRequest(*gh.getGoal()), names_.base_link, defaults_, query, error)) {
      result.message = "invalid request: " + error;
      ROS_WARN("%s: goal rejected: %s", via.c_str(), result.message.c_str());
      gh.setRejected(result, result.message);
      return;
    }
    WorkspaceOutcome refusal;
    const std::shared_ptr<Job> job = admit(refusal, std::string(name) + " " + gh.getGoalID().id);
    if (!job) {
      toResult(refusal, result);
      ROS_WARN("%s: goal rejected: %s", via.c_str(), result.message.c_str());
      gh.setRejected(result, result.message);
      return;
    }
    gh.setAccepted("job " + std::to_string(job->id));
    // A goal cancelled before it was accepted is now PREEMPTING: it stops at once with the partial result.
    if (gh.getGoalStatus().status == actionlib_msgs::GoalStatus::PREEMPTING) {
      job->client_cancel = true;
      job->cancel = true;
    }
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
  if (outcome.success && outcome.reason == verify::toString(verify::UndecidedReason::Cancelled)) {
    if (job->client_cancel) {
      gh.setCanceled(result, "cancelled by the client: " + outcome.message);
    } else {
      gh.setAborted(result, "stopped by " + pnh_.resolveName("cancel") + " or the node's shutdown: " + outcome.message);
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
    j.second->client_cancel = true;
    j.second->cancel = true;
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
