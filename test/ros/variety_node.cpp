// rostest (variety.test): /verify_variety on the reference robot of config/ref6.yaml. The oracle is independent of
// the verifier: the test evaluates the variety's monomials itself (double) and the worst error at each pose from the
// yaml geometry (GoughPlatform::worstErrorAt in double, VerifyHelpers.hpp), on a grid of parameter points.
// - verify: SAFE with thresholds 10% above the sampled maxima, UNSAFE 5% below them, the witness's parameters in
//   [0, 1]^m, its pose the variety's there and its error above the violated threshold by the oracle;
// - max_error: the bracket contains the sampled maxima, and each lower bound is attained (by the oracle) at the
//   reported parameter point, whose reported pose is the variety's there;
// - a 3-parameter variety (a volume of poses); a variety in a tilted tf2 frame (the oracle composes the frame's
//   transform itself); ~verdict (region "variety", the bounding box of the poses) and ~boxes (the parameter grid,
//   green when SAFE); every malformed field refused by name while the node keeps serving; the ~verify_variety
//   action (goal / result = request / response field for field, the same answers, malformed goals rejected).
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <actionlib/client/simple_action_client.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <visualization_msgs/MarkerArray.h>
#include <Eigen/Geometry>

#include "ActionHelpers.hpp"
#include "VerifyHelpers.hpp"
#include "pkm_accuracy/VerificationResult.h"
#include "pkm_accuracy/VerifyVariety.h"
#include "pkm_accuracy/VerifyVarietyAction.h"
#include "pkm_accuracy/ros/BoxMarkers.hpp"
#include "pkm_accuracy/ros/VerifyVarietyConversion.hpp"

namespace {

using pkm_accuracy::VarietyTerm;
using pkm_accuracy::VerificationResult;
using pkm_accuracy::VerifyVariety;
using pkm_accuracy_test::kNone;
using pkm_accuracy_test::Latest;
using pkm_accuracy_test::to6;
using pkm_accuracy_test::worstErrorAt;
using Pose = std::array<double, 6>;

constexpr const char* kService = "/verify_variety";

VerifyVariety::Response call(const VerifyVariety::Request& req) {
  EXPECT_TRUE(ros::service::waitForService(kService, ros::Duration(20.0)));
  VerifyVariety srv;
  srv.request = req;
  EXPECT_TRUE(ros::service::call(kService, srv));  // transport success even for bad requests
  return srv.response;
}

VarietyTerm term(double coefficient, std::vector<std::uint32_t> exponents) {
  VarietyTerm t;
  t.coefficient = coefficient;
  t.exponents = std::move(exponents);
  return t;
}

/// A curved surface inside the paper workspace: x = -0.06 + 0.12 u, y = -0.05 + 0.1 v + 0.02 u v,
/// z = 0.46 + 0.03 u^2, roll = 0.1 v - 0.05, pitch = 0.08 u v, yaw = 0.2 u - 0.1 v^2.
VerifyVariety::Request surface(const std::array<double, 6>& thresholds) {
  VerifyVariety::Request r;
  r.parameters = 2;
  r.x = {term(-0.06, {0, 0}), term(0.12, {1, 0})};
  r.y = {term(-0.05, {0, 0}), term(0.1, {0, 1}), term(0.02, {1, 1})};
  r.z = {term(0.46, {0, 0}), term(0.03, {2, 0})};
  r.roll = {term(-0.05, {0, 0}), term(0.1, {0, 1})};
  r.pitch = {term(0.08, {1, 1})};
  r.yaw = {term(0.2, {1, 0}), term(-0.1, {0, 2})};
  for (std::size_t k = 0; k < 6; ++k) r.thresholds[k] = thresholds[k];
  r.threads = 2;
  return r;
}

/// A volume of poses (3 parameters): a 6 cm cube at z 0.45 .. 0.51 with the yaw turning along w.
VerifyVariety::Request volume(const std::array<double, 6>& thresholds) {
  VerifyVariety::Request r;
  r.parameters = 3;
  r.x = {term(-0.03, {0, 0, 0}), term(0.06, {1, 0, 0})};
  r.y = {term(-0.03, {0, 0, 0}), term(0.06, {0, 1, 0})};
  r.z = {term(0.45, {0, 0, 0}), term(0.06, {0, 0, 1})};
  r.yaw = {term(-0.1, {0, 0, 0}), term(0.2, {0, 0, 1}), term(0.05, {1, 1, 0})};
  for (std::size_t k = 0; k < 6; ++k) r.thresholds[k] = thresholds[k];
  r.threads = 2;
  return r;
}

/// The oracle's pose of a variety at a parameter point (its own evaluation of the monomials), in the request's frame.
Pose poseOf(const VerifyVariety::Request& r, const std::vector<double>& t) {
  const std::vector<VarietyTerm>* coords[6] = {&r.x, &r.y, &r.z, &r.roll, &r.pitch, &r.yaw};
  Pose p{};
  for (std::size_t k = 0; k < 6; ++k) {
    for (const VarietyTerm& m : *coords[k]) {
      double v = m.coefficient;
      for (std::size_t i = 0; i < m.exponents.size(); ++i) v *= std::pow(t[i], static_cast<double>(m.exponents[i]));
      p[k] += v;
    }
  }
  return p;
}

/// tilted (variety.test): translation (0.02, -0.01, 0.1), R = Rz(0.3) Ry(0.1) Rx(-0.05).
Pose tiltedToBase(const Pose& p) {
  const Eigen::Matrix3d F =
      (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(-0.05, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  const Eigen::Matrix3d R =
      F * (Eigen::AngleAxisd(p[5], Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(p[4], Eigen::Vector3d::UnitY()) *
           Eigen::AngleAxisd(p[3], Eigen::Vector3d::UnitX()))
              .toRotationMatrix();
  const Eigen::Vector3d x = Eigen::Vector3d(0.02, -0.01, 0.1) + F * Eigen::Vector3d(p[0], p[1], p[2]);
  return {x.x(), x.y(), x.z(), std::atan2(R(2, 1), R(2, 2)), std::asin(-R(2, 0)), std::atan2(R(1, 0), R(0, 0))};
}

/// Maxima of the worst error over a grid of n points per parameter (the oracle); `toBase` maps the request's frame.
std::array<double, 6> sampledMaxima(const VerifyVariety::Request& r, int n, Pose (*toBase)(const Pose&) = nullptr) {
  const std::size_t m = r.parameters;
  std::array<double, 6> best{};
  std::vector<int> idx(m, 0);
  while (true) {
    std::vector<double> t(m);
    for (std::size_t i = 0; i < m; ++i) t[i] = static_cast<double>(idx[i]) / (n - 1);
    const Pose p = toBase ? toBase(poseOf(r, t)) : poseOf(r, t);
    const std::array<double, 6> e = worstErrorAt(p);
    for (std::size_t k = 0; k < 6; ++k) best[k] = std::max(best[k], e[k]);
    std::size_t i = 0;
    while (i < m && ++idx[i] == n) idx[i++] = 0;
    if (i == m) break;
  }
  return best;
}

std::array<double, 6> scaled(const std::array<double, 6>& a, double f) {
  std::array<double, 6> out{};
  for (std::size_t k = 0; k < 6; ++k) out[k] = a[k] * f;
  return out;
}

void expectPoseNear(const Pose& got, const Pose& want, const std::string& what) {
  for (std::size_t k = 0; k < 6; ++k) EXPECT_NEAR(got[k], want[k], 1e-9) << what << " coordinate " << k;
}

/// The checks of a max_error response against the oracle: sampled maxima inside the bracket, every lower bound
/// attained at its reported parameter point, whose pose is the variety's.
void expectBracket(const VerifyVariety::Request& req, const VerifyVariety::Response& res,
                   const std::array<double, 6>& sampled, Pose (*toBase)(const Pose&) = nullptr) {
  ASSERT_TRUE(res.success) << res.message;
  const std::size_t m = req.parameters;
  ASSERT_EQ(res.lower_bound_parameters.size(), 6 * m);
  ASSERT_EQ(res.lower_bound_poses.size(), 36u);
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_LE(res.lower_bound[k], res.upper_bound[k]) << k;
    EXPECT_LE(sampled[k], res.upper_bound[k] * (1 + 1e-12)) << "component " << k;
    std::vector<double> t(res.lower_bound_parameters.begin() + static_cast<long>(k * m),
                          res.lower_bound_parameters.begin() + static_cast<long>((k + 1) * m));
    for (double ti : t) {
      EXPECT_GE(ti, 0.0);
      EXPECT_LE(ti, 1.0);
    }
    const Pose inFrame = poseOf(req, t);
    Pose reported{};
    for (std::size_t i = 0; i < 6; ++i) reported[i] = res.lower_bound_poses[6 * k + i];
    expectPoseNear(reported, inFrame, "lower_bound_poses row " + std::to_string(k));
    const double attained = worstErrorAt(toBase ? toBase(inFrame) : inFrame)[k];
    EXPECT_GE(attained, res.lower_bound[k] * (1 - 1e-9)) << "component " << k;
  }
}

TEST(VerifyVariety, SurfaceVerdictsAroundTheSampledMaxima) {
  const VerifyVariety::Request base = surface(kNone);
  const std::array<double, 6> sampled = sampledMaxima(base, 41);

  const VerifyVariety::Response safe = call(surface(scaled(sampled, 1.1)));
  ASSERT_TRUE(safe.success) << safe.message;
  EXPECT_EQ(safe.verdict, "SAFE") << safe.message;
  EXPECT_DOUBLE_EQ(safe.safe_fraction, 1.0);
  EXPECT_TRUE(safe.witness_parameters.empty());

  const VerifyVariety::Request tight = surface(scaled(sampled, 0.95));
  const VerifyVariety::Response unsafe = call(tight);
  ASSERT_TRUE(unsafe.success) << unsafe.message;
  ASSERT_EQ(unsafe.verdict, "UNSAFE") << unsafe.message;
  ASSERT_TRUE(unsafe.has_witness);
  ASSERT_EQ(unsafe.witness_parameters.size(), 2u);
  for (double t : unsafe.witness_parameters) {
    EXPECT_GE(t, 0.0);
    EXPECT_LE(t, 1.0);
  }
  const Pose pose = poseOf(tight, unsafe.witness_parameters);
  expectPoseNear(to6(unsafe.witness_pose), pose, "witness_pose");
  ASSERT_GE(unsafe.witness_component, 0);
  const auto c = static_cast<std::size_t>(unsafe.witness_component);
  const double oracle = worstErrorAt(pose)[c];
  EXPECT_GT(oracle, tight.thresholds[c]);
  EXPECT_GE(oracle, unsafe.witness_error[c] * (1 - 1e-9));
  EXPECT_GT(unsafe.witness_error[c], tight.thresholds[c]);
}

TEST(VerifyVariety, SurfaceMaxErrorContainsTheSampledMaxima) {
  VerifyVariety::Request req = surface(kNone);
  req.mode = VerifyVariety::Request::MODE_MAX_ERROR;
  req.alpha = 0.01;
  const VerifyVariety::Response res = call(req);
  ASSERT_TRUE(res.success) << res.message;
  EXPECT_TRUE(res.converged);
  expectBracket(req, res, sampledMaxima(req, 41));
}

TEST(VerifyVariety, VolumeOfPosesVerdictsAndBracket) {
  const std::array<double, 6> sampled = sampledMaxima(volume(kNone), 13);
  const VerifyVariety::Response safe = call(volume(scaled(sampled, 1.1)));
  ASSERT_TRUE(safe.success) << safe.message;
  EXPECT_EQ(safe.verdict, "SAFE") << safe.message;
  const VerifyVariety::Request tight = volume(scaled(sampled, 0.95));
  const VerifyVariety::Response unsafe = call(tight);
  ASSERT_EQ(unsafe.verdict, "UNSAFE") << unsafe.message;
  ASSERT_EQ(unsafe.witness_parameters.size(), 3u);
  const auto c = static_cast<std::size_t>(unsafe.witness_component);
  EXPECT_GT(worstErrorAt(poseOf(tight, unsafe.witness_parameters))[c], tight.thresholds[c]);

  VerifyVariety::Request req = volume(kNone);
  req.mode = VerifyVariety::Request::MODE_MAX_ERROR;
  req.alpha = 0.02;
  expectBracket(req, call(req), sampled);
}

TEST(VerifyVariety, TiltedFrameIsComposedExactly) {
  // The same surface given in the tilted frame: its base-frame poses are tiltedToBase() of the frame's.
  VerifyVariety::Request req = surface(kNone);
  req.frame_id = "tilted";
  const std::array<double, 6> sampled = sampledMaxima(req, 41, tiltedToBase);
  req.mode = VerifyVariety::Request::MODE_MAX_ERROR;
  req.alpha = 0.01;
  expectBracket(req, call(req), sampled, tiltedToBase);

  // And verdicts around the frame's own maxima (they differ from the base-frame surface's).
  VerifyVariety::Request safe = surface(scaled(sampled, 1.1));
  safe.frame_id = "tilted";
  EXPECT_EQ(call(safe).verdict, "SAFE");
  VerifyVariety::Request tight = surface(scaled(sampled, 0.95));
  tight.frame_id = "tilted";
  const VerifyVariety::Response unsafe = call(tight);
  ASSERT_EQ(unsafe.verdict, "UNSAFE") << unsafe.message;
  const Pose inFrame = poseOf(tight, unsafe.witness_parameters);
  expectPoseNear(to6(unsafe.witness_pose), inFrame, "witness_pose (frame tilted)");
  const auto c = static_cast<std::size_t>(unsafe.witness_component);
  EXPECT_GT(worstErrorAt(tiltedToBase(inFrame))[c], tight.thresholds[c]);
}

void expectRefused(const VerifyVariety::Request& req, const std::string& field) {
  const VerifyVariety::Response res = call(req);
  EXPECT_FALSE(res.success) << field;
  EXPECT_NE(res.message.find(field), std::string::npos) << "expected '" << field << "' in: " << res.message;
  EXPECT_EQ(res.verdict, "");
  EXPECT_EQ(res.job_id, 0u) << field;
}

TEST(VerifyVariety, MalformedFieldsAreRefusedByNameAndTheNodeKeepsServing) {
  const std::array<double, 6> generous = {1e-3, 1e-3, 1e-3, 1e-2, 1e-2, 1e-2};
  VerifyVariety::Request r = surface(generous);
  r.parameters = 0;
  expectRefused(r, "parameters");
  r.parameters = 7;
  expectRefused(r, "parameters");
  r = surface(generous);
  r.y[1].exponents = {0, 1, 0};
  expectRefused(r, "y[1].exponents");
  r = surface(generous);
  r.yaw[1].exponents[1] = 32;
  expectRefused(r, "yaw[1].exponents[1]");
  r = surface(generous);
  r.z[0].coefficient = std::nan("");
  expectRefused(r, "z[0].coefficient");
  r = surface(generous);
  r.pitch[0].coefficient = HUGE_VAL;
  expectRefused(r, "pitch[0].coefficient");
  r = surface(generous);
  r.thresholds[4] = -1.0;
  expectRefused(r, "thresholds[4]");
  r = surface(generous);
  r.min_width = 1.0;
  expectRefused(r, "min_width");
  r = surface(generous);
  r.mode = "fastest";
  expectRefused(r, "mode");
  r = surface(generous);
  r.method = "guess";
  expectRefused(r, "method");
  r = surface(generous);
  r.geometry_splitting = "flat";
  expectRefused(r, "geometry_splitting");

  // An unknown frame: success false naming frame_id (the lookup comes before the request becomes a job: no number).
  r = surface(generous);
  r.frame_id = "nowhere";
  const VerifyVariety::Response unknown = call(r);
  EXPECT_FALSE(unknown.success);
  EXPECT_EQ(unknown.job_id, 0u);
  EXPECT_NE(unknown.message.find("frame_id"), std::string::npos) << unknown.message;

  // The node still answers.
  const VerifyVariety::Response ok = call(surface(generous));
  ASSERT_TRUE(ok.success) << ok.message;
  EXPECT_EQ(ok.verdict, "SAFE");
}

TEST(VerifyVariety, VerdictAndBoxesDescribeTheVarietyJob) {
  Latest<VerificationResult> verdict("/pkm_accuracy/verdict");
  Latest<visualization_msgs::MarkerArray> boxes("/pkm_accuracy/boxes");
  const std::array<double, 6> generous = {1e-3, 1e-3, 1e-3, 1e-2, 1e-2, 1e-2};
  const VerifyVariety::Request req = surface(generous);
  const VerifyVariety::Response res = call(req);
  ASSERT_TRUE(res.success) << res.message;
  ASSERT_EQ(res.verdict, "SAFE");

  const auto v = verdict.waitFor([&](const VerificationResult& m) { return m.job_id == res.job_id; });
  ASSERT_TRUE(v);
  EXPECT_EQ(v->region_type, "variety");
  EXPECT_EQ(v->verdict, "SAFE");
  // workspace_min / max enclose every pose of the variety (sampled by the oracle).
  for (int i = 0; i <= 10; ++i) {
    for (int j = 0; j <= 10; ++j) {
      const Pose p = poseOf(req, {i / 10.0, j / 10.0});
      for (std::size_t k = 0; k < 6; ++k) {
        EXPECT_LE(v->workspace_min[k], p[k]) << k;
        EXPECT_GE(v->workspace_max[k], p[k]) << k;
      }
    }
  }

  // ~boxes: the parameter grid, every piece green (SAFE), its points on the surface.
  const auto a = boxes.waitFor([](const visualization_msgs::MarkerArray& m) {
    for (const auto& marker : m.markers) {
      if (marker.ns == pkm_accuracy::ros_layer::kMarkerNsVariety) return true;
    }
    return false;
  });
  ASSERT_TRUE(a);
  const visualization_msgs::Marker* grid = nullptr;
  for (const auto& marker : a->markers) {
    if (marker.ns == pkm_accuracy::ros_layer::kMarkerNsVariety) grid = &marker;
  }
  ASSERT_TRUE(grid);
  EXPECT_EQ(grid->type, visualization_msgs::Marker::LINE_LIST);
  ASSERT_FALSE(grid->points.empty());
  ASSERT_EQ(grid->colors.size(), grid->points.size());
  for (const auto& c : grid->colors) EXPECT_TRUE(c.g > 0.7f && c.r < 0.5f && c.b < 0.5f);
  // The first piece starts at (u, v) = (0, 0).
  const Pose p0 = poseOf(req, {0.0, 0.0});
  EXPECT_NEAR(grid->points[0].x, p0[0], 1e-12);
  EXPECT_NEAR(grid->points[0].y, p0[1], 1e-12);
  EXPECT_NEAR(grid->points[0].z, p0[2], 1e-12);
}

// ---- the ~verify_variety action ---------------------------------------------------------------------------------

using pkm_accuracy::VerifyVarietyAction;
using pkm_accuracy::VerifyVarietyGoal;
using pkm_accuracy::VerifyVarietyResult;
using pkm_accuracy_test::bytes;
using pkm_accuracy_test::convert;
using Client = actionlib::SimpleActionClient<VerifyVarietyAction>;
using State = actionlib::SimpleClientGoalState;

Client& client() {
  static Client c("/pkm_accuracy/verify_variety", true);
  return c;
}

TEST(VarietyAction, GoalAndResultAreTheServicesRequestAndResponse) {
  EXPECT_STREQ(ros::message_traits::md5sum<VerifyVarietyGoal>(), ros::message_traits::md5sum<VerifyVariety::Request>());
  EXPECT_STREQ(ros::message_traits::md5sum<VerifyVarietyResult>(),
               ros::message_traits::md5sum<VerifyVariety::Response>());
  // Every field of a goal reaches the request, every field of an outcome the result (bytes equal to the response's).
  VerifyVariety::Request r = surface({1.5, 2.5, 3.5, 4.5, 5.5, 6.5});
  r.mode = "max_error";
  r.alpha = 0.25;
  r.time_budget = 11.5;
  r.min_width = 0.125;
  r.threads = 13;
  r.method = "precond";
  r.frame_id = "somewhere";
  r.geometry_splitting = "never";
  EXPECT_EQ(bytes(pkm_accuracy::ros_layer::toRequest(convert<VerifyVarietyGoal>(r))), bytes(r));
  const pkm_accuracy::ros_layer::WorkspaceOutcome o = pkm_accuracy_test::filledOutcome();
  VerifyVariety::Response res;
  VerifyVarietyResult result;
  pkm_accuracy::ros_layer::toResponse(o, res);
  pkm_accuracy::ros_layer::toResult(o, result);
  EXPECT_EQ(bytes(result), bytes(res));
  EXPECT_EQ(res.lower_bound_parameters, o.lower_bound_parameters);
  EXPECT_EQ(res.witness_parameters, o.witness_parameters);
  EXPECT_EQ(res.singular_parameters, o.singular_parameters);
  EXPECT_EQ(res.undecided_lower, o.undecided_parameters_lower);
  EXPECT_EQ(res.undecided_upper, o.undecided_parameters_upper);
  EXPECT_EQ(res.sensitive_parameters, o.sensitive.parameters);
  EXPECT_EQ(res.sensitive_region_lower, o.sensitive.region_lower);
  EXPECT_EQ(res.sensitive_region_upper, o.sensitive.region_upper);
  EXPECT_EQ(res.lower_bound_poses, o.lower_bound_poses);
}

TEST(VarietyAction, GoalGivesTheServicesAnswerAndMalformedGoalsAreRejected) {
  ASSERT_TRUE(client().waitForServer(ros::Duration(20.0)));
  const std::array<double, 6> sampled = sampledMaxima(surface(kNone), 41);
  const VerifyVariety::Request tight = surface(scaled(sampled, 0.95));
  const State state = client().sendGoalAndWait(convert<VerifyVarietyGoal>(tight), ros::Duration(30.0));
  ASSERT_EQ(state, State::SUCCEEDED) << state.toString() << ": " << state.getText();
  const auto result = client().getResult();
  ASSERT_TRUE(result);
  ASSERT_EQ(result->verdict, "UNSAFE") << result->message;
  const VerifyVariety::Response res = call(tight);
  EXPECT_EQ(result->witness_parameters, res.witness_parameters);
  EXPECT_EQ(result->witness_component, res.witness_component);
  EXPECT_EQ(res.job_id, result->job_id + 1);  // one job counter for every interface

  VerifyVariety::Request bad = tight;
  bad.x[1].exponents = {1};
  const State rejected = client().sendGoalAndWait(convert<VerifyVarietyGoal>(bad), ros::Duration(10.0));
  EXPECT_EQ(rejected, State::REJECTED);
  ASSERT_TRUE(client().getResult());
  EXPECT_NE(client().getResult()->message.find("x[1].exponents"), std::string::npos) << client().getResult()->message;
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "variety_test");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
