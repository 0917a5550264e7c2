// domain::TransformedDomain of a Workspace: a workspace in a frame F fixed to the base frame. The identity transform is
// the workspace itself (bit for bit); the pose enclosures contain the exactly mapped poses (long double reference) and
// the gradient is the transform's; the verifier gives the same verdicts and overlapping max-error brackets as on the
// equivalent base-frame workspace; unsupported or invalid transforms are refused with a message saying why.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "RotationOracle.hpp"
#include "TestRobots.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/TransformedDomain.hpp"
#include "pkm_accuracy/core/domain/Workspace.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"

using namespace pkm_accuracy;
using domain::RigidTransform;
using domain::TransformedDomain;
using domain::Workspace;

namespace {

/// The workspace ws in the frame whose pose in the base frame is t.
TransformedDomain transformed(Workspace ws, const RigidTransform& t) {
  return TransformedDomain(std::make_unique<Workspace>(std::move(ws)), t);
}

bool identical(const Interval& a, const Interval& b) { return a.lower() == b.lower() && a.upper() == b.upper(); }

/// A small box workspace of the reference robot: x, y in [-0.01, 0.01], z in [0.47, 0.48] (m), angles +-0.01 rad.
Workspace smallBox(double dx = 0.0, double dy = 0.0, double dz = 0.0, double dyaw = 0.0) {
  return Workspace::fromRanges({Interval(-0.01 + dx, 0.01 + dx), Interval(-0.01 + dy, 0.01 + dy),
                                Interval(0.47 + dz, 0.48 + dz), Interval(-0.01, 0.01), Interval(-0.01, 0.01),
                                Interval(-0.01 + dyaw, 0.01 + dyaw)});
}

using test::Mat3L;
using test::product;
using test::rpy;

verify::VerifierOptions verifyOptions(const DVec& thresholds) {
  verify::VerifierOptions o;
  o.thresholds = thresholds;
  o.threads = 1;
  o.time_limit_s = 30.0;
  return o;
}

DVec six(double a, double b) { return (DVec(6) << a, a, a, b, b, b).finished(); }

/// Maximum of every component over random points of a domain (points of its initial box inside its region).
DVec sampledMaxima(const model::RobotModel& robot, const domain::Domain& d, int samples, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  DVec best = DVec::Zero(robot.dof());
  for (int s = 0; s < samples; ++s) {
    const DVec t = test::randomPoint(d.initialBox(), rng);
    IVec thin(6);
    for (int i = 0; i < 6; ++i) thin[i] = Interval(t[i]);
    if (d.classify(thin) != domain::Containment::Inside) continue;
    const IVec pose = d.poseAt(t);
    DVec p(6);
    for (int i = 0; i < 6; ++i) p[i] = pose[i].mid();
    const DVec f = robot.worstErrorAt(p);
    for (int k = 0; k < robot.dof(); ++k) best[k] = std::max(best[k], f[k]);
  }
  return best;
}

}  // namespace

TEST(TransformedWorkspace, IdentityTransformIsTheWorkspaceItself) {
  const Workspace ws = smallBox();
  const TransformedDomain tw = transformed(ws, RigidTransform());
  EXPECT_EQ(tw.yawOffset(), 0.0);
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    IVec box(6);
    for (int i = 0; i < 6; ++i) {
      const DVec a = test::randomPoint(ws.initialBox(), rng), b = test::randomPoint(ws.initialBox(), rng);
      box[i] = Interval::hullOf(a[i], b[i]);
    }
    enclosure::BoxInput x, y;
    ws.poseView(box, true, x);
    tw.poseView(box, true, y);
    ASSERT_EQ(y.variables, 6);
    ASSERT_TRUE(y.hasGradient);
    for (int i = 0; i < 6; ++i) {
      EXPECT_TRUE(identical(x.pose[i], y.pose[i])) << i;
      EXPECT_TRUE(identical(x.centrePose[i], y.centrePose[i])) << i;
      EXPECT_TRUE(identical(x.deviation[i], y.deviation[i])) << i;
      EXPECT_TRUE(identical(x.dualPose[i].value(), y.dualPose[i].value())) << i;
      for (int j = 0; j < 6; ++j) EXPECT_TRUE(identical(x.dualPose[i].d(j), y.dualPose[i].d(j))) << i << " " << j;
    }
    EXPECT_EQ(ws.classify(box), tw.classify(box));
  }
  // Same search, same result.
  const io::RobotFile file = test::ref6File();
  const model::GoughPlatform robot(file.geometry);
  const auto a = verify::Verifier::run(robot, ws, verifyOptions(six(1e-3, 1e-2)));
  const auto b = verify::Verifier::run(robot, tw, verifyOptions(six(1e-3, 1e-2)));
  EXPECT_EQ(a.verdict, verify::Verdict::Safe) << a.message;
  EXPECT_EQ(b.verdict, a.verdict) << b.message;
  EXPECT_EQ(b.stats.boxes, a.stats.boxes);
}

TEST(TransformedWorkspace, EnclosesTheExactlyMappedPosesWithTheTransformsGradient) {
  const Workspace ws = smallBox();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> angle(-3.2, 3.2), offset(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    const double a = trial == 0 ? 1.5707963267948966 : angle(rng);
    const Eigen::Vector3d t(offset(rng), offset(rng), offset(rng));
    const TransformedDomain tw = transformed(ws, RigidTransform::fromTranslationYaw(t, a));
    EXPECT_EQ(tw.yawOffset(), std::atan2(std::sin(a), std::cos(a)));
    const long double ca = std::cos(static_cast<long double>(tw.yawOffset()));
    const long double sa = std::sin(static_cast<long double>(tw.yawOffset()));
    for (int b = 0; b < 20; ++b) {
      const IVec box = test::centredSubBox(ws.initialBox(), 0.3);
      IVec sub(6);
      const DVec c = test::randomPoint(box, rng);
      for (int i = 0; i < 6; ++i) sub[i] = Interval::hullOf(c[i], test::randomPoint(box, rng)[i]);
      enclosure::BoxInput in;
      tw.poseView(sub, true, in);
      // Exact gradient of the map: d(x', y')/d(x, y) = Rz(a), the other coordinates pass through.
      const long double jac[6][6] = {{ca, -sa, 0, 0, 0, 0}, {sa, ca, 0, 0, 0, 0}, {0, 0, 1, 0, 0, 0},
                                     {0, 0, 0, 1, 0, 0},    {0, 0, 0, 0, 1, 0},   {0, 0, 0, 0, 0, 1}};
      for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j) {
          const Interval& g = in.dualPose[i].d(j);
          EXPECT_TRUE(g.lower() <= jac[i][j] && jac[i][j] <= g.upper()) << i << " " << j << " " << g;
          EXPECT_LT(g.width(), 1e-15);
        }
      }
      // Points of the box map into the enclosures (pose and dualPose value), the centre into centrePose.
      for (int s = 0; s < 20; ++s) {
        const DVec p = s == 0 ? domain::centreOf(sub) : test::randomPoint(sub, rng);
        const long double x = t.x() + ca * p[0] - sa * p[1];
        const long double y = t.y() + sa * p[0] + ca * p[1];
        const long double mapped[6] = {x,    y,    t.z() + static_cast<long double>(p[2]),
                                       p[3], p[4], static_cast<long double>(p[5]) + tw.yawOffset()};
        const IVec at = tw.poseAt(p);
        for (int i = 0; i < 6; ++i) {
          EXPECT_TRUE(in.pose[i].lower() <= mapped[i] && mapped[i] <= in.pose[i].upper()) << i;
          EXPECT_TRUE(in.dualPose[i].value().lower() <= mapped[i] && mapped[i] <= in.dualPose[i].value().upper());
          EXPECT_TRUE(at[i].lower() <= mapped[i] && mapped[i] <= at[i].upper()) << i;
          EXPECT_LT(at[i].width(), 1e-14) << i;
          if (s == 0) {
            EXPECT_TRUE(in.centrePose[i].lower() <= mapped[i] && mapped[i] <= in.centrePose[i].upper()) << i;
          }
        }
      }
      for (int i = 0; i < 6; ++i) EXPECT_TRUE(sub[i].isSubsetOf(in.deviation[i] + Interval(sub[i].mid())));
    }
  }
}

TEST(TransformedWorkspace, YawOffsetComposesTheOrientationExactly) {
  // Rz(a) Rz(yaw) Ry(pitch) Rx(roll) = Rz(a + yaw) Ry(pitch) Rx(roll): the base-frame orientation of the domain.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int trial = 0; trial < 100; ++trial) {
    const long double a = u(rng), r = u(rng), p = u(rng), y = u(rng);
    const Mat3L lhs = product(rpy(0, 0, a), rpy(r, p, y));
    const Mat3L rhs = rpy(r, p, a + y);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) EXPECT_LT(std::abs(lhs[i][j] - rhs[i][j]), 1e-17L) << i << " " << j;
  }
}

TEST(TransformedWorkspace, SameVerdictsAsTheEquivalentBaseFrameWorkspace) {
  const io::RobotFile file = test::ref6File();
  const model::GoughPlatform robot(file.geometry);
  // A vertical cylinder is mapped to a vertical cylinder by any translation + rotation about z: the two
  // workspaces below are the same set of base-frame poses.
  const double a = 0.7;
  const Eigen::Vector3d t(0.03, -0.02, 0.1);
  const Eigen::Vector2d centreBase(0.01, -0.005);
  const Eigen::Vector2d centreFrame = Eigen::Rotation2Dd(-a) * (centreBase - t.head<2>());
  const std::array<Interval, 3> angles = {Interval(-0.01, 0.01), Interval(-0.01, 0.01), Interval(-0.01, 0.01)};
  const Workspace base(domain::PositionRegion::cylinder(centreBase.x(), centreBase.y(), 0.01, 0.47, 0.48), angles);
  const TransformedDomain framed =
      transformed(Workspace(domain::PositionRegion::cylinder(centreFrame.x(), centreFrame.y(), 0.01, 0.37, 0.38),
                            {Interval(-0.01, 0.01), Interval(-0.01, 0.01), Interval(-0.01 - a, 0.01 - a)}),
                  RigidTransform::fromTranslationYaw(t, a));

  for (const auto& [thresholds, expected] : {std::make_pair(six(1e-3, 1e-2), verify::Verdict::Safe),
                                             std::make_pair(six(1e-6, 1e-6), verify::Verdict::Unsafe)}) {
    const auto rb = verify::Verifier::run(robot, base, verifyOptions(thresholds));
    const auto rf = verify::Verifier::run(robot, framed, verifyOptions(thresholds));
    EXPECT_EQ(rb.verdict, expected) << rb.message;
    EXPECT_EQ(rf.verdict, rb.verdict) << rf.message << " / " << rb.message;
    if (rf.verdict == verify::Verdict::Unsafe) {
      // The witness is a point of the frame's workspace; its base-frame pose (computed independently) violates
      // the threshold.
      const int k = rf.witness_component;
      ASSERT_GE(k, 0);
      IVec thin(6);
      for (int i = 0; i < 6; ++i) thin[i] = Interval(rf.witness[i]);
      EXPECT_EQ(framed.classify(thin), domain::Containment::Inside);
      const double c = std::cos(a), s = std::sin(a);
      DVec pose(6);
      pose << t.x() + c * rf.witness[0] - s * rf.witness[1], t.y() + s * rf.witness[0] + c * rf.witness[1],
          t.z() + rf.witness[2], rf.witness[3], rf.witness[4], rf.witness[5] + a;
      EXPECT_GT(robot.worstErrorAt(pose)[k], thresholds[k]);
      for (int i = 0; i < 6; ++i) EXPECT_NEAR(rf.witness_pose[i].mid(), pose[i], 1e-12) << i;
    }
  }

  // A larger pair that needs a real search: thresholds 10 % above / 5 % below the sampled maxima.
  const Workspace bigBase(domain::PositionRegion::cylinder(centreBase.x(), centreBase.y(), 0.05, 0.46, 0.49),
                          {Interval(-0.1, 0.1), Interval(-0.1, 0.1), Interval(-0.1, 0.1)});
  const TransformedDomain bigFramed =
      transformed(Workspace(domain::PositionRegion::cylinder(centreFrame.x(), centreFrame.y(), 0.05, 0.36, 0.39),
                            {Interval(-0.1, 0.1), Interval(-0.1, 0.1), Interval(-0.1 - a, 0.1 - a)}),
                  RigidTransform::fromTranslationYaw(t, a));
  const DVec maxima = sampledMaxima(robot, bigBase, 20000, 11);
  for (const auto& [factor, expected] :
       {std::make_pair(1.10, verify::Verdict::Safe), std::make_pair(0.95, verify::Verdict::Unsafe)}) {
    const auto rb = verify::Verifier::run(robot, bigBase, verifyOptions(maxima * factor));
    const auto rf = verify::Verifier::run(robot, bigFramed, verifyOptions(maxima * factor));
    EXPECT_EQ(rb.verdict, expected) << rb.message;
    EXPECT_EQ(rf.verdict, rb.verdict) << rf.message << " / " << rb.message;
    if (expected == verify::Verdict::Safe) {
      EXPECT_GT(rf.stats.boxes, 1u);
    }
  }
}

TEST(TransformedWorkspace, MaxErrorBracketsOverlapThoseOfTheEquivalentBaseFrameWorkspace) {
  // Brackets of the same maxima must overlap (both are certified). A translated box is a box.
  const io::RobotFile file = test::ref6File();
  const model::GoughPlatform robot(file.geometry);
  const Eigen::Vector3d t(0.03, -0.02, 0.1);
  auto box = [](const Eigen::Vector3d& shift) {
    return Workspace::fromRanges({Interval(-0.004 + shift.x(), 0.004 + shift.x()),
                                  Interval(-0.004 + shift.y(), 0.004 + shift.y()),
                                  Interval(0.473 + shift.z(), 0.477 + shift.z()), Interval(-0.004, 0.004),
                                  Interval(-0.004, 0.004), Interval(-0.004, 0.004)});
  };
  const Workspace base = box(Eigen::Vector3d::Zero());
  const TransformedDomain framed = transformed(box(-t), RigidTransform::fromTranslationYaw(t, 0.0));
  verify::VerifierOptions o;
  o.mode = verify::Mode::MaxError;
  o.alpha = 0.2;
  o.threads = 1;
  o.time_limit_s = 30.0;
  const auto mb = verify::Verifier::run(robot, base, o);
  const auto mf = verify::Verifier::run(robot, framed, o);
  ASSERT_TRUE(mb.converged) << mb.message;
  ASSERT_TRUE(mf.converged) << mf.message;
  for (int k = 0; k < 6; ++k) {
    EXPECT_LE(mf.max_lower[k], mb.max_upper[k]) << k;
    EXPECT_LE(mb.max_lower[k], mf.max_upper[k]) << k;
  }
}

TEST(TransformedWorkspace, RefusesInvalidTransformsAndTellsRotationsAboutZ) {
  const Workspace ws = smallBox();
  auto message = [&](const RigidTransform& t) -> std::string {
    try {
      TransformedDomain tw = transformed(ws, t);
    } catch (const InvalidArgument& e) {
      return e.what();
    }
    return "";
  };
  RigidTransform scaled;
  scaled.rotation = 2.0 * Eigen::Matrix3d::Identity();
  EXPECT_NE(message(scaled).find("expected a rotation matrix"), std::string::npos) << message(scaled);
  RigidTransform mirrored;
  mirrored.rotation = Eigen::Vector3d(1, 1, -1).asDiagonal();
  EXPECT_NE(message(mirrored).find("det R"), std::string::npos) << message(mirrored);
  RigidTransform nan;
  nan.rotation(0, 0) = std::nan("");
  EXPECT_NE(message(nan).find("finite rotation"), std::string::npos) << message(nan);
  RigidTransform far;
  far.translation.x() = HUGE_VAL;
  EXPECT_NE(message(far).find("transform translation"), std::string::npos) << message(far);

  // Rotations about z built by fromTranslationYaw or Eigen's AngleAxis have exactly zero off-z entries: the cheap
  // exact case. Any other rotation is accepted too (the general case).
  EXPECT_EQ(message(RigidTransform::fromTranslationYaw(Eigen::Vector3d(1, 2, 3), -2.0)), "");
  EXPECT_TRUE(transformed(ws, RigidTransform::fromTranslationYaw(Eigen::Vector3d(1, 2, 3), -2.0)).aboutZ());
  RigidTransform aboutZ;
  aboutZ.rotation = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_EQ(message(aboutZ), "");
  EXPECT_TRUE(transformed(ws, aboutZ).aboutZ());
  EXPECT_DOUBLE_EQ(transformed(ws, aboutZ).yawOffset(), 0.3);
  RigidTransform tilted;
  tilted.rotation = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_EQ(message(tilted), "");
  const TransformedDomain tw = transformed(ws, tilted);
  EXPECT_FALSE(tw.aboutZ());
  EXPECT_DOUBLE_EQ(tw.rotationRpy()[0], 0.1);
  EXPECT_EQ(tw.rotationRpy()[1], 0.0);
  EXPECT_EQ(tw.rotationRpy()[2], 0.0);
}

namespace {

using Vec3L = std::array<long double, 3>;

/// The exactly mapped base-frame pose of a frame-F point (long double): position, and principal RPY of R_T R_F.
void exactPose(const TransformedDomain& tw, const DVec& p, long double out[6]) {
  const auto& a = tw.rotationRpy();
  const Mat3L rt = rpy(a[0], a[1], a[2]);
  const Mat3L n = product(rt, rpy(p[3], p[4], p[5]));
  for (int k = 0; k < 3; ++k) {
    out[k] = tw.translation()[k] + rt[k][0] * p[0] + rt[k][1] * p[1] + rt[k][2] * p[2];
  }
  out[3] = std::atan2(n[2][1], n[2][2]);
  out[4] = std::atan2(-n[2][0], std::hypot(n[0][0], n[1][0]));
  out[5] = std::atan2(n[1][0], n[0][0]);
}

/// Whether an enclosure contains an angle modulo 2 pi.
bool containsAngle(const Interval& e, long double angle) {
  const long double twoPi = 2.0L * 3.14159265358979323846264338327950288L;
  for (int k = -2; k <= 2; ++k) {
    const long double a = angle + k * twoPi;
    if (e.lower() <= a && a <= e.upper()) return true;
  }
  return false;
}

/// a - b reduced to (-pi, pi].
long double angleDifference(long double a, long double b) {
  const long double pi = 3.14159265358979323846264338327950288L;
  long double d = std::fmod(a - b, 2 * pi);
  if (d > pi) d -= 2 * pi;
  if (d <= -pi) d += 2 * pi;
  return d;
}

}  // namespace

TEST(TransformedWorkspace, GeneralRotationEnclosesTheExactlyMappedPosesAndTheirGradient) {
  const Workspace ws = Workspace::fromRanges({Interval(-0.05, 0.05), Interval(-0.05, 0.05), Interval(0.4, 0.5),
                                              Interval(-0.3, 0.3), Interval(-0.3, 0.3), Interval(-3.1, 3.1)});
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> angle(-3.1, 3.1), tilt(-1.2, 1.2), offset(-1.0, 1.0), width(1e-4, 0.05);
  int boxes = 0;
  for (int trial = 0; trial < 40; ++trial) {
    // The last trials put the base-frame yaw or roll across +-pi inside the boxes.
    const double yaw = trial >= 30 ? 3.14 : angle(rng);
    const TransformedDomain tw =
        transformed(ws, RigidTransform::fromTranslationRpy(Eigen::Vector3d(offset(rng), offset(rng), offset(rng)),
                                                           tilt(rng), tilt(rng), yaw));
    ASSERT_FALSE(tw.aboutZ());
    for (int b = 0; b < 20; ++b) {
      const DVec c = test::randomPoint(ws.initialBox(), rng);
      IVec box(6);
      for (int i = 0; i < 6; ++i) {
        const double h = width(rng);
        box[i] = Interval(c[i] - h, c[i] + h);
      }
      enclosure::BoxInput in;
      tw.poseView(box, true, in);
      ++boxes;
      for (int s = 0; s < 10; ++s) {
        const DVec p = s == 0 ? domain::centreOf(box) : test::randomPoint(box, rng);
        long double exact[6];
        exactPose(tw, p, exact);
        const IVec at = tw.poseAt(p);
        for (int i = 0; i < 6; ++i) {
          if (i < 3 || i == 4) {
            EXPECT_TRUE(in.pose[i].lower() <= exact[i] && exact[i] <= in.pose[i].upper()) << i << " " << in.pose[i];
            EXPECT_TRUE(at[i].lower() <= exact[i] && exact[i] <= at[i].upper()) << i;
          } else {
            EXPECT_TRUE(containsAngle(in.pose[i], exact[i])) << i << " " << in.pose[i] << " " << exact[i];
            EXPECT_TRUE(containsAngle(in.dualPose[i].value(), exact[i])) << i;
            EXPECT_TRUE(containsAngle(at[i], exact[i])) << i << " " << at[i] << " " << exact[i];
          }
          if (std::cos(exact[4]) > 0.1) {
            EXPECT_LT(at[i].width(), 1e-12) << i;  // a point maps to a tight enclosure (away from gimbal lock)
          }
          if (s == 0) {
            EXPECT_TRUE(containsAngle(in.centrePose[i], exact[i]) ||
                        (in.centrePose[i].lower() <= exact[i] && exact[i] <= in.centrePose[i].upper()))
                << i;
          }
        }
        // Gradient: central differences (long double) lie in the derivative enclosures over the box.
        if (s == 1) {
          const long double h = 1e-7;
          for (int j = 0; j < 6; ++j) {
            DVec plus = p, minus = p;
            plus[j] += static_cast<double>(h);
            minus[j] -= static_cast<double>(h);
            const long double step = static_cast<long double>(plus[j]) - minus[j];
            long double ep[6], em[6];
            exactPose(tw, plus, ep);
            exactPose(tw, minus, em);
            for (int i = 0; i < 6; ++i) {
              const long double d = (i >= 3 ? angleDifference(ep[i], em[i]) : ep[i] - em[i]) / step;
              const Interval& g = in.dualPose[i].d(j);
              EXPECT_TRUE(g.lower() - 1e-6 <= d && d <= g.upper() + 1e-6) << i << " " << j << " " << g << " " << d;
            }
          }
        }
      }
    }
  }
  EXPECT_EQ(boxes, 800);
}

namespace {

/// The base-frame pose of a frame-F point computed independently of the domain (double rotation matrices).
DVec independentBasePose(const RigidTransform& t, const DVec& p) {
  const Eigen::Matrix3d rf =
      (Eigen::AngleAxisd(p[5], Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(p[4], Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(p[3], Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  const Eigen::Matrix3d n = t.rotation * rf;
  const Eigen::Vector3d pos = t.translation + t.rotation * Eigen::Vector3d(p[0], p[1], p[2]);
  DVec out(6);
  out << pos.x(), pos.y(), pos.z(), std::atan2(n(2, 1), n(2, 2)), std::atan2(-n(2, 0), std::hypot(n(0, 0), n(1, 0))),
      std::atan2(n(1, 0), n(0, 0));
  return out;
}

/// RPY of a rotation matrix (double).
Eigen::Vector3d rpyOfMatrix(const Eigen::Matrix3d& n) {
  return Eigen::Vector3d(std::atan2(n(2, 1), n(2, 2)), std::atan2(-n(2, 0), std::hypot(n(0, 0), n(1, 0))),
                         std::atan2(n(1, 0), n(0, 0)));
}

}  // namespace

TEST(TransformedWorkspace, TiltedFrameVerdictsAgreeWithAnIndependentMapping) {
  const io::RobotFile file = test::ref6File();
  const model::GoughPlatform robot(file.geometry);
  // A frame tilted and turned; the workspace in it is placed so that its base-frame poses are around the reference
  // pose (0, 0, 0.475), level: position box around R_T^T (p0 - t), orientations around the RPY of R_T^T.
  const RigidTransform t = RigidTransform::fromTranslationRpy(Eigen::Vector3d(0.02, -0.01, 0.05), 0.1, -0.15, 2.9);
  const Eigen::Vector3d c = t.rotation.transpose() * (Eigen::Vector3d(0.0, 0.0, 0.475) - t.translation);
  const Eigen::Vector3d a = rpyOfMatrix(t.rotation.transpose());
  const double h = 0.01, ha = 0.02;
  const TransformedDomain framed =
      transformed(Workspace::fromRanges({Interval(c.x() - h, c.x() + h), Interval(c.y() - h, c.y() + h),
                                         Interval(c.z() - h, c.z() + h), Interval(a.x() - ha, a.x() + ha),
                                         Interval(a.y() - ha, a.y() + ha), Interval(a.z() - ha, a.z() + ha)}),
                  t);
  ASSERT_FALSE(framed.aboutZ());
  std::mt19937_64 rng(17);
  DVec maxima = DVec::Zero(6);
  for (int s = 0; s < 20000; ++s) {
    const DVec f = robot.worstErrorAt(independentBasePose(t, test::randomPoint(framed.initialBox(), rng)));
    for (int k = 0; k < 6; ++k) maxima[k] = std::max(maxima[k], f[k]);
  }
  const auto safe = verify::Verifier::run(robot, framed, verifyOptions(maxima * 1.10));
  EXPECT_EQ(safe.verdict, verify::Verdict::Safe) << safe.message;
  const auto unsafe = verify::Verifier::run(robot, framed, verifyOptions(maxima * 0.95));
  ASSERT_EQ(unsafe.verdict, verify::Verdict::Unsafe) << unsafe.message;
  const int k = unsafe.witness_component;
  ASSERT_GE(k, 0);
  EXPECT_GT(robot.worstErrorAt(independentBasePose(t, unsafe.witness))[k], maxima[k] * 0.95);
  EXPECT_LE(unsafe.witness_lower_bound, robot.worstErrorAt(independentBasePose(t, unsafe.witness))[k] * (1 + 1e-9));
}

TEST(TransformedWorkspace, TiltedFrameGivesTheVerdictsOfTheEquivalentBaseFrameWorkspace) {
  // A ball maps to a ball under any rigid transform, and a fixed orientation to a fixed orientation: the base-frame
  // workspace below is the frame's (up to the double rounding of its centre and angles).
  const io::RobotFile file = test::ref6File();
  const model::GoughPlatform robot(file.geometry);
  const RigidTransform t = RigidTransform::fromTranslationRpy(Eigen::Vector3d(0.03, 0.01, 0.1), -0.2, 0.1, 0.4);
  const Eigen::Vector3d centreBase(0.01, -0.01, 0.475), rpyFrame(0.12, 0.05, -0.35);
  const Eigen::Vector3d centreFrame = t.rotation.transpose() * (centreBase - t.translation);
  const Eigen::Matrix3d rf = (Eigen::AngleAxisd(rpyFrame.z(), Eigen::Vector3d::UnitZ()) *
                              Eigen::AngleAxisd(rpyFrame.y(), Eigen::Vector3d::UnitY()) *
                              Eigen::AngleAxisd(rpyFrame.x(), Eigen::Vector3d::UnitX()))
                                 .toRotationMatrix();
  const Eigen::Vector3d rpyBase = rpyOfMatrix(t.rotation * rf);
  auto fixed = [](const Eigen::Vector3d& r) {
    return std::array<Interval, 3>{Interval(r.x()), Interval(r.y()), Interval(r.z())};
  };
  const Workspace base(domain::PositionRegion::sphere(centreBase, 0.01), fixed(rpyBase));
  const TransformedDomain framed =
      transformed(Workspace(domain::PositionRegion::sphere(centreFrame, 0.01), fixed(rpyFrame)), t);
  for (const auto& [thresholds, expected] : {std::make_pair(six(1e-3, 1e-2), verify::Verdict::Safe),
                                             std::make_pair(six(1e-6, 1e-6), verify::Verdict::Unsafe)}) {
    const auto rb = verify::Verifier::run(robot, base, verifyOptions(thresholds));
    const auto rf2 = verify::Verifier::run(robot, framed, verifyOptions(thresholds));
    EXPECT_EQ(rb.verdict, expected) << rb.message;
    EXPECT_EQ(rf2.verdict, rb.verdict) << rf2.message << " / " << rb.message;
  }
  verify::VerifierOptions o;
  o.mode = verify::Mode::MaxError;
  o.alpha = 0.05;
  o.threads = 1;
  o.time_limit_s = 30.0;
  const auto mb = verify::Verifier::run(robot, base, o);
  const auto mf = verify::Verifier::run(robot, framed, o);
  ASSERT_TRUE(mb.converged) << mb.message;
  ASSERT_TRUE(mf.converged) << mf.message;
  for (int k = 0; k < 6; ++k) {
    EXPECT_LE(mf.max_lower[k], mb.max_upper[k]) << k;
    EXPECT_LE(mb.max_lower[k], mf.max_upper[k]) << k;
  }
}
