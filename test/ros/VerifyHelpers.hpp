// Helpers of the /verify_workspace rostests: requests on sub-boxes of the `paper` workspace of config/ref6.yaml,
// service calls, and an independent oracle: the reference robot read directly from config/ref6.yaml (Ref6.hpp) and
// evaluated pointwise in double (model::RobotModel::worstErrorAt, not the interval verifier under test).
#pragma once

#include <array>
#include <cmath>
#include <functional>
#include <mutex>
#include <string>

#include <gtest/gtest.h>
#include <ros/ros.h>

#include "Ref6.hpp"
#include "pkm_accuracy/Cancel.h"
#include "pkm_accuracy/Describe.h"
#include "pkm_accuracy/VerifyTrajectory.h"
#include "pkm_accuracy/VerifyWorkspace.h"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"

namespace pkm_accuracy_test {

using pkm_accuracy::Cancel;
using pkm_accuracy::Describe;
using pkm_accuracy::VerifyTrajectory;
using pkm_accuracy::VerifyWorkspace;

constexpr const char* kVerifyService = "/verify_workspace";
constexpr const char* kDescribeService = "/pkm_accuracy/describe";
constexpr const char* kCancelService = "/pkm_accuracy/cancel";
constexpr double k40deg = 0.6981317007977318;
/// +-38 deg: no singular pose (max_error over the paper box at these angles has a finite certified bracket), and
/// max_error to 1e-4 over it takes more than 20 s on one thread: the long jobs of the tests (at +-40 deg a singular
/// pose ends a max_error job at once; at +-15 deg it converges to 1e-4 in about a second).
constexpr double k38deg = 0.6632251157578453;
constexpr double k15deg = 0.2617993877991494;

/// A box workspace: x, y in [-xy, xy], z in [z0, z1] (m), every angle in [-angle, angle] (rad).
inline VerifyWorkspace::Request boxRequest(double xy, double z0, double z1, double angle,
                                           const std::array<double, 6>& thresholds, const std::string& mode) {
  VerifyWorkspace::Request r;
  r.region_type = VerifyWorkspace::Request::REGION_BOX;
  r.box_min = {-xy, -xy, z0};
  r.box_max = {xy, xy, z1};
  r.roll_min = r.pitch_min = r.yaw_min = -angle;
  r.roll_max = r.pitch_max = r.yaw_max = angle;
  for (std::size_t k = 0; k < 6; ++k) r.thresholds[k] = thresholds[k];
  r.mode = mode;
  r.time_budget = 20.0;
  return r;
}

/// The small sub-box of the paper workspace used by most tests: x, y in [-0.01, 0.01], z in [0.47, 0.48] (m),
/// angles in [-0.01, 0.01] rad. Decided in milliseconds.
inline VerifyWorkspace::Request smallRequest(const std::array<double, 6>& thresholds,
                                             const std::string& mode = "verify") {
  return boxRequest(0.01, 0.47, 0.48, 0.01, thresholds, mode);
}

inline const std::array<double, 6> kGenerous = {1e-3, 1e-3, 1e-3, 1e-2, 1e-2, 1e-2};
inline const std::array<double, 6> kTiny = {1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-6};
inline const std::array<double, 6> kPaper = {1e-4, 1e-4, 1e-4, 1e-3, 1e-3, 1e-3};
inline const std::array<double, 6> kNone = {0, 0, 0, 0, 0, 0};

/// A /verify_trajectory request: three waypoints at t = 1, 2, 4 s inside the paper workspace: x, y in [-0.01, 0.01],
/// z in [0.47, 0.48] (m), angles within 0.01 rad (base frame).
inline VerifyTrajectory::Request shortTrajectory(const std::array<double, 6>& thresholds,
                                                 const std::string& interpolation = "slerp") {
  VerifyTrajectory::Request r;
  r.times = {1.0, 2.0, 4.0};
  r.x = {-0.01, 0.0, 0.01};
  r.y = {0.01, -0.005, -0.01};
  r.z = {0.47, 0.475, 0.48};
  r.roll = {0.0, 0.01, -0.01};
  r.pitch = {-0.01, 0.0, 0.01};
  r.yaw = {0.005, -0.01, 0.0};
  r.interpolation = interpolation;
  for (std::size_t k = 0; k < 6; ++k) r.thresholds[k] = thresholds[k];
  r.time_budget = 20.0;
  return r;
}

inline VerifyWorkspace::Response verify(const VerifyWorkspace::Request& req) {
  EXPECT_TRUE(ros::service::waitForService(kVerifyService, ros::Duration(20.0)));
  VerifyWorkspace srv;
  srv.request = req;
  EXPECT_TRUE(ros::service::call(kVerifyService, srv));  // transport success even for bad requests
  return srv.response;
}

inline Describe::Response describe() {
  EXPECT_TRUE(ros::service::waitForService(kDescribeService, ros::Duration(20.0)));
  Describe srv;
  EXPECT_TRUE(ros::service::call(kDescribeService, srv));
  return srv.response;
}

inline Cancel::Response cancel(std::uint64_t job_id) {
  EXPECT_TRUE(ros::service::waitForService(kCancelService, ros::Duration(20.0)));
  Cancel srv;
  srv.request.job_id = job_id;
  EXPECT_TRUE(ros::service::call(kCancelService, srv));
  return srv.response;
}

/// The reference robot as a core model, built from the yaml oracle.
inline const pkm_accuracy::model::GoughPlatform& oracleModel() {
  static const pkm_accuracy::model::GoughPlatform model = [] {
    const Ref6 ref = loadRef6();
    pkm_accuracy::model::GoughGeometry g;
    g.base_anchors = ref.base_anchors;
    g.platform_anchors = ref.platform_anchors;
    g.sensor_error = ref.sensor_error;
    g.tool_point = ref.tool_point;
    return pkm_accuracy::model::GoughPlatform(g);
  }();
  return model;
}

/// Worst error of every component at a pose (double, not certified; independent of the verifier's enclosures).
inline std::array<double, 6> worstErrorAt(const std::array<double, 6>& pose) {
  pkm_accuracy::DVec p(6);
  for (int i = 0; i < 6; ++i) p[i] = pose[static_cast<std::size_t>(i)];
  const pkm_accuracy::DVec f = oracleModel().worstErrorAt(p);
  std::array<double, 6> out{};
  for (int k = 0; k < 6; ++k) out[static_cast<std::size_t>(k)] = f[k];
  return out;
}

/// Whether a pose lies in the box workspace of a request (exactly, no tolerance).
inline ::testing::AssertionResult poseInWorkspace(const std::array<double, 6>& pose,
                                                  const VerifyWorkspace::Request& r) {
  const double lo[6] = {r.box_min[0], r.box_min[1], r.box_min[2], r.roll_min, r.pitch_min, r.yaw_min};
  const double hi[6] = {r.box_max[0], r.box_max[1], r.box_max[2], r.roll_max, r.pitch_max, r.yaw_max};
  for (int i = 0; i < 6; ++i) {
    if (!(lo[i] <= pose[static_cast<std::size_t>(i)] && pose[static_cast<std::size_t>(i)] <= hi[i])) {
      return ::testing::AssertionFailure() << "coordinate " << i << " = " << pose[static_cast<std::size_t>(i)]
                                           << " outside [" << lo[i] << ", " << hi[i] << "]";
    }
  }
  return ::testing::AssertionSuccess();
}

/// Keeps the last message of a latched topic; waits for one that satisfies a predicate.
template <class Msg>
class Latest {
 public:
  explicit Latest(const std::string& topic)
      : sub_(ros::NodeHandle().subscribe<Msg>(topic, 10, [this](const boost::shared_ptr<const Msg>& m) {
          std::lock_guard<std::mutex> lock(mutex_);
          last_ = m;
        })) {}
  boost::shared_ptr<const Msg> waitFor(const std::function<bool(const Msg&)>& ok, double timeout = 10.0) {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
    while (ros::WallTime::now() < deadline) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (last_ && ok(*last_)) return last_;
      }
      ros::WallDuration(0.02).sleep();
    }
    return nullptr;
  }

 private:
  std::mutex mutex_;
  boost::shared_ptr<const Msg> last_;
  ros::Subscriber sub_;
};

template <class Array>
std::array<double, 6> to6(const Array& a) {
  std::array<double, 6> out{};
  for (std::size_t k = 0; k < 6; ++k) out[k] = a[k];
  return out;
}

}  // namespace pkm_accuracy_test
