#include "pkm_accuracy/ros/AccuracyCheckerNode.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <sstream>
#include <vector>

#include <geometry_msgs/TransformStamped.h>
#include <urdf/model.h>

#include "pkm_accuracy/Progress.h"
#include "pkm_accuracy/VerificationResult.h"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
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
  if (verify_spinner_) verify_spinner_->stop();
  verify_workspace_srv_.shutdown();
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
  ROS_INFO("Loaded robot from %s: %s", source_ == "yaml" ? ("parameters in " + pnh_.getNamespace()).c_str() : "URDF",
           robot_.summary().c_str());

  verdict_pub_ = pnh_.advertise<VerificationResult>("verdict", 1, /*latch=*/true);
  progress_pub_ = pnh_.advertise<Progress>("progress", 10);
  describe_srv_ = pnh_.advertiseService("describe", &AccuracyCheckerNode::onDescribe, this);
  cancel_srv_ = pnh_.advertiseService("cancel", &AccuracyCheckerNode::onCancel, this);

  ros::NodeHandle verify_nh(nh_);
  verify_nh.setCallbackQueue(&verify_queue_);
  verify_workspace_srv_ =
      verify_nh.advertiseService(kVerifyWorkspaceService, &AccuracyCheckerNode::onVerifyWorkspace, this);
  verify_spinner_.reset(new ros::AsyncSpinner(static_cast<std::uint32_t>(max_parallel_jobs_ + 1), &verify_queue_));
  verify_spinner_->start();

  if (pnh_.param("publish_anchor_frames", true)) publishAnchorFrames();
  ROS_INFO("Services: %s, %s, %s; topics: %s, %s (at most %d job(s) at once)", describe_srv_.getService().c_str(),
           cancel_srv_.getService().c_str(), verify_workspace_srv_.getService().c_str(),
           verdict_pub_.getTopic().c_str(), progress_pub_.getTopic().c_str(), max_parallel_jobs_);
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
    res.robot_source = source_;
    res.base_frame = names_.base_link;
    res.platform_frame = names_.platform_link;
    for (const auto& a : robot_.base_anchors) res.base_anchors.push_back(toPoint(a));
    for (const auto& b : robot_.platform_anchors) res.platform_anchors.push_back(toPoint(b));
    res.sensor_error = robot_.sensor_error;
    res.tool_point = toPoint(robot_.tool_point);
    for (const auto& h : robot_.base_anchor_halfwidth) res.base_anchor_halfwidth.push_back(toVector3(h));
    for (const auto& h : robot_.platform_anchor_halfwidth) res.platform_anchor_halfwidth.push_back(toVector3(h));
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

std::shared_ptr<AccuracyCheckerNode::Job> AccuracyCheckerNode::admit(WorkspaceOutcome& refusal) {
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
    for (const auto& j : jobs_) os << " job " << j.first << " for " << (now - j.second->started).toSec() << " s;";
    os << " retry later, or stop them with " << pnh_.resolveName("cancel");
    refusal.busy = true;
    refusal.message = os.str();
    return nullptr;
  }
  auto job = std::make_shared<Job>();
  job->id = ++last_job_id_;
  job->started = ros::WallTime::now();
  jobs_[job->id] = job;
  return job;
}

void AccuracyCheckerNode::finish(const std::shared_ptr<Job>& job) {
  std::lock_guard<std::mutex> lock(jobs_mutex_);
  jobs_.erase(job->id);
}

bool AccuracyCheckerNode::onVerifyWorkspace(VerifyWorkspace::Request& req, VerifyWorkspace::Response& res) {
  std::shared_ptr<Job> job;
  try {
    res = VerifyWorkspace::Response();
    WorkspaceQuery query;
    std::string error;
    if (!fromRequest(req, names_.base_link, defaults_, query, error)) {
      res.message = "invalid request: " + error;
      ROS_WARN("%s: %s", kVerifyWorkspaceService, res.message.c_str());
      return true;
    }
    WorkspaceOutcome outcome;
    job = admit(outcome);
    if (!job) {
      toResponse(outcome, res);
      ROS_WARN("%s: %s", kVerifyWorkspaceService, res.message.c_str());
      return true;
    }
    const std::uint64_t id = job->id;
    const std::string mode = modeName(query.mode);
    ROS_INFO("%s: job %lu started (%s, %s region)", kVerifyWorkspaceService, static_cast<unsigned long>(id),
             mode.c_str(), toString(query.workspace.position.type).c_str());

    JobHooks hooks;
    hooks.cancel = &job->cancel;
    if (progress_period_s_ > 0.0) {
      hooks.progress_period_s = progress_period_s_;
      hooks.progress = [this, id, mode, &query](const verify::Progress& p) {
        Progress msg;
        msg.header.stamp = ros::Time::now();
        msg.header.frame_id = names_.base_link;
        msg.job_id = id;
        msg.mode = mode;
        msg.time_budget = query.time_budget;
        fillProgressStats(p.stats, msg);
        for (int k = 0; k < p.lower.size(); ++k) msg.lower.push_back(p.lower[k]);
        for (int k = 0; k < p.upper.size(); ++k) msg.upper.push_back(p.upper[k]);
        progress_pub_.publish(msg);
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
    outcome.job_id = id;
    toResponse(outcome, res);

    // ~verdict (latched) after every job, and a last ~progress with the final statistics.
    VerificationResult result;
    result.header.stamp = ros::Time::now();
    result.header.frame_id = names_.base_link;
    toResultMessage(query, toVerifierOptions(query).method, outcome, result);
    verdict_pub_.publish(result);
    if (progress_period_s_ > 0.0 && outcome.success) {
      Progress last;
      last.header = result.header;
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
    finish(job);
    if (outcome.success) {
      ROS_INFO("%s: job %lu: %s%s%s in %.3f s, %lu boxes: %s", kVerifyWorkspaceService, static_cast<unsigned long>(id),
               outcome.verdict.c_str(), outcome.reason.empty() ? "" : " ", outcome.reason.c_str(), outcome.seconds,
               static_cast<unsigned long>(outcome.boxes), outcome.message.c_str());
    } else {
      ROS_WARN("%s: job %lu: %s", kVerifyWorkspaceService, static_cast<unsigned long>(id), outcome.message.c_str());
    }
  } catch (const std::exception& e) {
    if (job) finish(job);
    const std::uint64_t id = job ? job->id : 0;
    res = VerifyWorkspace::Response();
    res.job_id = id;
    res.message = std::string("verification failed: ") + e.what();
    ROS_ERROR("%s: %s", kVerifyWorkspaceService, res.message.c_str());
  } catch (...) {
    if (job) finish(job);
    const std::uint64_t id = job ? job->id : 0;
    res = VerifyWorkspace::Response();
    res.job_id = id;
    res.message = "verification failed: unknown exception";
    ROS_ERROR("%s: %s", kVerifyWorkspaceService, res.message.c_str());
  }
  return true;  // the answer is in success/message; never make the client see a transport error
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

WorkspaceOutcome AccuracyCheckerNode::verifyWorkspace(const model::RobotModel& model, const WorkspaceQuery& query,
                                                      const JobHooks& hooks) const {
  return runWorkspaceQuery(model, query, hooks);
}

}  // namespace ros_layer
}  // namespace pkm_accuracy
