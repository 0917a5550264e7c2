// Soundness of every enclosure method: for random boxes (wide, small, near-singular, some zero widths) the worst
// error at random points of the box never exceeds the method's upper bound. The point values come from the
// certified point evaluation and, independently, from an MPFR computation (200 bits) of J^-1, its inverse and
// sum_j |J_kj| e_j.
#include <gtest/gtest.h>

#include <mpfr.h>
#include <algorithm>
#include <array>
#include <iostream>

#include <cmath>
#include <random>
#include <vector>

#include "MpfrGough.hpp"
#include "TestRobots.hpp"
#include "pkm_accuracy/core/domain/Workspace.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/enclosure/PreconditionedInverseEnclosure.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"

using namespace pkm_accuracy;
using namespace pkm_accuracy::test;  // the MPFR reference toolkit (MpfrGough.hpp)

namespace {

/// Sample s of a 6-D box: its vertex number s for s < 64 (bit i: upper end of variable i), else a random point.
DVec vertexOrRandomPoint(const IVec& box, int s, std::mt19937_64& rng) {
  if (s >= 64) return test::randomPoint(box, rng);
  DVec q(6);
  for (int i = 0; i < 6; ++i) q[i] = (s >> i) & 1 ? box[i].upper() : box[i].lower();
  return q;
}

/// Box number `trial` of the MPFR tests below: 1/4, 1/8, 1/16 and 1/32 of every range of `whole` (by trial % 4), at
/// random corners of it for trial < 8, else at random places inside.
IVec cornerOrInnerBox(const IVec& whole, int trial, std::mt19937_64& rng) {
  const double fraction = std::pow(0.5, 2 + trial % 4);
  IVec box(6);
  for (int i = 0; i < 6; ++i) {
    const double w = fraction * (whole[i].upper() - whole[i].lower());
    const double lo = trial < 8 ? (rng() % 2 ? whole[i].upper() - w : whole[i].lower())
                                : std::uniform_real_distribution<double>(whole[i].lower(), whole[i].upper() - w)(rng);
    box[i] = Interval(lo, lo + w);
  }
  return box;
}

/// S(t) = C J^-1(t) - I in MPFR (C: a preconditioner, J^-1 of geometry g at pose t).
MpMat mpPoseResidual(const DMat& c, const model::GoughGeometry& g, const DVec& t) {
  const MpMat jt = mpInverseJacobian(g, t);
  MpMat sm(6, std::vector<Mp>(6, Mp(0.0)));
  for (int k = 0; k < 6; ++k)
    for (int l = 0; l < 6; ++l) {
      Mp x(k == l ? -1.0 : 0.0);
      for (int m = 0; m < 6; ++m) x = x + Mp(c(k, m)) * jt[m][l];
      sm[k][l] = x;
    }
  return sm;
}

}  // namespace

TEST(ErrorEnclosure, RegistryKnowsEveryMethodAndRejectsUnknownNames) {
  for (const auto& name : enclosure::enclosureNames()) EXPECT_EQ(enclosure::makeEnclosure(name)->name(), name);
  try {
    enclosure::makeEnclosure("nope");
    FAIL();
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("nope"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("mean_value"), std::string::npos);
  }
}

TEST(ErrorEnclosure, CertifiedPointValueContainsMpfrValue) {
  const io::RobotFile rf = test::ref6File();
  for (const bool withTool : {false, true}) {
    model::GoughGeometry g = rf.geometry;
    if (withTool) g.tool_point = Eigen::Vector3d(0.02, 0.01, -0.03);
    const model::GoughPlatform robot(g);
    std::mt19937_64 rng(5);
    const IVec ws = rf.workspaces.at("paper_40deg").initialBox();
    int evaluated = 0;
    for (int trial = 0; trial < 300; ++trial) {
      const DVec q = test::randomPoint(ws, rng);
      IVec thin(6), f;
      for (int i = 0; i < 6; ++i) thin[i] = Interval(q[i]);
      if (!enclosure::errorAtPose(robot, thin, f)) continue;  // (near-)singular: nothing certified, nothing to check
      ++evaluated;
      const auto exact = mpfrWorstError(g, q);
      for (int k = 0; k < 6; ++k) {
        EXPECT_TRUE(mpGreaterEqual(exact[k], f[k].lower())) << "component " << k << " trial " << trial;
        EXPECT_TRUE(mpLessEqual(exact[k], f[k].upper())) << "component " << k << " trial " << trial;
        // And the enclosure is tight (a point evaluation, not a box).
        EXPECT_LT(f[k].upper() - f[k].lower(), 1e-9 * f[k].upper());
      }
    }
    EXPECT_GT(evaluated, 250);
  }
}

TEST(ErrorEnclosure, EveryMethodBoundsEveryPointOfRandomBoxes) {
  const io::RobotFile rf = test::ref6File();
  const model::GoughPlatform robot(rf.geometry);
  const IVec ws = rf.workspaces.at("paper_40deg").initialBox();
  const domain::Workspace whole = rf.workspaces.at("paper_40deg");
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> logFrac(-7.0, -1.0);
  std::vector<std::unique_ptr<enclosure::ErrorEnclosure>> methods;
  for (const auto& name : enclosure::enclosureNames()) methods.push_back(enclosure::makeEnclosure(name));
  int bounded = 0, checkedMpfr = 0;
  const int boxes = 1500;
  for (int trial = 0; trial < boxes; ++trial) {
    const DVec c = test::randomPoint(ws, rng);
    IVec box(6);
    const double frac = std::pow(2.0, logFrac(rng) * 2.0);
    for (int i = 0; i < 6; ++i) {
      const double h = (trial % 5 == 0 && i == trial % 6) ? 0.0 : frac * 0.5 * (ws[i].upper() - ws[i].lower());
      box[i] = Interval(c[i] - h, c[i] + h);
    }
    enclosure::BoxInput in;
    whole.poseView(box, true, in);
    std::vector<enclosure::ErrorBounds> bounds(methods.size());
    for (std::size_t m = 0; m < methods.size(); ++m) {
      methods[m]->enclose(robot, in, bounds[m]);
      ASSERT_EQ(bounds[m].upper.size(), 6);
      for (int k = 0; k < 6; ++k) ASSERT_FALSE(std::isnan(bounds[m].upper[k]));
      if (bounds[m].bounded()) ++bounded;
    }
    for (int s = 0; s < 5; ++s) {
      const DVec q = test::randomPoint(box, rng);
      IVec thin(6), f;
      for (int i = 0; i < 6; ++i) thin[i] = Interval(q[i]);
      const bool certified = enclosure::errorAtPose(robot, thin, f);
      std::vector<Mp> exact;
      if (s == 0 && trial % 10 == 0) {
        exact = mpfrWorstError(rf.geometry, q);
        ++checkedMpfr;
      }
      for (std::size_t m = 0; m < methods.size(); ++m) {
        for (int k = 0; k < 6; ++k) {
          if (certified) {
            EXPECT_LE(f[k].lower(), bounds[m].upper[k]) << methods[m]->name() << " k=" << k << " trial " << trial;
            EXPECT_GE(f[k].upper(), bounds[m].lower[k]) << methods[m]->name() << " k=" << k << " trial " << trial;
          }
          if (!exact.empty()) {
            EXPECT_TRUE(mpLessEqual(exact[k], bounds[m].upper[k])) << methods[m]->name() << " k=" << k;
            EXPECT_TRUE(mpGreaterEqual(exact[k], bounds[m].lower[k])) << methods[m]->name() << " k=" << k;
          }
        }
      }
    }
  }
  // The test must exercise bounded enclosures, not only +inf answers.
  EXPECT_GT(bounded, boxes / 2);
  EXPECT_GT(checkedMpfr, 100);
}

// With an exact geometry, second_order bounds boxes of 3 or more variables with the affine form of
// PreconditionedInverseEnclosure (no geometry terms) instead of the interval-Gauss form it uses when the caller asks
// for the internals. The signs of J it certifies (which a search hands down to sub-boxes) hold at every sampled pose,
// and both forms bound the sampled errors.
TEST(ErrorEnclosure, SecondOrderOnExactGeometryUsesTheAffineFormAndItsSignsHold) {
  const io::RobotFile rf = test::ref6File();
  const model::GoughPlatform robot(rf.geometry);
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const IVec whole = ws.initialBox();
  const auto method = enclosure::makeEnclosure("second_order");
  std::mt19937_64 rng(23);
  int signsChecked = 0, compared = 0;
  std::uniform_int_distribution<int> corner(0, 63);
  for (int trial = 0; trial < 200; ++trial) {
    // Boxes around workspace corners, where the errors are largest (the boxes the search has to refine).
    DVec c(6);
    const int v = corner(rng);
    for (int i = 0; i < 6; ++i) c[i] = (v >> i) & 1 ? whole[i].upper() : whole[i].lower();
    const double frac = std::pow(0.5, 4 + trial % 3);
    IVec box(6);
    for (int i = 0; i < 6; ++i) {
      const double h = frac * 0.5 * (whole[i].upper() - whole[i].lower());
      box[i] = Interval(c[i] - h, c[i] + h);
    }
    enclosure::BoxInput in;
    ws.poseView(box, true, in);
    enclosure::ErrorBounds affine, gauss;
    method->enclose(robot, in, affine);
    in.keepInternals = true;  // the interval-Gauss form (it fills the internals)
    method->enclose(robot, in, gauss);
    ASSERT_TRUE(gauss.internals.valid || !gauss.bounded());
    EXPECT_FALSE(affine.internals.valid);
    for (int k = 0; k < 6; ++k) compared += std::isfinite(affine.upper[k]) ? 1 : 0;
    for (int s = 0; s < 5; ++s) {
      const DVec q = test::randomPoint(box, rng);
      const DVec f = robot.worstErrorAt(q);
      for (int k = 0; k < 6; ++k) {
        EXPECT_LE(f[k], affine.upper[k] * (1 + 1e-12)) << "trial " << trial << " k=" << k;
        EXPECT_LE(f[k], gauss.upper[k] * (1 + 1e-12)) << "trial " << trial << " k=" << k;
      }
      const DMat j = robot.jacobian(q);
      for (int k = 0; k < 6; ++k)
        for (int l = 0; l < 6; ++l) {
          const int bit = k * 6 + l;
          if (!affine.signs.known(bit)) continue;
          EXPECT_GT(affine.signs.sign(bit) * j(k, l), 0.0) << "trial " << trial << " entry " << k << "," << l;
          ++signsChecked;
        }
    }
  }
  EXPECT_GT(signsChecked, 10000);
  EXPECT_GT(compared, 1000);
}

TEST(ErrorEnclosure, SecondOrderIsTightOnEighthBoxesThroughTheCentredPoseDerivatives) {
  // Boxes of 1/8 of every range at workspace corners (where the errors are largest): the pose slopes through the
  // model's Hessian (PreconditionedInverseEnclosure::prepare, second-order Taylor slopes) keep the bound within 13% of
  // the sampled maximum over the box; with the centred derivative ranges alone it is 5-26% above it, with the direct
  // derivative enclosures alone 22-104%.
  const io::RobotFile rf = test::ref6File();
  const model::GoughPlatform robot(rf.geometry);
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const IVec whole = ws.initialBox();
  const auto method = enclosure::makeEnclosure("second_order");
  std::mt19937_64 rng(29);
  std::uniform_int_distribution<int> corner(0, 63);
  double worst = 0.0;
  for (int trial = 0; trial < 12; ++trial) {
    const int v = corner(rng);
    IVec box(6);
    for (int i = 0; i < 6; ++i) {
      const double w = 0.125 * (whole[i].upper() - whole[i].lower());
      box[i] = (v >> i) & 1 ? Interval(whole[i].upper() - w, whole[i].upper())
                            : Interval(whole[i].lower(), whole[i].lower() + w);
    }
    enclosure::BoxInput in;
    ws.poseView(box, true, in);
    enclosure::ErrorBounds b;
    method->enclose(robot, in, b);
    DVec hi = DVec::Zero(6);
    for (int s = 0; s < 64 + 300; ++s) {
      const DVec q = vertexOrRandomPoint(box, s, rng);
      hi = hi.cwiseMax(robot.worstErrorAt(q));
    }
    for (int k = 0; k < 6; ++k) {
      EXPECT_GE(b.upper[k], hi[k]) << "trial " << trial << " k=" << k;
      worst = std::max(worst, b.upper[k] / hi[k]);
    }
  }
  std::cout << "[ info     ] 1/8 boxes at workspace corners: bound / sampled maximum <= " << worst << "\n";
  EXPECT_LT(worst, 1.2);
}

TEST(ErrorEnclosure, PoseSlopesHoldAtEveryVertexInMpfr) {
  // PreconditionedInverseEnclosure's pose slopes T_i, entry by entry either the range of C dJ^-1/dt_i over the box or
  // the second-order Taylor slope D_i(t0) + (1/2) sum_l C H_il(box) [-dev_l, dev_l] (half the centred range's radius):
  // C (J^-1(t) - J^-1(t0)) - sum_i mid(T_i) (t_i - t0_i) must stay within sum_i rad(T_i) |t_i - t0_i| at every vertex
  // (where the second-order term is largest) and at random points, with J^-1 in MPFR. The bound must also be reached
  // closely somewhere (largest ratio > 0.6), so that a Hessian term too small by a factor 0.6 fails here.
  const io::RobotFile rf = test::ref6File();
  const model::GoughPlatform robot(rf.geometry);
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const IVec whole = ws.initialBox();
  std::mt19937_64 rng(71);
  double worstRatio = 0.0;
  int checked = 0;
  for (int trial = 0; trial < 16; ++trial) {
    // Boxes of 1/4, 1/8, 1/16 and 1/32 of every range, at random corners of the workspace or inside it.
    const IVec box = cornerOrInnerBox(whole, trial, rng);
    enclosure::BoxInput in;
    ws.poseView(box, true, in);
    enclosure::PreconditionedInverseEnclosure act;
    ASSERT_TRUE(act.prepare(robot, in, enclosure::PreconditionedInverseEnclosure::GeometryTerms::AtCentre))
        << "trial " << trial;
    const DMat& c = act.preconditioner();
    DVec t0(6);
    for (int i = 0; i < 6; ++i) t0[i] = in.centrePose[i].mid();
    const MpMat j0 = mpInverseJacobian(rf.geometry, t0);
    for (int s = 0; s < 64 + 16; ++s) {
      const DVec t = vertexOrRandomPoint(box, s, rng);
      const MpMat jt = mpInverseJacobian(rf.geometry, t);
      for (int k = 0; k < 6; ++k)
        for (int l = 0; l < 6; ++l) {
          Mp diff(0.0);
          for (int m = 0; m < 6; ++m) diff = diff + Mp(c(k, m)) * (jt[m][l] - j0[m][l]);
          double bound = 0.0;
          for (int i = 0; i < 6; ++i) {
            const Mp dev = Mp(t[i]) - Mp(t0[i]);
            diff = diff - Mp(act.poseSlopeMid(i)(k, l)) * dev;
            bound += act.poseSlopeRad(i)(k, l) * std::abs(t[i] - t0[i]);
          }
          const double excess = toDouble(mpAbs(diff));
          ASSERT_TRUE(mpLessEqual(mpAbs(diff), bound * (1.0 + 1e-12)))
              << "trial " << trial << " sample " << s << " entry " << k << "," << l << ": " << excess << " > " << bound;
          if (bound > 0.0) worstRatio = std::max(worstRatio, excess / bound);
          ++checked;
        }
    }
  }
  std::cout << "[ info     ] pose slopes: largest |residual| / bound " << worstRatio << " over " << checked
            << " checks\n";
  EXPECT_GT(worstRatio, 0.6);
}

TEST(ErrorEnclosure, PoseSquareMagnitudeBoundsSSquaredInMpfr) {
  // PreconditionedInverseEnclosure's |S S| bound (S(t) = C J^-1(t) - I, the pose part of E): |S(t) S(t)| <=
  // poseSquareMagnitude() entry by entry at every vertex and at random points of boxes of 1/4 ... 1/32 of every range,
  // with S(t) S(t) in MPFR. The bound must be reached closely somewhere (0.96 of it is; a bound too small by a factor
  // 0.8 fails), and it must be below |S| |S| on the whole (the products' cancellations are what it is for).
  const io::RobotFile rf = test::ref6File();
  const model::GoughPlatform robot(rf.geometry);
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const IVec whole = ws.initialBox();
  std::mt19937_64 rng(83);
  double worstRatio = 0.0, sumBound = 0.0, sumSquare = 0.0;
  int checked = 0;
  for (int trial = 0; trial < 16; ++trial) {
    const IVec box = cornerOrInnerBox(whole, trial, rng);
    enclosure::BoxInput in;
    ws.poseView(box, true, in);
    enclosure::PreconditionedInverseEnclosure act;
    ASSERT_TRUE(act.prepare(robot, in, enclosure::PreconditionedInverseEnclosure::GeometryTerms::AtCentre))
        << "trial " << trial;
    const DMat& c = act.preconditioner();
    const DMat& m2 = act.poseSquareMagnitude();
    const DMat& magS = act.poseMagnitude();
    ASSERT_EQ(m2.rows(), 6);
    ASSERT_EQ(m2.cols(), 6);
    const DMat ss = magS * magS;
    for (int k = 0; k < 6; ++k)
      for (int l = 0; l < 6; ++l) {
        ASSERT_LE(m2(k, l), ss(k, l) * (1.0 + 1e-12)) << "trial " << trial << " entry " << k << "," << l;
        sumBound += m2(k, l);
        sumSquare += ss(k, l);
      }
    for (int s = 0; s < 64 + 16; ++s) {
      const DVec t = vertexOrRandomPoint(box, s, rng);
      const MpMat sm = mpPoseResidual(c, rf.geometry, t);
      for (int k = 0; k < 6; ++k)
        for (int l = 0; l < 6; ++l) {
          Mp x(0.0);
          for (int m = 0; m < 6; ++m) x = x + sm[k][m] * sm[m][l];
          ASSERT_TRUE(mpLessEqual(mpAbs(x), m2(k, l))) << "trial " << trial << " sample " << s << " entry " << k << ","
                                                       << l << ": " << toDouble(mpAbs(x)) << " > " << m2(k, l);
          if (m2(k, l) > 0.0) worstRatio = std::max(worstRatio, toDouble(mpAbs(x)) / m2(k, l));
          ++checked;
        }
    }
  }
  std::cout << "[ info     ] |S S|: largest |S(t) S(t)| / bound " << worstRatio << " over " << checked
            << " checks; sum of the bounds / sum of |S| |S| " << sumBound / sumSquare << "\n";
  EXPECT_GT(worstRatio, 0.8);
  EXPECT_LT(sumBound, 0.9 * sumSquare);
}

TEST(ErrorEnclosure, AffineHessianFormsBoundTheThirdOrderTaylorRestInMpfr) {
  // What PreconditionedInverseEnclosure::tightenByResidual takes from the model: with C H_il(t0 + s dt) within s L_il +
  // R_il + s^2 Q_il of its centre C Hc_il (GoughPlatform::preconditionedHessianMagnitude's linear part, remainder and
  // quadratic part, and its centre output), the Taylor rest
  //   C (J^-1(t) - J^-1(t0)) - sum_i C D_i(t0) dt_i - (1/2) sum_il C Hc_il dt_i dt_l
  // is bounded entry by entry by sum_i |C| rad(D_i(t0)) |dt_i| + sum_il (L_il / 6 + R_il / 2 + Q_il / 12) |dt_i dt_l|
  // (integral form of the remainder). Checked in MPFR at every vertex and random points of boxes of 1/4 ... 1/32 of
  // every range; the bound must be reached within a factor of 5 somewhere (it is not vacuous).
  const io::RobotFile rf = test::ref6File();
  const model::GoughPlatform robot(rf.geometry);
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const IVec whole = ws.initialBox();
  std::mt19937_64 rng(41);
  double worstRatio = 0.0;
  int checked = 0;
  for (int trial = 0; trial < 16; ++trial) {
    const IVec box = cornerOrInnerBox(whole, trial, rng);
    enclosure::BoxInput in;
    ws.poseView(box, true, in);
    enclosure::PreconditionedInverseEnclosure act;
    ASSERT_TRUE(act.prepare(robot, in, enclosure::PreconditionedInverseEnclosure::GeometryTerms::AtCentre))
        << "trial " << trial;
    const DMat c = act.preconditioner();
    std::array<DMat, MatrixHessian::kPairs> mag, lin, quad, rest, centre;
    ASSERT_TRUE(robot.preconditionedHessianMagnitude(box, c, mag, &lin, &quad, &rest, &centre)) << "trial " << trial;
    MatrixHessian at;
    ASSERT_TRUE(robot.inverseJacobianHessianAtGeometryCentre(in.centrePose, at, false));
    DVec t0(6);
    for (int i = 0; i < 6; ++i) t0[i] = in.centrePose[i].mid();
    const MpMat j0 = mpInverseJacobian(rf.geometry, t0);
    for (int s = 0; s < 64 + 16; ++s) {
      const DVec t = vertexOrRandomPoint(box, s, rng);
      const MpMat jt = mpInverseJacobian(rf.geometry, t);
      std::vector<Mp> dt;
      for (int i = 0; i < 6; ++i) dt.push_back(Mp(t[i]) - Mp(t0[i]));
      for (int k = 0; k < 6; ++k)
        for (int l = 0; l < 6; ++l) {
          Mp r(0.0);
          double bound = 0.0;
          for (int q = 0; q < 6; ++q) r = r + Mp(c(k, q)) * (jt[q][l] - j0[q][l]);
          for (int i = 0; i < 6; ++i) {
            Mp d(0.0);
            double rad = 0.0;
            for (int q = 0; q < 6; ++q) {
              d = d + Mp(c(k, q)) * Mp(at.first[i](q, l).mid());
              rad += std::abs(c(k, q)) * at.first[i](q, l).rad();
            }
            r = r - d * dt[i];
            bound += rad * std::abs(t[i] - t0[i]);
            for (int m = 0; m < 6; ++m) {
              const int p = MatrixHessian::index(i, m);
              r = r - Mp(0.5 * centre[p](k, l)) * dt[i] * dt[m];
              bound += (lin[p](k, l) / 6.0 + rest[p](k, l) / 2.0 + quad[p](k, l) / 12.0) * std::abs(t[i] - t0[i]) *
                       std::abs(t[m] - t0[m]);
            }
          }
          bound = bound * (1.0 + 1e-10) + 1e-300;
          ASSERT_TRUE(mpLessEqual(mpAbs(r), bound)) << "trial " << trial << " sample " << s << " entry " << k << ","
                                                    << l << ": " << toDouble(mpAbs(r)) << " > " << bound;
          if (bound > 0.0) worstRatio = std::max(worstRatio, toDouble(mpAbs(r)) / bound);
          ++checked;
        }
    }
  }
  std::cout << "[ info     ] third-order Taylor rest: largest |rest| / bound " << worstRatio << " over " << checked
            << " checks\n";
  EXPECT_GT(worstRatio, 0.2);
}

TEST(ErrorEnclosure, ResidualRadiusContainsNVInMpfrAndTightensTheForms) {
  // PreconditionedInverseEnclosure::tightenByResidual: for the forms of N V (V = C, whose columns are J = N C's, and
  // random interval columns), every tightened radius still bounds |N(t) v - x-hat(tau)| at every vertex and at random
  // points of boxes of 1/4 ... 1/32 of every range and of half of it (N v in MPFR, v a vertex or a random point of V's
  // intervals); the centres and coefficients are kept and no radius grows; and on the whole the radii shrink (the point
  // of it), with the bound reached closely somewhere (a bound that ignored a term of the residual would show it there).
  const io::RobotFile rf = test::ref6File();
  const model::GoughPlatform robot(rf.geometry);
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const IVec whole = ws.initialBox();
  std::mt19937_64 rng(97);
  double worstRatio = 0.0, sumOld = 0.0, sumNew = 0.0;
  int checked = 0, tightened = 0, entries = 0;
  for (int trial = 0; trial < 17; ++trial) {
    IVec box = cornerOrInnerBox(whole, trial, rng);
    if (trial == 16)  // half of every range around the centre (the whole workspace is too large for the expansion)
      for (int i = 0; i < 6; ++i)
        box[i] = Interval(whole[i].lower() + 0.25 * (whole[i].upper() - whole[i].lower()),
                          whole[i].upper() - 0.25 * (whole[i].upper() - whole[i].lower()));
    enclosure::BoxInput in;
    ws.poseView(box, true, in);
    enclosure::PreconditionedInverseEnclosure act;
    ASSERT_TRUE(act.prepare(robot, in, enclosure::PreconditionedInverseEnclosure::GeometryTerms::AtCentre))
        << "trial " << trial;
    const DMat& c = act.preconditioner();
    for (int which = 0; which < 2; ++which) {
      // V = C (the columns of J = N C), then 3 random columns, one of them with a radius.
      const int m = which == 0 ? 6 : 3;
      IMat v(6, m);
      std::uniform_real_distribution<double> unit(-1.0, 1.0);
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < m; ++j) {
          const double x = which == 0 ? c(i, j) : unit(rng),
                       r = which == 1 && j == 2 ? 1e-3 * std::abs(unit(rng)) : 0.0;
          v(i, j) = Interval(x - r, x + r);
        }
      enclosure::PreconditionedInverseEnclosure::AffineMatrix a, b;
      ASSERT_TRUE(act.apply(v, a)) << "trial " << trial;
      b = a;
      act.tightenByResidual(v, b);
      for (int k = 0; k < 6; ++k)
        for (int j = 0; j < m; ++j) {
          ASSERT_EQ(b.centre(k, j), a.centre(k, j));
          for (int i = 0; i < 6; ++i) ASSERT_EQ(b.pose[i](k, j), a.pose[i](k, j));
          ASSERT_LE(b.radius(k, j), a.radius(k, j));
          sumOld += a.radius(k, j);
          sumNew += b.radius(k, j);
          tightened += b.radius(k, j) < a.radius(k, j);
          ++entries;
        }
      for (int s = 0; s < 64 + 16; ++s) {
        const DVec t = vertexOrRandomPoint(box, s, rng);
        const MpMat jt = mpInverseJacobian(rf.geometry, t);
        MpMat cj(6, std::vector<Mp>(6, Mp(0.0)));
        for (int k = 0; k < 6; ++k)
          for (int l = 0; l < 6; ++l)
            for (int q = 0; q < 6; ++q) cj[k][l] = cj[k][l] + Mp(c(k, q)) * jt[q][l];
        MpMat vp(6, std::vector<Mp>(m, Mp(0.0)));
        for (int i = 0; i < 6; ++i)
          for (int j = 0; j < m; ++j)
            vp[i][j] = Mp(s % 3 == 0   ? v(i, j).lower()
                          : s % 3 == 1 ? v(i, j).upper()
                                       : std::uniform_real_distribution<double>(v(i, j).lower(), v(i, j).upper())(rng));
        const MpMat nv = mpSolve(cj, vp);
        std::vector<Mp> tau;
        for (int i = 0; i < 6; ++i) tau.push_back((Mp(t[i]) - Mp(in.centrePose[i].mid())) / Mp(act.deviation(i)));
        for (int k = 0; k < 6; ++k)
          for (int j = 0; j < m; ++j) {
            Mp xhat(b.centre(k, j));
            for (int i = 0; i < 6; ++i) xhat = xhat + Mp(b.pose[i](k, j)) * tau[i];
            const Mp d = mpAbs(nv[k][j] - xhat);
            ASSERT_TRUE(mpLessEqual(d, b.radius(k, j)))
                << "trial " << trial << " sample " << s << " entry " << k << "," << j << ": " << toDouble(d) << " > "
                << b.radius(k, j) << " (before: " << a.radius(k, j) << ")";
            if (b.radius(k, j) > 0.0) worstRatio = std::max(worstRatio, toDouble(d) / b.radius(k, j));
            ++checked;
          }
      }
    }
  }
  std::cout << "[ info     ] residual radius: largest |N v - x-hat| / radius " << worstRatio << " over " << checked
            << " checks; " << tightened << " of " << entries << " radii tightened, sum of the radii " << sumNew / sumOld
            << " of before\n";
  EXPECT_GT(tightened, entries / 2);
  EXPECT_LT(sumNew, 0.8 * sumOld);
  EXPECT_GT(worstRatio, 0.1);
}

TEST(ErrorEnclosure, SeparableSsyPartOfTheRadiusHoldsAfterTheResidualTightening) {
  // GeometryIncrement takes ssy(k, j) out of splitRadius(k, j) as a separable part: x - x-hat - (S S y) is bounded
  // by splitRadius - ssy and S S y by ssy alone (its dot products with the geometry derivatives are then bounded
  // through |S y| instead). The forms it gets are those of the default pipeline, apply() then tightenByResidual(),
  // which lowers radius below splitRadius: checked in MPFR at the vertices and random points of boxes of 1/4 ... 1/32
  // of the paper workspace, for J = N C (V = C) and random columns. S = C J^-1(t) - I, y = N v. (The tightened
  // radius has no such part: radius - ssy in place of splitRadius - ssy fails here by two orders of magnitude.)
  const io::RobotFile rf = test::ref6File();
  const model::GoughPlatform robot(rf.geometry);
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const IVec whole = ws.initialBox();
  std::mt19937_64 rng(4801);
  int checked = 0, split = 0, tightened = 0;
  double worst = 0.0;  // largest |x - x-hat - S S y| / (splitRadius - ssy)
  for (int trial = 0; trial < 16; ++trial) {
    const IVec box = cornerOrInnerBox(whole, trial, rng);
    enclosure::BoxInput in;
    ws.poseView(box, true, in);
    enclosure::PreconditionedInverseEnclosure act;
    ASSERT_TRUE(act.prepare(robot, in, enclosure::PreconditionedInverseEnclosure::GeometryTerms::AtCentre))
        << "trial " << trial;
    const DMat& c = act.preconditioner();
    for (int which = 0; which < 2; ++which) {
      const int m = which == 0 ? 6 : 3;
      IMat v(6, m);
      std::uniform_real_distribution<double> unit(-1.0, 1.0);
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < m; ++j) v(i, j) = Interval(which == 0 ? c(i, j) : unit(rng));
      enclosure::PreconditionedInverseEnclosure::AffineMatrix a;
      ASSERT_TRUE(act.apply(v, a,
                            which == 1 ? enclosure::PreconditionedInverseEnclosure::Refinements::ForErrorBounds
                                       : enclosure::PreconditionedInverseEnclosure::Refinements::Standard))
          << "trial " << trial;
      act.tightenByResidual(v, a);
      for (int k = 0; k < 6; ++k)
        for (int j = 0; j < m; ++j) {
          ASSERT_LE(a.radius(k, j), a.splitRadius(k, j));
          tightened += a.radius(k, j) < a.splitRadius(k, j) && a.radius(k, j) < a.splitRadius(k, j) - a.ssy(k, j);
        }
      for (int s = 0; s < 64 + 8; ++s) {
        const DVec t = vertexOrRandomPoint(box, s, rng);
        const MpMat sm = mpPoseResidual(c, rf.geometry, t);
        MpMat cj = sm;
        for (int k = 0; k < 6; ++k) cj[k][k] = cj[k][k] + Mp(1.0);
        MpMat vp(6, std::vector<Mp>(m, Mp(0.0)));
        for (int i = 0; i < 6; ++i)
          for (int j = 0; j < m; ++j) vp[i][j] = Mp(v(i, j).mid());
        const MpMat nv = mpSolve(cj, vp);
        std::vector<Mp> tau;
        for (int i = 0; i < 6; ++i) tau.push_back((Mp(t[i]) - Mp(in.centrePose[i].mid())) / Mp(act.deviation(i)));
        for (int j = 0; j < m; ++j) {
          std::vector<Mp> sy(6, Mp(0.0));
          for (int k = 0; k < 6; ++k)
            for (int l = 0; l < 6; ++l) sy[k] = sy[k] + sm[k][l] * nv[l][j];
          for (int k = 0; k < 6; ++k) {
            if (!(a.ssy(k, j) >= 0.0 && a.ssy(k, j) <= a.splitRadius(k, j))) continue;  // (no split then)
            Mp rest = nv[k][j] - Mp(a.centre(k, j));
            for (int i = 0; i < 6; ++i) rest = rest - Mp(a.pose[i](k, j)) * tau[i];
            for (int l = 0; l < 6; ++l) rest = rest - sm[k][l] * sy[l];
            const double allowed = a.splitRadius(k, j) - a.ssy(k, j);
            EXPECT_TRUE(mpLessEqual(mpAbs(rest), allowed * (1.0 + 1e-12) + 1e-300))
                << "trial " << trial << " sample " << s << " entry " << k << "," << j
                << ": |x - x-hat - S S y| = " << toDouble(mpAbs(rest)) << " > radius - ssy = " << allowed
                << " (splitRadius " << a.splitRadius(k, j) << ", ssy " << a.ssy(k, j) << ")";
            if (allowed > 0.0) worst = std::max(worst, toDouble(mpAbs(rest)) / allowed);
            split += a.ssy(k, j) > 0.0;
            ++checked;
          }
        }
      }
    }
  }
  std::cout << "[ info     ] separable ssy: " << checked << " checks (" << split
            << " with ssy > 0), largest |x - x-hat - S S y| / (splitRadius - ssy) " << worst << "; " << tightened
            << " radii tightened below splitRadius - ssy\n";
  EXPECT_GT(checked, 50000);
  EXPECT_GT(split, checked / 2);
  EXPECT_GT(tightened, 16 * 9);  // the case the split must not be taken from
  EXPECT_GT(worst, 0.05);        // (not vacuous)
}

TEST(ErrorEnclosure, BoxContainingASingularPoseIsUnbounded) {
  const io::RobotFile rf = test::ref6File();
  const model::GoughPlatform robot(rf.geometry);
  std::array<Interval, 6> r = {Interval(-0.01, 0.01), Interval(-0.01, 0.01), Interval(-0.01, 0.01),
                               Interval(-0.01, 0.01), Interval(-0.01, 0.01), Interval(-0.01, 0.01)};
  const domain::Workspace ws = domain::Workspace::fromRanges(r);  // contains the flat singular pose z = 0
  for (const auto& name : enclosure::enclosureNames()) {
    const auto m = enclosure::makeEnclosure(name);
    enclosure::BoxInput in;
    ws.poseView(ws.initialBox(), true, in);
    enclosure::ErrorBounds b;
    m->enclose(robot, in, b);
    EXPECT_FALSE(b.bounded()) << name;
    for (int k = 0; k < 6; ++k) EXPECT_TRUE(std::isinf(b.upper[k]) || b.upper[k] > 1e3) << name;
  }
}

TEST(ErrorEnclosure, MeanValueIsTighterThanPlainPreconditioningOnSmallBoxes) {
  const io::RobotFile rf = test::ref6File();
  const model::GoughPlatform robot(rf.geometry);
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const IVec box = test::centredSubBox(ws.initialBox(), 1.0 / 16.0);
  enclosure::BoxInput in;
  ws.poseView(box, true, in);
  enclosure::ErrorBounds mv, pc;
  enclosure::makeEnclosure("mean_value")->enclose(robot, in, mv);
  enclosure::makeEnclosure("precond")->enclose(robot, in, pc);
  ASSERT_TRUE(mv.bounded());
  for (int k = 0; k < 6; ++k) EXPECT_LT(mv.upper[k], pc.upper[k]) << k;
}

TEST(ErrorEnclosure, ErrorGradientContainsFiniteDifferencesOfTheWorstError) {
  const io::RobotFile rf = test::ref6File();
  const model::GoughPlatform robot(rf.geometry);
  const domain::Workspace& ws = rf.workspaces.at("paper");
  std::mt19937_64 rng(8);
  int checked = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const DVec c = test::randomPoint(ws.initialBox(), rng);
    IVec box(6);
    const double frac = std::pow(0.5, 4 + trial % 5);
    for (int i = 0; i < 6; ++i) {
      const double h = frac * 0.5 * (ws.initialBox()[i].upper() - ws.initialBox()[i].lower());
      box[i] = Interval(c[i] - h, c[i] + h);
    }
    enclosure::BoxInput in;
    ws.poseView(box, true, in);
    in.keepInternals = true;
    enclosure::ErrorBounds b;
    enclosure::makeEnclosure("second_order")->enclose(robot, in, b);
    ASSERT_TRUE(b.internals.valid || !b.bounded());
    for (int k = 0; k < 6; ++k) {
      IVec g;
      if (!enclosure::errorGradient(b, robot.sensorError(), k, g)) continue;
      for (int s = 0; s < 3; ++s) {
        const DVec q = test::randomPoint(box, rng);
        for (int i = 0; i < 6; ++i) {
          const double h = 1e-7 * (1.0 + std::abs(q[i]));
          DVec qp = q, qm = q;
          qp[i] += h;
          qm[i] -= h;
          const double fd = (robot.worstErrorAt(qp)[k] - robot.worstErrorAt(qm)[k]) / (2 * h);
          const double slack = 1e-6 * std::abs(fd) + 1e-12;
          EXPECT_LE(g[i].lower() - slack, fd) << "k=" << k << " i=" << i << " trial " << trial;
          EXPECT_GE(g[i].upper() + slack, fd) << "k=" << k << " i=" << i << " trial " << trial;
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(checked, 5000);
}

TEST(ErrorEnclosure, EveryMethodBoundsEveryAdmissibleGeometryUnderAnchorUncertainty) {
  const io::RobotFile rf = test::ref6File();
  for (const double h : {0.0005, 0.001}) {
    model::GoughGeometry uncertain = rf.geometry;
    uncertain.setUniformAnchorUncertainty(h);
    const model::GoughPlatform robot(uncertain);
    const domain::Workspace& ws = rf.workspaces.at("paper");
    std::mt19937_64 rng(31);
    std::vector<std::unique_ptr<enclosure::ErrorEnclosure>> methods;
    for (const auto& name : enclosure::enclosureNames()) methods.push_back(enclosure::makeEnclosure(name));
    int bounded = 0;
    for (int trial = 0; trial < 150; ++trial) {
      const IVec box = test::centredSubBox(ws.initialBox(), std::pow(0.5, 3 + trial % 4));
      IVec shifted(6);
      const DVec c = test::randomPoint(ws.initialBox(), rng);
      for (int i = 0; i < 6; ++i) {
        const double half = 0.5 * box[i].width(), mid = std::min(std::max(c[i], ws.initialBox()[i].lower() + half),
                                                                 ws.initialBox()[i].upper() - half);
        shifted[i] = Interval(mid - half, mid + half);
      }
      enclosure::BoxInput in;
      ws.poseView(shifted, true, in);
      std::vector<enclosure::ErrorBounds> bounds(methods.size());
      for (std::size_t m = 0; m < methods.size(); ++m) {
        methods[m]->enclose(robot, in, bounds[m]);
        bounded += bounds[m].bounded();
      }
      // Random admissible geometries (vertices of the uncertainty box and interior points) at random poses.
      for (int s = 0; s < 4; ++s) {
        model::GoughGeometry g = rf.geometry;
        std::uniform_real_distribution<double> u(-h, h);
        for (auto* pts : {&g.base_anchors, &g.platform_anchors})
          for (auto& p : *pts)
            for (int k = 0; k < 3; ++k) p[k] += (s % 2 == 0) ? (rng() % 2 ? h : -h) : u(rng);
        const model::GoughPlatform sample(g);
        const DVec q = test::randomPoint(shifted, rng);
        const DVec f = sample.worstErrorAt(q);
        for (std::size_t m = 0; m < methods.size(); ++m)
          for (int k = 0; k < 6; ++k) {
            EXPECT_LE(f[k], bounds[m].upper[k] * (1 + 1e-12)) << methods[m]->name() << " h=" << h << " k=" << k;
            EXPECT_GE(f[k], bounds[m].lower[k] * (1 - 1e-12)) << methods[m]->name() << " h=" << h << " k=" << k;
          }
      }
    }
    EXPECT_GT(bounded, 150);  // the check is not vacuous
  }
}
