// rostest (verify.test): /verify_workspace answered by the core verifier on the reference robot. SAFE with generous
// thresholds, UNSAFE with a certified witness inside the workspace, the paper_40deg workspace UNSAFE, max_error
// brackets, the latched ~verdict and ~progress, and every malformed field refused naming the field while the node
// keeps serving. Every job here is decided in well under a second.
#include <atomic>
#include <cstring>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <Eigen/LU>

#include "VerifyHelpers.hpp"
#include "pkm_accuracy/Progress.h"
#include "pkm_accuracy/VerificationResult.h"
#include "pkm_accuracy/core/verify/VerifierOptions.hpp"

namespace {

using namespace pkm_accuracy_test;  // NOLINT(build/namespaces)
using pkm_accuracy::Progress;
using pkm_accuracy::VerificationResult;

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

/// Corners and centre of a box workspace (3^6 grid), for oracle checks of certified bounds.
std::vector<std::array<double, 6>> grid(const VerifyWorkspace::Request& r) {
  const double lo[6] = {r.box_min[0], r.box_min[1], r.box_min[2], r.roll_min, r.pitch_min, r.yaw_min};
  const double hi[6] = {r.box_max[0], r.box_max[1], r.box_max[2], r.roll_max, r.pitch_max, r.yaw_max};
  std::vector<std::array<double, 6>> out;
  for (int idx = 0; idx < 729; ++idx) {
    std::array<double, 6> p{};
    int rest = idx;
    for (std::size_t i = 0; i < 6; ++i, rest /= 3) p[i] = lo[i] + (hi[i] - lo[i]) * (rest % 3) / 2.0;
    out.push_back(p);
  }
  return out;
}

/// A converged max-error answer: every component's bracket [lower, upper] is finite, at most alpha * lower wide, its
/// lower bound attained (by the double-precision oracle) at its pose inside the workspace, and no pose of grid() above
/// its upper bound.
void expectBracketsHold(const VerifyWorkspace::Request& req, const VerifyWorkspace::Response& r, double alpha) {
  ASSERT_EQ(r.lower_bound_poses.size(), 36u);
  const auto samples = grid(req);
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_GT(r.lower_bound[k], 0.0) << k;
    EXPECT_LE(r.lower_bound[k], r.upper_bound[k]) << k;
    EXPECT_TRUE(std::isfinite(r.upper_bound[k])) << k;
    EXPECT_LE(r.upper_bound[k] - r.lower_bound[k], alpha * r.lower_bound[k] * (1.0 + 1e-9)) << k;
    std::array<double, 6> pose{};
    for (std::size_t i = 0; i < 6; ++i) pose[i] = r.lower_bound_poses[6 * k + i];
    EXPECT_TRUE(poseInWorkspace(pose, req)) << k;
    EXPECT_GE(worstErrorAt(pose)[k], r.lower_bound[k] * (1.0 - 1e-9)) << k;
    for (const auto& p : samples) ASSERT_LE(worstErrorAt(p)[k], r.upper_bound[k]) << k;
  }
}

TEST(VerifyWorkspace, SafeWithGenerousThresholds) {
  const auto req = smallRequest(kGenerous);
  const auto r = verify(req);
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.verdict, "SAFE") << r.message;
  EXPECT_EQ(r.reason, "");
  EXPECT_FALSE(r.busy);
  EXPECT_GT(r.job_id, 0u);
  EXPECT_FALSE(r.has_witness);
  EXPECT_EQ(r.witness_component, -1);
  EXPECT_GE(r.boxes, 1u);
  EXPECT_EQ(r.safe_fraction, 1.0);
  EXPECT_EQ(r.undecided_fraction, 0.0);
  EXPECT_EQ(r.undecided_boxes, 0u);
  EXPECT_TRUE(r.lower_bound_poses.empty());
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(r.lower_bound[k], 0.0) << k;
    EXPECT_EQ(r.upper_bound[k], kGenerous[k]) << k;  // SAFE proves E_k <= threshold_k
  }
  // No anchor uncertainty on this node: the uncertainty fields are empty.
  EXPECT_EQ(r.geometry_switches, 0u);
  EXPECT_EQ(r.geometry_splits, 0u);
  EXPECT_EQ(r.sensitive_poses, 0u);
  EXPECT_EQ(r.sensitive_component, -1);
  EXPECT_TRUE(r.sensitive_failing_geometry.empty());
  // The geometry options are accepted (and change nothing without uncertainty).
  for (const char* splitting : {"auto", "never", "always"}) {
    auto other = req;
    other.geometry_splitting = splitting;
    const auto o = verify(other);
    ASSERT_TRUE(o.success) << splitting << ": " << o.message;
    EXPECT_EQ(o.verdict, "SAFE") << splitting;
    EXPECT_EQ(o.geometry_splits, 0u) << splitting;
  }
  // Oracle: no sampled pose exceeds a threshold.
  for (const auto& p : grid(req)) {
    const auto f = worstErrorAt(p);
    for (std::size_t k = 0; k < 6; ++k) ASSERT_LE(f[k], kGenerous[k]) << k;
  }
}

TEST(VerifyWorkspace, UnsafeWithTinyThresholdsHasAWitnessInsideTheWorkspace) {
  const auto req = smallRequest(kTiny);
  const auto r = verify(req);
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.verdict, "UNSAFE") << r.message;
  EXPECT_EQ(r.reason, "");
  ASSERT_TRUE(r.has_witness);
  ASSERT_GE(r.witness_component, 0);
  ASSERT_LT(r.witness_component, 6);
  const auto c = static_cast<std::size_t>(r.witness_component);
  const auto pose = to6(r.witness_pose);
  EXPECT_TRUE(poseInWorkspace(pose, req));
  EXPECT_GT(r.witness_error[c], kTiny[c]);
  // Oracle: the worst error at the witness (double, independent) is at least the certified lower bound.
  const auto f = worstErrorAt(pose);
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_GE(f[k], r.witness_error[k] * (1.0 - 1e-9)) << k;
    EXPECT_EQ(r.lower_bound[k], r.witness_error[k]) << k;
    EXPECT_EQ(r.upper_bound[k], kInf) << k;
  }
  EXPECT_GT(f[c], kTiny[c]);
}

TEST(VerifyWorkspace, Paper40DegIsUnsafe) {
  const auto req = boxRequest(0.15, 0.45, 0.50, k40deg, kPaper, "verify");
  const ros::WallTime t0 = ros::WallTime::now();
  const auto r = verify(req);
  EXPECT_LT((ros::WallTime::now() - t0).toSec(), 10.0);
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.verdict, "UNSAFE") << r.message;
  ASSERT_TRUE(r.has_witness);
  const auto pose = to6(r.witness_pose);
  EXPECT_TRUE(poseInWorkspace(pose, req));
  const auto c = static_cast<std::size_t>(r.witness_component);
  ASSERT_LT(c, 6u);
  EXPECT_GT(r.witness_error[c], kPaper[c]);
  EXPECT_GT(worstErrorAt(pose)[c], kPaper[c]);
}

TEST(VerifyWorkspace, SingularWorkspaceIsUnsafeWhateverTheThresholds) {
  // paper_40deg contains singular poses: with thresholds no pose can be certified above, the verdict is still UNSAFE,
  // through the certified sign change of det J^-1 between the two poses of singular_poses (checked here in double).
  auto req = boxRequest(0.15, 0.45, 0.50, k40deg, {1e15, 1e15, 1e15, 1e15, 1e15, 1e15}, "verify");
  const auto r = verify(req);
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.verdict, "UNSAFE") << r.message;
  ASSERT_TRUE(r.singular) << r.message;
  EXPECT_NE(r.message.find("singular"), std::string::npos) << r.message;
  std::array<double, 6> a, b;
  for (std::size_t i = 0; i < 6; ++i) {
    a[i] = r.singular_poses[i];
    b[i] = r.singular_poses[i + 6];
  }
  EXPECT_TRUE(poseInWorkspace(a, req));
  EXPECT_TRUE(poseInWorkspace(b, req));
  auto det = [](const std::array<double, 6>& p) {
    pkm_accuracy::DVec q(6);
    for (int i = 0; i < 6; ++i) q[i] = p[static_cast<std::size_t>(i)];
    return oracleModel().inverseJacobian(q).determinant();
  };
  EXPECT_LT(det(a) * det(b), 0.0);
  // Max-error mode: the maximum is unbounded, and the job ends at once.
  req.mode = "max_error";
  req.thresholds = {0, 0, 0, 0, 0, 0};
  const auto m = verify(req);
  ASSERT_TRUE(m.success) << m.message;
  EXPECT_TRUE(m.singular) << m.message;
  EXPECT_FALSE(m.converged);
  for (std::size_t k = 0; k < 6; ++k) EXPECT_EQ(m.upper_bound[k], kInf) << k;
  EXPECT_LT(m.seconds, 1.0);
}

TEST(VerifyWorkspace, MaxErrorBracketsEveryComponent) {
  auto req = smallRequest(kNone, "max_error");
  req.alpha = 0.2;
  const auto r = verify(req);
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.verdict, "UNDECIDED");
  EXPECT_EQ(r.reason, "no_thresholds");
  EXPECT_TRUE(r.converged) << r.message;
  expectBracketsHold(req, r, 0.2);
}

TEST(VerifyWorkspace, MaxErrorOverThePaperWorkspaceReportsItsSearch) {
  // The whole paper workspace (+-15 deg) to the default alpha (1%): about 4 000 boxes, well under a second on two
  // threads; the search statistics are the core's, carried by the bridge (hopeless boxes are split without an
  // enclosure on this job whatever the thread count: more than 500 of them).
  auto req = boxRequest(0.15, 0.45, 0.50, k15deg, kNone, "max_error");
  req.threads = 2;
  const auto r = verify(req);
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_TRUE(r.converged) << r.message;
  EXPECT_EQ(r.reason, "no_thresholds");
  EXPECT_GT(r.boxes, 1000u);
  EXPECT_GT(r.unenclosed_boxes, 0u);
  EXPECT_LE(r.unenclosed_boxes, r.boxes);
  expectBracketsHold(req, r, 0.01);
}

TEST(VerifyWorkspace, MaxErrorWithThresholdsGivesAVerdict) {
  auto req = smallRequest(kGenerous, "max_error");
  req.alpha = 0.5;
  const auto r = verify(req);
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.verdict, "SAFE") << r.message;
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_LE(r.lower_bound[k], r.upper_bound[k]) << k;
    EXPECT_LE(r.upper_bound[k], kGenerous[k]) << k;
  }
}

TEST(VerifyWorkspace, OtherRegionsAndMethods) {
  // Every enclosure method (on a 2 mm / 2 mrad box: the paper's baseline method is too coarse to certify the 2 cm box
  // quickly).
  for (const char* method : {"mean_value", "precond", "paper_baseline"}) {
    auto req = boxRequest(0.001, 0.47, 0.471, 0.001, kGenerous, "verify");
    req.time_budget = 10.0;
    req.method = method;
    const auto r = verify(req);
    ASSERT_TRUE(r.success) << method << ": " << r.message;
    EXPECT_EQ(r.verdict, "SAFE") << method;
  }
  auto sphere = smallRequest(kGenerous);
  sphere.region_type = "sphere";
  sphere.center.z = 0.475;
  sphere.radius = 0.005;
  auto r = verify(sphere);
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.verdict, "SAFE");

  auto cylinder = smallRequest(kTiny);
  cylinder.region_type = "cylinder";
  cylinder.radius = 0.005;
  cylinder.z_min = 0.47;
  cylinder.z_max = 0.48;
  r = verify(cylinder);
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.verdict, "UNSAFE");
  ASSERT_TRUE(r.has_witness);
  EXPECT_LE(std::hypot(r.witness_pose[0], r.witness_pose[1]), 0.005);

  auto poly = smallRequest(kGenerous);
  poly.region_type = "polyhedron";
  poly.halfspace_normals.resize(1);
  poly.halfspace_normals[0].x = 1.0;
  poly.halfspace_normals[0].y = 1.0;
  poly.halfspace_offsets = {-0.005};  // x + y <= -0.005
  r = verify(poly);
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.verdict, "SAFE");
  // (A region whose bounding-box centre is outside it, like this one, is not searched for witnesses well by the
  // verifier yet: with tiny thresholds it ends UNDECIDED on its time budget. With the centre inside:)
  poly.halfspace_offsets = {0.005};  // x + y <= 0.005
  poly.thresholds = {1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-6};
  poly.time_budget = 5.0;
  r = verify(poly);
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.verdict, "UNSAFE") << r.message;
  ASSERT_TRUE(r.has_witness);
  EXPECT_LE(r.witness_pose[0] + r.witness_pose[1], 0.005);

  // Angle ranges up to 2 pi: a whole turn, also written in [0, 2 pi], is a range like any other.
  auto turn = smallRequest(kGenerous);
  turn.yaw_min = 0.0;
  turn.yaw_max = 6.283185307179586;
  turn.time_budget = 2.0;
  r = verify(turn);
  EXPECT_TRUE(r.success) << r.message;

  // .inf = this component is not checked.
  auto inf = smallRequest(kTiny);
  inf.thresholds = {kInf, kInf, kInf, kInf, kInf, kInf};
  r = verify(inf);
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.verdict, "SAFE") << r.message;
}

TEST(VerifyWorkspace, VerdictIsLatched) {
  const auto r = verify(smallRequest(kTiny));
  ASSERT_TRUE(r.success) << r.message;
  // A subscriber that appears after the job still receives its result.
  ros::NodeHandle nh;
  std::mutex m;
  std::vector<VerificationResult> got;
  ros::Subscriber sub = nh.subscribe<VerificationResult>("/pkm_accuracy/verdict", 10,
                                                         [&](const pkm_accuracy::VerificationResultConstPtr& msg) {
                                                           std::lock_guard<std::mutex> lock(m);
                                                           got.push_back(*msg);
                                                         });
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10.0);
  while (ros::WallTime::now() < deadline) {
    {
      std::lock_guard<std::mutex> lock(m);
      if (!got.empty()) break;
    }
    ros::WallDuration(0.05).sleep();
  }
  std::lock_guard<std::mutex> lock(m);
  ASSERT_FALSE(got.empty()) << "no latched message on /pkm_accuracy/verdict";
  const VerificationResult& v = got.back();
  EXPECT_EQ(v.job_id, r.job_id);
  EXPECT_EQ(v.header.frame_id, "base_link");
  EXPECT_TRUE(v.success);
  EXPECT_EQ(v.verdict, "UNSAFE");
  EXPECT_EQ(v.mode, "verify");
  EXPECT_EQ(v.method, pkm_accuracy::verify::VerifierOptions().method);  // the verifier's default
  EXPECT_EQ(v.region_type, "box");
  EXPECT_EQ(v.workspace_min[2], 0.47);
  EXPECT_EQ(v.workspace_max[5], 0.01);
  EXPECT_EQ(v.thresholds[0], 1e-6);
  EXPECT_TRUE(v.has_witness);
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(v.witness_pose[k], r.witness_pose[k]);
    EXPECT_EQ(v.lower_bound[k], r.lower_bound[k]);
  }
  EXPECT_EQ(v.message, r.message);
  EXPECT_EQ(v.geometry_splitting, "auto");  // "" in the request
  EXPECT_EQ(v.sensitive_poses, 0u);
  EXPECT_EQ(v.sensitive_component, -1);
}

TEST(VerifyWorkspace, ProgressIsPublishedWhileAJobRuns) {
  ros::NodeHandle nh;
  std::mutex m;
  std::vector<Progress> got;
  ros::Subscriber sub =
      nh.subscribe<Progress>("/pkm_accuracy/progress", 100, [&](const pkm_accuracy::ProgressConstPtr& msg) {
        std::lock_guard<std::mutex> lock(m);
        got.push_back(*msg);
      });
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10.0);
  while (sub.getNumPublishers() == 0 && ros::WallTime::now() < deadline) ros::WallDuration(0.05).sleep();
  ASSERT_GT(sub.getNumPublishers(), 0u);
  ros::WallDuration(0.3).sleep();  // let the connection settle
  // About a second of work (max_error over the paper workspace at +-38 deg to 1%, stopped by its time budget: it
  // takes ~8 s on one thread of a fast machine; at +-15 deg it converges in 0.4 s, and +-40 deg contains singular
  // poses, which end a max_error job at once), ~progress_rate = 20 Hz.
  auto req = boxRequest(0.15, 0.45, 0.50, k38deg, kNone, "max_error");
  req.time_budget = 1.0;
  req.threads = 1;
  const auto r = verify(req);
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.verdict, "UNDECIDED");
  EXPECT_EQ(r.reason, "time_budget");
  for (std::size_t k = 0; k < 6; ++k) EXPECT_LE(r.lower_bound[k], r.upper_bound[k]) << k;
  // (How many boxes were split without an enclosure depends on how far 1 s gets: none in the first ~4 000 boxes of
  // this job. The count is checked on a deterministic job in MaxErrorOverThePaperWorkspaceReportsItsSearch.)
  EXPECT_LE(r.unenclosed_boxes, r.boxes);
  ros::WallDuration(0.5).sleep();
  std::lock_guard<std::mutex> lock(m);
  std::vector<Progress> mine;
  for (const auto& p : got)
    if (p.job_id == r.job_id) mine.push_back(p);
  ASSERT_GE(mine.size(), 3u) << "expected several ~progress messages for job " << r.job_id;
  for (std::size_t i = 0; i < mine.size(); ++i) {
    EXPECT_EQ(mine[i].mode, "max_error");
    EXPECT_EQ(mine[i].header.frame_id, "base_link");
    EXPECT_EQ(mine[i].lower.size(), 6u);
    EXPECT_EQ(mine[i].upper.size(), 6u);
    if (i > 0) {
      EXPECT_GE(mine[i].boxes, mine[i - 1].boxes);
      EXPECT_GE(mine[i].seconds, mine[i - 1].seconds);
    }
  }
  // The last one carries the final statistics.
  EXPECT_EQ(mine.back().boxes, r.boxes);
  EXPECT_EQ(mine.back().lower[0], r.lower_bound[0]);
}

struct BadCase {
  const char* field;
  void (*mutate)(VerifyWorkspace::Request&);
};

TEST(VerifyWorkspace, EveryMalformedFieldIsRefusedNamingItAndTheNodeKeepsServing) {
  const BadCase cases[] = {
      {"region_type", [](VerifyWorkspace::Request& r) { r.region_type = "cube"; }},
      {"region_type", [](VerifyWorkspace::Request& r) { r.region_type = ""; }},
      {"box_min[0]", [](VerifyWorkspace::Request& r) { r.box_min[0] = kNaN; }},
      {"box_min[2]", [](VerifyWorkspace::Request& r) { r.box_min[2] = 0.6; }},  // inverted
      {"box_max[1]", [](VerifyWorkspace::Request& r) { r.box_max[1] = kInf; }},
      {"center.y",
       [](VerifyWorkspace::Request& r) {
         r.region_type = "sphere";
         r.radius = 0.01;
         r.center.y = kNaN;
       }},
      {"radius",
       [](VerifyWorkspace::Request& r) {
         r.region_type = "sphere";
         r.radius = 0.0;
       }},
      {"radius",
       [](VerifyWorkspace::Request& r) {
         r.region_type = "cylinder";
         r.radius = -1.0;
       }},
      {"z_min",
       [](VerifyWorkspace::Request& r) {
         r.region_type = "cylinder";
         r.radius = 0.01;
         r.z_min = 0.5;
         r.z_max = 0.4;
       }},
      {"halfspace_offsets",
       [](VerifyWorkspace::Request& r) {  // wrong array size: 2 normals, 1 offset
         r.region_type = "polyhedron";
         r.halfspace_normals.resize(2);
         r.halfspace_normals[0].x = r.halfspace_normals[1].z = 1.0;
         r.halfspace_offsets = {0.1};
       }},
      {"halfspace_normals",
       [](VerifyWorkspace::Request& r) {  // wrong array size: none
         r.region_type = "polyhedron";
       }},
      {"halfspace_normals[0]",
       [](VerifyWorkspace::Request& r) {
         r.region_type = "polyhedron";
         r.halfspace_normals.resize(1);
         r.halfspace_offsets = {0.1};
       }},
      {"halfspace_offsets[0]",
       [](VerifyWorkspace::Request& r) {
         r.region_type = "polyhedron";
         r.halfspace_normals.resize(1);
         r.halfspace_normals[0].z = 1.0;
         r.halfspace_offsets = {kNaN};
       }},
      {"halfspace_normals", [](VerifyWorkspace::Request& r) { r.halfspace_normals.resize(1); }},  // not polyhedron
      {"roll_min", [](VerifyWorkspace::Request& r) { r.roll_min = kNaN; }},
      {"pitch_min", [](VerifyWorkspace::Request& r) { r.pitch_min = 1.0; }},  // inverted
      {"yaw_max", [](VerifyWorkspace::Request& r) { r.yaw_max = kInf; }},
      {"roll_max", [](VerifyWorkspace::Request& r) { r.roll_max = 7.0; }},     // beyond 2 pi
      {"yaw_min", [](VerifyWorkspace::Request& r) { r.yaw_min = -15.0; }},     // degrees for radians
      {"pitch_max", [](VerifyWorkspace::Request& r) { r.pitch_max = 90.0; }},  // degrees for radians
      {"halfspace_offsets",
       [](VerifyWorkspace::Request& r) {  // x + y <= -0.03 misses the box x, y in [-0.01, 0.01]: empty
         r.region_type = "polyhedron";
         r.halfspace_normals.resize(1);
         r.halfspace_normals[0].x = r.halfspace_normals[0].y = 1.0;
         r.halfspace_offsets = {-0.03};
       }},
      {"thresholds[0]", [](VerifyWorkspace::Request& r) { r.thresholds[0] = kNaN; }},
      {"thresholds[3]", [](VerifyWorkspace::Request& r) { r.thresholds[3] = -1.0; }},
      {"thresholds[0]", [](VerifyWorkspace::Request& r) { r.thresholds = {0, 0, 0, 0, 0, 0}; }},  // zero, verify
      {"thresholds[5]", [](VerifyWorkspace::Request& r) { r.thresholds[5] = 0.0; }},
      {"thresholds[2]",
       [](VerifyWorkspace::Request& r) {
         r.mode = "max_error";
         r.thresholds[2] = 0.0;  // max_error: all 0 or all > 0
       }},
      {"mode", [](VerifyWorkspace::Request& r) { r.mode = "fast"; }},
      {"alpha", [](VerifyWorkspace::Request& r) { r.alpha = -0.5; }},
      {"alpha", [](VerifyWorkspace::Request& r) { r.alpha = kNaN; }},
      {"time_budget", [](VerifyWorkspace::Request& r) { r.time_budget = -2.0; }},
      {"time_budget", [](VerifyWorkspace::Request& r) { r.time_budget = kInf; }},
      {"min_width", [](VerifyWorkspace::Request& r) { r.min_width = kNaN; }},
      {"threads", [](VerifyWorkspace::Request& r) { r.threads = 100000; }},
      {"method", [](VerifyWorkspace::Request& r) { r.method = "magic"; }},
      {"geometry_splitting", [](VerifyWorkspace::Request& r) { r.geometry_splitting = "sometimes"; }},
      {"geometry_splitting", [](VerifyWorkspace::Request& r) { r.geometry_splitting = "Auto"; }},
  };
  for (const auto& c : cases) {
    VerifyWorkspace::Request req = smallRequest(kGenerous);
    c.mutate(req);
    const auto r = verify(req);
    EXPECT_FALSE(r.success) << c.field;
    EXPECT_NE(r.message.find(c.field), std::string::npos)
        << "expected the message to name " << c.field << ": " << r.message;
    EXPECT_EQ(r.verdict, "") << c.field;
    EXPECT_EQ(r.job_id, 0u) << c.field;
    EXPECT_FALSE(r.busy) << c.field;
  }
  // A frame unknown to tf2 (no transform published here): refused after the ~tf_timeout lookup, naming it (frames.test
  // covers transformed requests).
  VerifyWorkspace::Request req = smallRequest(kGenerous);
  req.frame_id = "world";
  const auto unknown = verify(req);
  EXPECT_FALSE(unknown.success);
  EXPECT_EQ(unknown.verdict, "");
  EXPECT_NE(unknown.message.find("frame_id: no transform from frame \"world\" to the base frame \"base_link\""),
            std::string::npos)
      << unknown.message;
  req.frame_id = "base_link";  // the base frame by name is fine
  EXPECT_TRUE(verify(req).success);
  // Still serving.
  const auto ok = verify(smallRequest(kGenerous));
  EXPECT_TRUE(ok.success) << ok.message;
  EXPECT_EQ(ok.verdict, "SAFE");
  EXPECT_TRUE(describe().success);
}

// A client that sends a request with the right type and checksum but a truncated body (the fixed-size arrays cannot
// be given the wrong size through the generated C++ type): roscpp cannot deserialize it and reports a transport
// error; the node must survive.
struct TruncatedRequest {
  std::vector<std::uint8_t> bytes;
};
struct TruncatedService {
  typedef TruncatedRequest Request;
  typedef VerifyWorkspace::Response Response;
  Request request;
  Response response;
};

}  // namespace

namespace ros {
namespace message_traits {
template <>
struct MD5Sum<TruncatedRequest> {
  static const char* value() { return MD5Sum<pkm_accuracy::VerifyWorkspaceRequest>::value(); }
  static const char* value(const TruncatedRequest&) { return value(); }
};
template <>
struct DataType<TruncatedRequest> {
  static const char* value() { return DataType<pkm_accuracy::VerifyWorkspaceRequest>::value(); }
  static const char* value(const TruncatedRequest&) { return value(); }
};
}  // namespace message_traits
namespace service_traits {
template <>
struct MD5Sum<TruncatedService> {
  static const char* value() { return MD5Sum<pkm_accuracy::VerifyWorkspace>::value(); }
  static const char* value(const TruncatedService&) { return value(); }
};
template <>
struct DataType<TruncatedService> {
  static const char* value() { return DataType<pkm_accuracy::VerifyWorkspace>::value(); }
  static const char* value(const TruncatedService&) { return value(); }
};
}  // namespace service_traits
namespace serialization {
template <>
struct Serializer<TruncatedRequest> {
  template <typename Stream>
  inline static void write(Stream& stream, const TruncatedRequest& m) {
    if (!m.bytes.empty())
      std::memcpy(stream.advance(static_cast<uint32_t>(m.bytes.size())), m.bytes.data(), m.bytes.size());
  }
  inline static uint32_t serializedLength(const TruncatedRequest& m) { return static_cast<uint32_t>(m.bytes.size()); }
};
}  // namespace serialization
}  // namespace ros

namespace {

TEST(VerifyWorkspace, TruncatedRequestIsATransportErrorAndTheNodeSurvives) {
  const VerifyWorkspace::Request full = smallRequest(kGenerous);
  const uint32_t n = ros::serialization::serializationLength(full);
  std::vector<std::uint8_t> buffer(n);
  ros::serialization::OStream out(buffer.data(), n);
  ros::serialization::serialize(out, full);
  TruncatedService srv;
  // Cut inside the thresholds (they come after the region and the angles): as if float64[6] had 2 entries.
  srv.request.bytes.assign(buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(n / 2));
  ros::NodeHandle nh;
  ros::ServiceClient client = nh.serviceClient<TruncatedService>(kVerifyService);
  EXPECT_FALSE(client.call(srv));
  const auto ok = verify(smallRequest(kGenerous));
  EXPECT_TRUE(ok.success) << ok.message;
  EXPECT_EQ(ok.verdict, "SAFE");
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "verify_test");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(1);  // subscriber callbacks (~verdict, ~progress)
  spinner.start();
  return RUN_ALL_TESTS();
}
