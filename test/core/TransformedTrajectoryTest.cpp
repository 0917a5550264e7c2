// domain::TransformedDomain of trajectories: waypoints given in a frame F fixed to the base frame. A slerp trajectory
// in F is the slerp trajectory through its waypoints mapped to the base frame (the geodesic and the linear position
// are invariant under a rigid transform): same poses, same verdicts, overlapping max-error brackets. A linear-RPY
// trajectory in a tilted frame is not the linear-RPY trajectory of its mapped waypoints: its pose enclosures and
// their gradient contain the exactly mapped poses (long double) and their derivatives (central differences), and
// its max-error brackets contain the maxima of independently mapped sampled poses. A null inner domain is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "RotationOracle.hpp"
#include "TestRobots.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/TransformedDomain.hpp"
#include "pkm_accuracy/core/domain/WaypointTrajectory.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"

using namespace pkm_accuracy;
using domain::RigidTransform;
using domain::TransformedDomain;
using domain::WaypointTrajectory;

namespace {

const model::GoughPlatform& ref6() {
  static const model::GoughPlatform robot(test::ref6File().geometry);
  return robot;
}

// The frame F: translated and tilted (a general rotation, not about z).
const Eigen::Vector3d kT(0.02, -0.01, 0.1);
constexpr double kRoll = -0.05, kPitch = 0.1, kYaw = 0.3;

RigidTransform tilted() { return RigidTransform::fromTranslationRpy(kT, kRoll, kPitch, kYaw); }

Eigen::Matrix3d rotationOf(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

std::array<double, 3> rpyOf(const Eigen::Matrix3d& m) {
  return {std::atan2(m(2, 1), m(2, 2)), std::atan2(-m(2, 0), std::hypot(m(0, 0), m(1, 0))),
          std::atan2(m(1, 0), m(0, 0))};
}

/// Base-frame waypoints of the reference robot (t, x, y, z, roll, pitch, yaw), inside its `paper` workspace.
const std::vector<std::array<double, 7>> kBaseRows = {{0.0, -0.08, 0.05, 0.46, 0.15, -0.10, 0.12},
                                                      {1.0, 0.02, 0.08, 0.48, -0.12, 0.15, -0.20},
                                                      {2.5, 0.10, -0.06, 0.47, 0.05, 0.20, 0.10}};

/// The waypoints `rows` (base frame) expressed in F, in double: p_F = R^T (p - t), R_F = R^T R.
std::vector<WaypointTrajectory::Waypoint> inFrame(const std::vector<std::array<double, 7>>& rows) {
  const RigidTransform tr = tilted();
  std::vector<WaypointTrajectory::Waypoint> w(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Eigen::Vector3d p = tr.rotation.transpose() * (Eigen::Vector3d(rows[i][1], rows[i][2], rows[i][3]) - kT);
    const std::array<double, 3> a = rpyOf(tr.rotation.transpose() * rotationOf(rows[i][4], rows[i][5], rows[i][6]));
    w[i].t = rows[i][0];
    w[i].pose = {p.x(), p.y(), p.z(), a[0], a[1], a[2]};
  }
  return w;
}

std::vector<WaypointTrajectory::Waypoint> waypointsOf(const std::vector<std::array<double, 7>>& rows) {
  std::vector<WaypointTrajectory::Waypoint> w(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    w[i].t = rows[i][0];
    for (int k = 0; k < 6; ++k) w[i].pose[static_cast<std::size_t>(k)] = rows[i][static_cast<std::size_t>(k) + 1];
  }
  return w;
}

TransformedDomain framed(std::vector<WaypointTrajectory::Waypoint> w, WaypointTrajectory::Interpolation i) {
  return TransformedDomain(std::make_unique<WaypointTrajectory>(std::move(w), i), tilted());
}

DVec midOf(const IVec& v) {
  DVec m(v.size());
  for (int i = 0; i < v.size(); ++i) m[i] = v[i].mid();
  return m;
}

using test::Mat3L;

/// The base-frame pose of the frame-F pose p (long double, principal RPY; roll and yaw within pi of `near`).
std::array<long double, 6> toBaseL(const DVec& p, const DVec& near) {
  const Mat3L rt = test::rpy(kRoll, kPitch, kYaw);
  std::array<long double, 6> out{};
  for (int k = 0; k < 3; ++k) out[k] = kT[k] + rt[k][0] * p[0] + rt[k][1] * p[1] + rt[k][2] * p[2];
  const Mat3L n = test::product(rt, test::rpy(p[3], p[4], p[5]));
  out[3] = std::atan2(n[2][1], n[2][2]);
  out[4] = std::atan2(-n[2][0], std::sqrt(n[0][0] * n[0][0] + n[1][0] * n[1][0]));
  out[5] = std::atan2(n[1][0], n[0][0]);
  const long double pi = std::acos(-1.0L);
  for (int k : {3, 5}) {
    while (out[k] - near[k] > pi) out[k] -= 2 * pi;
    while (out[k] - near[k] < -pi) out[k] += 2 * pi;
  }
  return out;
}

/// Largest error of every component over `samples` points u of [0, 1] (and both ends), poses by `poseOf`.
template <class PoseOf>
DVec sampledMaxima(int samples, const PoseOf& poseOf) {
  DVec best = DVec::Zero(6);
  for (int s = 0; s <= samples; ++s) {
    const DVec f = ref6().worstErrorAt(poseOf(static_cast<double>(s) / samples));
    for (int k = 0; k < 6; ++k) best[k] = std::max(best[k], f[k]);
  }
  return best;
}

verify::VerifierOptions options(verify::Mode mode, const DVec& thresholds) {
  verify::VerifierOptions o;
  o.mode = mode;
  if (mode == verify::Mode::Verify) o.thresholds = thresholds;
  o.alpha = 0.01;
  o.alpha_relative = true;
  o.threads = 1;
  o.time_limit_s = 30.0;
  return o;
}

}  // namespace

TEST(TransformedTrajectory, SlerpTrajectoryInAFrameIsTheTrajectoryOfItsMappedWaypoints) {
  const auto slerp = WaypointTrajectory::Interpolation::Slerp;
  const TransformedDomain inF = framed(inFrame(kBaseRows), slerp);
  const WaypointTrajectory base(waypointsOf(kBaseRows), slerp);
  ASSERT_FALSE(inF.aboutZ());
  EXPECT_EQ(inF.variables(), 1);
  EXPECT_EQ(inF.initialBox()[0], Interval(0.0, 1.0));
  // The same poses (up to the double rounding of the waypoints mapped to F, ~1e-16).
  for (int s = 0; s <= 200; ++s) {
    const DVec u = DVec::Constant(1, s / 200.0);
    const IVec a = inF.poseAt(u), b = base.poseAt(u);
    for (int k = 0; k < 6; ++k) EXPECT_LT(a[k].width(), 1e-12) << k;
    const DVec pa = midOf(a), pb = midOf(b);
    EXPECT_LT((pa.head(3) - pb.head(3)).norm(), 1e-12) << "u " << u[0];
    EXPECT_LT((rotationOf(pa[3], pa[4], pa[5]) - rotationOf(pb[3], pb[4], pb[5])).norm(), 1e-12) << "u " << u[0];
  }
  // The same verdicts at 10% above and 5% below the sampled maxima, and overlapping max-error brackets.
  const DVec maxima = sampledMaxima(20000, [&](double u) { return midOf(base.poseAt(DVec::Constant(1, u))); });
  for (const auto& [factor, expected] :
       {std::make_pair(1.10, verify::Verdict::Safe), std::make_pair(0.95, verify::Verdict::Unsafe)}) {
    const auto rb = verify::Verifier::run(ref6(), base, options(verify::Mode::Verify, maxima * factor));
    const auto rf = verify::Verifier::run(ref6(), inF, options(verify::Mode::Verify, maxima * factor));
    EXPECT_EQ(rb.verdict, expected) << rb.message;
    EXPECT_EQ(rf.verdict, expected) << rf.message;
    if (rf.verdict == verify::Verdict::Unsafe) {
      // The witness time's base-frame pose (the base trajectory's, an independent evaluation) violates the threshold.
      ASSERT_EQ(rf.witness.size(), 1);
      const int k = rf.witness_component;
      ASSERT_GE(k, 0);
      const DVec pose = midOf(base.poseAt(rf.witness));
      EXPECT_GT(ref6().worstErrorAt(pose)[k], maxima[k] * factor);
    }
  }
  const auto mb = verify::Verifier::run(ref6(), base, options(verify::Mode::MaxError, DVec()));
  const auto mf = verify::Verifier::run(ref6(), inF, options(verify::Mode::MaxError, DVec()));
  ASSERT_TRUE(mb.converged && mf.converged) << mb.message << " / " << mf.message;
  for (int k = 0; k < 6; ++k) {
    EXPECT_LE(mf.max_lower[k], mb.max_upper[k]) << k;
    EXPECT_LE(mb.max_lower[k], mf.max_upper[k]) << k;
    EXPECT_LE(maxima[k], mf.max_upper[k]) << k;
  }
}

TEST(TransformedTrajectory, LinearRpyTrajectoryInATiltedFrameEnclosesTheMappedPosesAndDerivatives) {
  // In F, roll, pitch and yaw are each linear in time; in the base frame the path is R_T R(rpy_F(t)), which is not
  // linear in the base-frame angles.
  const auto linear = WaypointTrajectory::Interpolation::LinearRpy;
  const std::vector<WaypointTrajectory::Waypoint> w = inFrame(kBaseRows);
  const WaypointTrajectory inner(w, linear);
  const TransformedDomain inF = framed(w, linear);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int n = 0; n < 300; ++n) {
    const double lo = unit(rng), width = std::pow(10.0, -1.0 - 3.0 * unit(rng));
    const IVec box = IVec::Constant(1, Interval(std::max(0.0, lo - width), std::min(1.0, lo + width)));
    enclosure::BoxInput view;
    inF.poseView(box, true, view);
    ASSERT_TRUE(view.hasGradient);
    const DVec centre = midOf(view.centrePose);
    for (double s : {0.0, 0.25, 0.5, 0.77, 1.0}) {
      const double u = box[0].lower() + s * (box[0].upper() - box[0].lower());
      const DVec pF = midOf(inner.poseAt(DVec::Constant(1, u)));
      const std::array<long double, 6> exact = toBaseL(pF, centre);
      for (int k = 0; k < 6; ++k) {
        // (pF is the inner enclosure's midpoint, not the exact frame-F pose: allow for its tiny width.)
        const Interval e = view.pose[k];
        EXPECT_GE(static_cast<long double>(e.upper()) + 1e-13L, exact[k]) << "u " << u << " k " << k;
        EXPECT_LE(static_cast<long double>(e.lower()) - 1e-13L, exact[k]) << "u " << u << " k " << k;
      }
      // The derivative with respect to u (central differences of the exactly mapped poses) is in the gradient's
      // enclosure, up to the difference quotient's own error.
      const double h = 1e-6;
      if (u - h < box[0].lower() || u + h > box[0].upper()) continue;
      const std::array<long double, 6> plus = toBaseL(midOf(inner.poseAt(DVec::Constant(1, u + h))), centre);
      const std::array<long double, 6> minus = toBaseL(midOf(inner.poseAt(DVec::Constant(1, u - h))), centre);
      for (int k = 0; k < 6; ++k) {
        const long double d = (plus[k] - minus[k]) / (2 * h);
        const Interval g = view.dualPose[k].gradient()[0];
        EXPECT_GE(static_cast<long double>(g.upper()) + 1e-6L, d) << "u " << u << " k " << k;
        EXPECT_LE(static_cast<long double>(g.lower()) - 1e-6L, d) << "u " << u << " k " << k;
      }
    }
  }
  // Max-error brackets contain the maxima of the independently mapped sampled poses; SAFE 10% above them.
  const DVec maxima = sampledMaxima(20000, [&](double u) {
    const DVec pF = midOf(inner.poseAt(DVec::Constant(1, u)));
    const std::array<long double, 6> b = toBaseL(pF, DVec::Zero(6));
    DVec p(6);
    for (int k = 0; k < 6; ++k) p[k] = static_cast<double>(b[k]);
    return p;
  });
  const auto m = verify::Verifier::run(ref6(), inF, options(verify::Mode::MaxError, DVec()));
  ASSERT_TRUE(m.converged) << m.message;
  for (int k = 0; k < 6; ++k) {
    EXPECT_LE(maxima[k], m.max_upper[k]) << k;
    EXPECT_GE(maxima[k], m.max_lower[k] * (1 - 1e-9) - 0.01 * m.max_upper[k]) << k;  // sampling is dense
  }
  EXPECT_EQ(verify::Verifier::run(ref6(), inF, options(verify::Mode::Verify, maxima * 1.1)).verdict,
            verify::Verdict::Safe);
}

TEST(TransformedTrajectory, RefusesANullDomain) {
  try {
    TransformedDomain d(nullptr, RigidTransform());
    FAIL() << "a null inner domain was accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("null"), std::string::npos) << e.what();
  }
}
