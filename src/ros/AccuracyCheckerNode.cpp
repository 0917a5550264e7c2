#include "pkm_accuracy/ros/AccuracyCheckerNode.hpp"

#include <cmath>
#include <exception>
#include <vector>

#include <geometry_msgs/TransformStamped.h>
#include <urdf/model.h>

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

}  // namespace

AccuracyCheckerNode::AccuracyCheckerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh) : nh_(nh), pnh_(pnh) {}

AccuracyCheckerNode::~AccuracyCheckerNode() {
  if (verify_spinner_) verify_spinner_->stop();
  verify_workspace_srv_.shutdown();
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
}

bool AccuracyCheckerNode::start(std::string& error) {
  if (!loadRobot(error)) return false;
  readDefaults();
  ROS_INFO("Loaded robot from %s: %s", source_ == "yaml" ? ("parameters in " + pnh_.getNamespace()).c_str() : "URDF",
           robot_.summary().c_str());

  describe_srv_ = pnh_.advertiseService("describe", &AccuracyCheckerNode::onDescribe, this);

  ros::NodeHandle verify_nh(nh_);
  verify_nh.setCallbackQueue(&verify_queue_);
  verify_workspace_srv_ =
      verify_nh.advertiseService(kVerifyWorkspaceService, &AccuracyCheckerNode::onVerifyWorkspace, this);
  verify_spinner_.reset(new ros::AsyncSpinner(1, &verify_queue_));
  verify_spinner_->start();

  if (pnh_.param("publish_anchor_frames", true)) publishAnchorFrames();
  ROS_INFO("Services: %s, %s", describe_srv_.getService().c_str(), verify_workspace_srv_.getService().c_str());
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

bool AccuracyCheckerNode::onVerifyWorkspace(VerifyWorkspace::Request& req, VerifyWorkspace::Response& res) {
  try {
    res = VerifyWorkspace::Response();
    WorkspaceQuery query;
    std::string error;
    if (!fromRequest(req, names_.base_link, defaults_, query, error)) {
      res.message = "invalid request: " + error;
      ROS_WARN("%s: %s", kVerifyWorkspaceService, res.message.c_str());
      return true;
    }
    toResponse(verifyWorkspace(robot_, query), res);
  } catch (const std::exception& e) {
    res = VerifyWorkspace::Response();
    res.message = std::string("verification failed: ") + e.what();
    ROS_ERROR("%s: %s", kVerifyWorkspaceService, res.message.c_str());
  } catch (...) {
    res = VerifyWorkspace::Response();
    res.message = "verification failed: unknown exception";
    ROS_ERROR("%s: %s", kVerifyWorkspaceService, res.message.c_str());
  }
  return true;  // the answer is in success/message; never make the client see a transport error
}

WorkspaceOutcome AccuracyCheckerNode::verifyWorkspace(const model::GoughGeometry& /*robot*/,
                                                      const WorkspaceQuery& /*query*/) const {
  // TODO(core team): call the core verifier here. With the core API as of this writing, roughly:
  //   model::GoughPlatform model(robot);
  //   domain::PositionRegion region = PositionRegion::box(lo, hi), ::cylinder(cx, cy, r, zmin, zmax),
  //       ::sphere(c, r) or ::polyhedron(normals, offsets, box_min, box_max), from query.workspace.position;
  //   domain::Workspace ws(region, {roll, pitch, yaw} intervals from query.workspace.angle_min/max);
  //   verify::VerifierOptions o; o.mode, o.thresholds (if query.has_thresholds), o.alpha, o.time_limit_s =
  //   query.time_budget, o.min_width (6 x query.min_width, or empty if 0), o.threads;
  //   verify::VerifierResult r = verify::Verifier::run(model, ws, o);
  //   then copy verdict (verify::toString), bounds, witness and statistics into a WorkspaceOutcome, success = true.
  // Exceptions (InvalidArgument naming a field) are caught by onVerifyWorkspace() and become success=false.
  WorkspaceOutcome out;
  out.success = false;
  out.message = "verifier not available yet (the request is valid)";
  return out;
}

}  // namespace ros_layer
}  // namespace pkm_accuracy
