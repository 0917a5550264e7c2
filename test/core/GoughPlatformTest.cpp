// The Gough platform model against an independent implementation of the inverse kinematics (leg lengths from the
// rotation matrix built with Eigen's AngleAxis) and central finite differences.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <random>

#include "TestRobots.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"

using namespace pkm_accuracy;

namespace {

Eigen::Matrix3d rotationOf(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// Leg lengths with the tool point t (base frame) and rotation R: B_i = t + R (b_i - c).
Eigen::Matrix<double, 6, 1> lengths(const model::GoughGeometry& g, const Eigen::Vector3d& t, const Eigen::Matrix3d& r) {
  Eigen::Matrix<double, 6, 1> l;
  for (int i = 0; i < 6; ++i) l[i] = (t + r * (g.platform_anchors[i] - g.tool_point) - g.base_anchors[i]).norm();
  return l;
}

DVec pose6(double x, double y, double z, double r, double p, double yw) {
  DVec v(6);
  v << x, y, z, r, p, yw;
  return v;
}

/// The box of `frac` of every range of ws around c, and C = the inverse of J^-1 at its midpoint (as in the expansions).
void boxAndPreconditioner(const model::GoughPlatform& robot, const IVec& ws, const DVec& c, double frac, IVec& box,
                          DMat& cInv) {
  box.resize(6);
  IVec centre(6);
  for (int i = 0; i < 6; ++i) {
    const double h = frac * 0.5 * (ws[i].upper() - ws[i].lower());
    box[i] = Interval(c[i] - h, c[i] + h);
    centre[i] = Interval(box[i].mid());
  }
  const IMat mc = robot.inverseJacobianAtGeometryCentre(centre);
  DMat mid(6, 6);
  for (int r = 0; r < 6; ++r)
    for (int col = 0; col < 6; ++col) mid(r, col) = mc(r, col).mid();
  cInv = mid.inverse();
}

/// Lower bounds of |C d^2 J^-1 / dt_i dt_l (q)| for every pair p (the analytic Hessian at the point q, whose interval
/// enclosure is only a few ulps wide: |C mid| - |C| rad).
std::array<DMat, MatrixHessian::kPairs> preconditionedHessianAt(const model::GoughPlatform& robot, const IVec& q,
                                                                const DMat& c) {
  MatrixHessian at;
  EXPECT_TRUE(robot.inverseJacobianHessianAtGeometryCentre(q, at));
  std::array<DMat, MatrixHessian::kPairs> out;
  for (int p = 0; p < MatrixHessian::kPairs; ++p) {
    DMat hm(6, 6), hr(6, 6);
    for (int r = 0; r < 6; ++r)
      for (int col = 0; col < 6; ++col) {
        hm(r, col) = at.d[p](r, col).mid();
        hr(r, col) = at.d[p](r, col).rad();
      }
    out[p] = (c * hm).cwiseAbs() - c.cwiseAbs() * hr;
  }
  return out;
}

}  // namespace

TEST(GoughPlatform, InverseJacobianMatchesFiniteDifferencesOfLegLengths) {
  for (const bool withTool : {false, true}) {
    io::RobotFile rf = test::ref6File();
    if (withTool) rf.geometry.tool_point = Eigen::Vector3d(0.01, -0.02, 0.05);
    const model::GoughPlatform robot(rf.geometry);
    std::mt19937_64 rng(7);
    const IVec box = rf.workspaces.at("paper").initialBox();
    for (int trial = 0; trial < 200; ++trial) {
      const DVec q = test::randomPoint(box, rng);
      const Eigen::Matrix3d r = rotationOf(q[3], q[4], q[5]);
      const Eigen::Vector3d t = q.head<3>() + r * rf.geometry.tool_point;  // tool point in the base frame
      const DMat m = robot.inverseJacobian(q);
      const double h = 1e-6;
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d e = Eigen::Vector3d::Unit(k) * h;
        const Eigen::Matrix<double, 6, 1> d =
            (lengths(rf.geometry, t + e, r) - lengths(rf.geometry, t - e, r)) / (2 * h);
        for (int i = 0; i < 6; ++i) EXPECT_NEAR(m(i, k), d[i], 1e-8) << "leg " << i << " translation " << k;
        // Small rotation about base axis k around the tool point.
        const Eigen::Matrix3d rp = Eigen::AngleAxisd(h, Eigen::Vector3d::Unit(k)).toRotationMatrix() * r;
        const Eigen::Matrix3d rm = Eigen::AngleAxisd(-h, Eigen::Vector3d::Unit(k)).toRotationMatrix() * r;
        const Eigen::Matrix<double, 6, 1> dr = (lengths(rf.geometry, t, rp) - lengths(rf.geometry, t, rm)) / (2 * h);
        for (int i = 0; i < 6; ++i) EXPECT_NEAR(m(i, 3 + k), dr[i], 1e-8) << "leg " << i << " rotation " << k;
      }
      // Leg lengths agree with the independent formula.
      const DVec l = robot.legLengths(q);
      const Eigen::Matrix<double, 6, 1> li = lengths(rf.geometry, t, r);
      for (int i = 0; i < 6; ++i) EXPECT_NEAR(l[i], li[i], 1e-14);
    }
  }
}

TEST(GoughPlatform, JacobianTimesInverseIsIdentity) {
  const io::RobotFile rf = test::ref6File();
  const model::GoughPlatform robot(rf.geometry);
  std::mt19937_64 rng(11);
  const IVec box = rf.workspaces.at("paper").initialBox();
  for (int trial = 0; trial < 200; ++trial) {
    const DVec q = test::randomPoint(box, rng);
    const DMat prod = robot.inverseJacobian(q) * robot.jacobian(q);
    EXPECT_LT((prod - DMat::Identity(6, 6)).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(GoughPlatform, SingularPoseIsReportedNotNaN) {
  const io::RobotFile rf = test::ref6File();
  const model::GoughPlatform robot(rf.geometry);
  // Platform in the base plane: every leg is horizontal, the z column of J^-1 vanishes.
  const DVec q = pose6(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
  EXPECT_THROW(robot.jacobian(q), SingularMatrix);
  EXPECT_THROW(robot.worstErrorAt(q), SingularMatrix);
  const DVec f = enclosure::errorAtPoseDouble(robot, q);
  for (int k = 0; k < 6; ++k) EXPECT_TRUE(std::isinf(f[k]));
  IVec thin(6);
  for (int i = 0; i < 6; ++i) thin[i] = Interval(q[i]);
  IVec fi;
  EXPECT_FALSE(enclosure::errorAtPose(robot, thin, fi));
}

TEST(GoughPlatform, IntervalEnclosuresContainPointValuesAndDerivatives) {
  const io::RobotFile rf = test::ref6File();
  const model::GoughPlatform robot(rf.geometry);
  std::mt19937_64 rng(3);
  const IVec ws = rf.workspaces.at("paper_40deg").initialBox();
  std::uniform_real_distribution<double> frac(0.0, 0.3);
  for (int trial = 0; trial < 300; ++trial) {
    // Random sub-box, some dimensions of zero width.
    const DVec c = test::randomPoint(ws, rng);
    IVec box(6);
    for (int i = 0; i < 6; ++i) {
      const double h = (trial % 7 == i) ? 0.0 : frac(rng) * 0.5 * (ws[i].upper() - ws[i].lower());
      box[i] = Interval(c[i] - h, c[i] + h);
    }
    const IMat mi = robot.inverseJacobian(box);
    MatrixWithGradient mg;
    DualPose dp;
    for (int i = 0; i < 6; ++i) dp[i] = DualI::variable(box[i], i);
    robot.inverseJacobian(dp, mg);
    for (int s = 0; s < 20; ++s) {
      const DVec q = test::randomPoint(box, rng);
      const DMat m = robot.inverseJacobian(q);
      // Point derivative by dual numbers in double (independent of the interval path's scalar type).
      using D = interval::Dual<double, 6>;
      std::array<D, 6> qd;
      for (int i = 0; i < 6; ++i) qd[i] = D::variable(q[i], i);
      for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j) {
          const double slack = 1e-13 * (1.0 + std::abs(m(i, j)));
          EXPECT_LE(mi(i, j).lower() - slack, m(i, j));
          EXPECT_GE(mi(i, j).upper() + slack, m(i, j));
          EXPECT_LE(mg.value(i, j).lower() - slack, m(i, j));
          EXPECT_GE(mg.value(i, j).upper() + slack, m(i, j));
        }
      }
      // Central differences of J^-1 lie in the derivative enclosures (up to the difference error).
      const double h = 1e-6;
      for (int v = 0; v < 6; ++v) {
        if (box[v].isPoint()) continue;
        DVec qp = q, qm = q;
        qp[v] += h;
        qm[v] -= h;
        const DMat d = (robot.inverseJacobian(qp) - robot.inverseJacobian(qm)) / (2 * h);
        for (int i = 0; i < 6; ++i)
          for (int j = 0; j < 6; ++j) {
            EXPECT_LE(mg.d[v](i, j).lower() - 1e-6, d(i, j));
            EXPECT_GE(mg.d[v](i, j).upper() + 1e-6, d(i, j));
          }
      }
    }
  }
}

TEST(GoughPlatform, RejectsInvalidGeometry) {
  io::RobotFile rf = test::ref6File();
  model::GoughGeometry g = rf.geometry;
  g.base_anchors[3] = g.base_anchors[1];
  EXPECT_THROW(model::GoughPlatform{g}, InvalidGeometry);
  g = rf.geometry;
  g.platform_anchors.pop_back();
  EXPECT_THROW(model::GoughPlatform{g}, InvalidGeometry);
  g = rf.geometry;
  g.sensor_error[2] = 0.0;
  EXPECT_THROW(model::GoughPlatform{g}, InvalidGeometry);
  g = rf.geometry;
  g.sensor_error[2] = std::nan("");
  EXPECT_THROW(model::GoughPlatform{g}, InvalidGeometry);
  g = rf.geometry;
  g.base_anchors[0].x() = std::numeric_limits<double>::infinity();
  try {
    model::GoughPlatform robot(g);
    FAIL() << "expected InvalidGeometry";
  } catch (const InvalidGeometry& e) {
    EXPECT_NE(std::string(e.what()).find("base_anchors[0]"), std::string::npos) << e.what();
  }
}

TEST(GoughPlatform, AnalyticDerivativesAgreeWithDualNumbersAndChainRule) {
  io::RobotFile rf = test::ref6File();
  rf.geometry.tool_point = Eigen::Vector3d(0.01, 0.0, 0.03);
  rf.geometry.setUniformAnchorUncertainty(0.0005);
  const model::GoughPlatform robot(rf.geometry);
  std::mt19937_64 rng(21);
  const IVec ws = rf.workspaces.at("paper").initialBox();
  for (int trial = 0; trial < 200; ++trial) {
    const IVec box = test::centredSubBox(ws, std::pow(0.5, trial % 8));
    // Identity map and a non-trivial map q(t) = centre + G t (t in [-1, 1]^6) for the chain rule.
    DualPose identity, mapped;
    Eigen::Matrix<double, 6, 6> g = Eigen::Matrix<double, 6, 6>::Zero();
    for (int i = 0; i < 6; ++i) {
      identity[i] = DualI::variable(box[i], i);
      g(i, i) = box[i].rad();
      g(i, (i + 1) % 6) = 0.1 * box[(i + 1) % 6].rad();
    }
    for (int i = 0; i < 6; ++i) {
      DualI v(Interval(box[i].mid()));
      for (int j = 0; j < 6; ++j) v = v + DualI::variable(Interval(-1.0, 1.0), j) * Interval(g(i, j));
      mapped[i] = v;
    }
    for (const DualPose* p : {&identity, &mapped}) {
      MatrixWithGradient fast, reference;
      robot.inverseJacobian(*p, fast);
      robot.inverseJacobianByDualNumbers(*p, reference);
      for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 6; ++c) {
          // Both enclose the same function, so they must overlap. For the identity map (workspaces) the analytic
          // path evaluates the same expressions and must be as tight; through a general map the chain rule is
          // applied after the fact and may be looser than per-operation dual numbers (still an enclosure).
          EXPECT_FALSE(intersect(fast.value(r, c), reference.value(r, c)).isEmpty());
          for (int v = 0; v < 6; ++v) {
            EXPECT_FALSE(intersect(fast.d[v](r, c), reference.d[v](r, c)).isEmpty()) << trial << " " << v;
            if (p == &identity) {
              EXPECT_LE(fast.d[v](r, c).width(), 1.01 * reference.d[v](r, c).width() + 1e-15);
            }
          }
        }
    }
  }
}

TEST(GoughPlatform, HessianEnclosuresContainSecondDerivatives) {
  // Reference: central differences of the first derivatives by generic dual numbers (inverseJacobianByDualNumbers,
  // an implementation independent of the analytic formulas) at points of the box; their error (truncation ~h^2,
  // rounding ~1e-16 / h) is far below the tolerance, a wrong formula far above it.
  io::RobotFile rf = test::ref6File();
  rf.geometry.tool_point = Eigen::Vector3d(0.01, -0.02, 0.03);
  const model::GoughPlatform robot(rf.geometry);
  std::mt19937_64 rng(5);
  const IVec ws = rf.workspaces.at("paper_40deg").initialBox();
  auto derivativeAt = [&](const DVec& q, MatrixWithGradient& out) {
    DualPose dp;
    for (int i = 0; i < 6; ++i) dp[i] = DualI::variable(Interval(q[i]), i);
    robot.inverseJacobianByDualNumbers(dp, out);
  };
  int checked = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const DVec c = test::randomPoint(ws, rng);
    const double frac = std::pow(0.5, trial % 6);  // 1 .. 1/32 of the half-ranges, and thin boxes below
    IVec box(6);
    for (int i = 0; i < 6; ++i) {
      const double h = trial % 10 == 9 ? 0.0 : frac * 0.25 * (ws[i].upper() - ws[i].lower());
      box[i] = Interval(c[i] - h, c[i] + h);
    }
    MatrixHessian hess;
    ASSERT_TRUE(robot.inverseJacobianHessianAtGeometryCentre(box, hess));
    for (int s = 0; s < 8; ++s) {
      const DVec q = test::randomPoint(box, rng);
      // The first derivatives it also returns contain the dual-number ones at the point.
      MatrixWithGradient at;
      derivativeAt(q, at);
      for (int a = 0; a < 6; ++a)
        for (int r = 0; r < 6; ++r)
          for (int col = 0; col < 6; ++col) {
            EXPECT_LE(hess.first[a](r, col).lower(), at.d[a](r, col).upper()) << trial << " " << a;
            EXPECT_GE(hess.first[a](r, col).upper(), at.d[a](r, col).lower()) << trial << " " << a;
          }
      const double step = 1e-5;
      for (int b = 0; b < 6; ++b) {
        DVec qp = q, qm = q;
        qp[b] += step;
        qm[b] -= step;
        MatrixWithGradient plus, minus;
        derivativeAt(qp, plus);
        derivativeAt(qm, minus);
        for (int a = 0; a < 6; ++a) {
          const IMat& h = hess.d[MatrixHessian::index(a, b)];
          for (int r = 0; r < 6; ++r)
            for (int col = 0; col < 6; ++col) {
              const double fd = (plus.d[a](r, col).mid() - minus.d[a](r, col).mid()) / (2 * step);
              EXPECT_LE(h(r, col).lower() - 1e-6, fd) << trial << " " << a << b << " " << r << col;
              EXPECT_GE(h(r, col).upper() + 1e-6, fd) << trial << " " << a << b << " " << r << col;
              ++checked;
            }
        }
      }
    }
    if (box[0].isPoint()) {
      // At a point the enclosures are tight (a wrong-but-wide enclosure would pass the containment above).
      for (const IMat& h : hess.d)
        for (int r = 0; r < 6; ++r)
          for (int col = 0; col < 6; ++col) EXPECT_LT(h(r, col).width(), 1e-10);
      for (const IMat& f : hess.first)
        for (int r = 0; r < 6; ++r)
          for (int col = 0; col < 6; ++col) EXPECT_LT(f(r, col).width(), 1e-12);
      // Without the second derivatives: the same first ones, no second ones.
      MatrixHessian firstOnly;
      ASSERT_TRUE(robot.inverseJacobianHessianAtGeometryCentre(box, firstOnly, false));
      EXPECT_EQ(firstOnly.d[0].rows(), 0);
      for (int a = 0; a < 6; ++a) EXPECT_TRUE(firstOnly.first[a] == hess.first[a]);
    }
  }
  EXPECT_EQ(checked, 60 * 8 * 6 * 6 * 36);
}

TEST(GoughPlatform, PreconditionedHessianMagnitudeBoundsEveryPointAndBeatsTheIntervalHessian) {
  // The affine-form bound of |C d^2 J^-1 / dt_i dt_l| over a pose box against the analytic Hessian at points of the
  // box (HessianEnclosuresContainSecondDerivatives checks that one against finite differences), C the inverse of J^-1
  // at the box centre as in the expansions; on boxes of 1/8 of the ranges it must also be far below the interval
  // Hessian's |C Hm| + |C| Hr, which loses the cancellations between legs (docs/enclosures.md, Affine Hessian bound).
  io::RobotFile rf = test::ref6File();
  rf.geometry.tool_point = Eigen::Vector3d(0.01, -0.02, 0.03);
  const model::GoughPlatform robot(rf.geometry);
  std::mt19937_64 rng(11);
  const IVec ws = rf.workspaces.at("paper").initialBox();
  double affineSum = 0.0, intervalSum = 0.0;
  int checked = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const DVec c = test::randomPoint(ws, rng);
    const double frac = trial % 8 == 7 ? 0.0 : std::pow(0.5, 1 + trial % 4);  // 1/2 .. 1/16 of the ranges, points
    IVec box;
    DMat cInv;
    boxAndPreconditioner(robot, ws, c, frac, box, cInv);
    std::array<DMat, MatrixHessian::kPairs> bound;
    ASSERT_TRUE(robot.preconditionedHessianMagnitude(box, cInv, bound)) << trial;
    MatrixHessian overBox;
    ASSERT_TRUE(robot.inverseJacobianHessianAtGeometryCentre(box, overBox));
    for (int s = 0; s < 6; ++s) {
      const DVec q = s == 0 ? DVec(c) : test::randomPoint(box, rng);
      IVec point(6);
      for (int i = 0; i < 6; ++i) point[i] = Interval(q[i]);
      const std::array<DMat, MatrixHessian::kPairs> values = preconditionedHessianAt(robot, point, cInv);
      for (int p = 0; p < MatrixHessian::kPairs; ++p) {
        const DMat& value = values[p];  // <= |C H(q)|
        for (int r = 0; r < 6; ++r)
          for (int col = 0; col < 6; ++col) {
            EXPECT_LE(value(r, col), bound[p](r, col) * (1.0 + 1e-9) + 1e-12) << trial << " " << p << " " << r << col;
            ++checked;
          }
      }
    }
    if (trial % 8 == 2) {  // boxes of 1/8 of the ranges
      for (int p = 0; p < MatrixHessian::kPairs; ++p) {
        DMat hm(6, 6), hr(6, 6);
        for (int r = 0; r < 6; ++r)
          for (int col = 0; col < 6; ++col) {
            hm(r, col) = overBox.d[p](r, col).mid();
            hr(r, col) = overBox.d[p](r, col).rad();
          }
        intervalSum += ((cInv * hm).cwiseAbs() + cInv.cwiseAbs() * hr).sum();
        affineSum += bound[p].sum();
      }
    }
  }
  EXPECT_EQ(checked, 40 * 6 * MatrixHessian::kPairs * 36);
  std::printf("sum of the bounds on 1/8 boxes: affine %.4g, interval %.4g\n", affineSum, intervalSum);
  EXPECT_LT(affineSum, 0.5 * intervalSum);
}

TEST(GoughPlatform, PreconditionedHessianPartsScaleAlongSegmentsFromTheCentre) {
  // With `linear`, |C H_il(t0 + s dt)| <= out + s linear for every t0 + dt in the box (t0 its midpoint, s in [0, 1]):
  // what lets the mean-value and Taylor forms of PreconditionedInverseEnclosure weight the linear part by 1/2 and 1/3.
  // Checked against the analytic Hessian at points; on small boxes (where the affine remainder in `out` is second order
  // and the linear part first order) the bound is reached to within a few percent at the 64 vertices scaled by s, so a
  // linear part too small by a fifth, or one that did not scale with s, fails here. Without `linear`, `out` is the
  // sum of both parts. With `quadratic` too, |C H_il(t0 + s dt)| <= out + s linear + s^2 quadratic, checked the same
  // way (GoughPlatform then evaluates in interval::SegmentAffineForm).
  io::RobotFile rf = test::ref6File();
  const model::GoughPlatform robot(rf.geometry);
  std::mt19937_64 rng(5);
  const IVec ws = rf.workspaces.at("paper").initialBox();
  double closest[3] = {0.0, 0.0, 0.0};  // per s: the largest (|C H| - out) / (s linear) over the checks
  double splitSum[3] = {0.0, 0.0, 0.0}, wholeSum[3] = {0.0, 0.0, 0.0};  // the three-part and two-part bounds, summed
  const double scales[3] = {1.0, 0.5, 0.25};
  int checked = 0;
  for (int trial = 0; trial < 12; ++trial) {
    const DVec c = test::randomPoint(ws, rng);
    const double frac = trial % 3 == 0 ? 0.25 : (trial % 3 == 1 ? 1.0 / 64 : 1.0 / 256);
    IVec box;
    DMat cInv;
    boxAndPreconditioner(robot, ws, c, frac, box, cInv);
    std::array<DMat, MatrixHessian::kPairs> out, linear, whole, out3, linear3, quadratic3;
    ASSERT_TRUE(robot.preconditionedHessianMagnitude(box, cInv, out, &linear)) << trial;
    ASSERT_TRUE(robot.preconditionedHessianMagnitude(box, cInv, whole)) << trial;
    ASSERT_TRUE(robot.preconditionedHessianMagnitude(box, cInv, out3, &linear3, &quadratic3)) << trial;
    for (int p = 0; p < MatrixHessian::kPairs; ++p) {
      const DMat sum = out[p] + linear[p];
      for (int r = 0; r < 6; ++r)
        for (int col = 0; col < 6; ++col) EXPECT_NEAR(whole[p](r, col), sum(r, col), 1e-9 * sum(r, col) + 1e-300);
    }
    for (int si = 0; si < 3; ++si) {
      for (int v = 0; v < 64; ++v) {
        IVec point(6);
        for (int i = 0; i < 6; ++i) {
          const double half = scales[si] * 0.5 * (box[i].upper() - box[i].lower());
          point[i] = Interval(box[i].mid() + ((v >> i) & 1 ? half : -half));
        }
        const std::array<DMat, MatrixHessian::kPairs> values = preconditionedHessianAt(robot, point, cInv);
        for (int p = 0; p < MatrixHessian::kPairs; ++p) {
          const DMat& value = values[p];  // <= |C H(point)|
          for (int r = 0; r < 6; ++r)
            for (int col = 0; col < 6; ++col) {
              const double lin = scales[si] * linear[p](r, col);
              EXPECT_LE(value(r, col), (out[p](r, col) + lin) * (1.0 + 1e-9) + 1e-12)
                  << trial << " s " << scales[si] << " pair " << p << " " << r << col;
              const double s3 = scales[si];
              const double split = out3[p](r, col) + s3 * linear3[p](r, col) + s3 * s3 * quadratic3[p](r, col);
              EXPECT_LE(value(r, col), split * (1.0 + 1e-9) + 1e-12)
                  << trial << " s " << s3 << " pair " << p << " " << r << col << " (three parts)";
              splitSum[si] += split;
              wholeSum[si] += out[p](r, col) + lin;
              // (Entries whose linear part is tiny say nothing about it.)
              if (frac < 0.01 && lin > 0.2 * out[p](r, col) && lin > 1e-9)
                closest[si] = std::max(closest[si], (value(r, col) - out[p](r, col)) / lin);
              ++checked;
            }
        }
      }
    }
  }
  EXPECT_EQ(checked, 12 * 3 * 64 * MatrixHessian::kPairs * 36);
  std::printf("largest (|C H| - out) / (s linear) on small boxes: s = 1 %.3f, 1/2 %.3f, 1/4 %.3f\n", closest[0],
              closest[1], closest[2]);
  for (int si = 0; si < 3; ++si) EXPECT_GT(closest[si], 0.8) << "s " << scales[si];
  // With the remainder's s^2 part apart, the bound near the centre is far below the two-part one (whose remainder is
  // the whole box's at every s); at s = 1 it may be a little above (no square means in the centres).
  std::printf("three-part / two-part bounds summed: s = 1 %.3f, 1/2 %.3f, 1/4 %.3f\n", splitSum[0] / wholeSum[0],
              splitSum[1] / wholeSum[1], splitSum[2] / wholeSum[2]);
  EXPECT_LT(splitSum[2], 0.8 * wholeSum[2]);
}
