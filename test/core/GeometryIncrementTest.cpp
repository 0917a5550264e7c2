// GeometryIncrement under bounded anchor uncertainty (docs/uncertainty.md): its entry bounds DJ_kj hold against
// sampled geometries and reach the worst vertex, alone and as the default pipeline composes them with the
// second_order bound.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "TestRobots.hpp"
#include "UncertaintyFixtures.hpp"
#include "pkm_accuracy/core/domain/Workspace.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/enclosure/GeometryIncrement.hpp"
#include "pkm_accuracy/core/enclosure/PreconditionedInverseEnclosure.hpp"
#include "pkm_accuracy/core/interval/AffineForm.hpp"

using namespace pkm_accuracy;
using namespace pkm_accuracy::test;               // the reference robots (TestRobots.hpp)
using namespace pkm_accuracy::test::uncertainty;  // the uncertain robot (UncertaintyFixtures.hpp)

namespace {

/// The forms of J0 = N C over the box from a nominal expansion (prepared without geometry terms): as apply() gives
/// them, or as the default pipeline uses them, tightened by their residual radius (MeanValueEnclosure).
bool nominalJ0(const enclosure::PreconditionedInverseEnclosure& act, bool tightened,
               enclosure::PreconditionedInverseEnclosure::AffineMatrix& jac) {
  const DMat& c = act.preconditioner();
  IMat all(c.rows(), c.cols());
  for (int j = 0; j < c.cols(); ++j)
    for (int l = 0; l < c.rows(); ++l) all(l, j) = Interval(c(l, j));
  if (!act.apply(all, jac)) return false;
  if (tightened) act.tightenByResidual(all, jac);
  return true;
}

}  // namespace

TEST(UncertaintyEnclosure, GeometryIncrementEntryBoundsHoldAndReachTheWorstVertex) {
  // GeometryIncrement::entryIncrease(k, j) = DJ_kj >= |J_kj(t, g) - J_kj(t, g0)| for every pose of the box and every
  // geometry: the fixed point of |Y| <= A + A |Y| tightened by the sign-coupled phi (tightenFixedPoint), DJ = |J0| Y.
  // Checked at poses of random boxes (thin to 1/8 of the paper workspace) for random geometry vertices and, per
  // entry, the vertex that the signs of dJ_kj / dg_p point to (the worst one to first order). DJ is exact to first
  // order, so on thin boxes the worst vertex must reach most of it (a bound too small by a fifth would fail).
  const io::RobotFile rf = test::ref6File();
  const domain::Workspace& ws = rf.workspaces.at("paper");
  std::mt19937_64 rng(2027);
  int ready = 0, checked = 0;
  double worstThin = 0.0;  // the largest |Delta J_kj| / DJ_kj on thin boxes
  for (const double h : {0.0005, 0.001}) {
    const Uncertain u(withUncertainty(h));
    const model::GoughPlatform robot(u.geometry);
    for (int trial = 0; trial < 12; ++trial) {
      const int size = trial % 4;
      const double fraction = size == 0 ? 0.0 : (size == 1 ? 1.0 / 64.0 : (size == 2 ? 1.0 / 16.0 : 1.0 / 8.0));
      const IVec box = randomSubBox(ws.initialBox(), fraction, rng);
      enclosure::BoxInput in;
      ws.poseView(box, true, in);
      enclosure::PreconditionedInverseEnclosure act;
      ASSERT_TRUE(act.prepare(robot, in, enclosure::PreconditionedInverseEnclosure::GeometryTerms::AtCentre))
          << "trial " << trial;
      enclosure::PreconditionedInverseEnclosure::AffineMatrix jac;
      ASSERT_TRUE(nominalJ0(act, false, jac));
      enclosure::GeometryIncrement increment;
      if (increment.prepare(robot, in, act, jac) != enclosure::GeometryIncrement::Preparation::Ready) continue;
      ++ready;
      for (int s = 0; s < 3; ++s) {
        const DVec q = s == 0 ? test::randomPoint(box, rng) : randomVertexOf(box, rng);
        const DMat j0 = model::GoughPlatform(u.at(u.nominal)).jacobian(q);
        std::vector<DMat> dM;
        for (int p = 0; p < u.count(); ++p) dM.push_back(u.inverseJacobianDerivative(u.nominal, p, q));
        const auto check = [&](const Geometry& g, int onlyK, int onlyJ) {
          const DMat jg = model::GoughPlatform(u.at(g)).jacobian(q);
          for (int k = 0; k < 6; ++k)
            for (int j = 0; j < 6; ++j) {
              if (onlyK >= 0 && (k != onlyK || j != onlyJ)) continue;
              const double diff = std::abs(jg(k, j) - j0(k, j));
              const double dj = increment.entryIncrease(k, j);
              EXPECT_LE(diff, dj * (1.0 + 1e-9) + 1e-12 * std::abs(j0(k, j)))
                  << "k=" << k << " j=" << j << " h=" << h << " trial " << trial << " " << where(q);
              if (size == 0 && dj > 1e-3 * j0.row(k).cwiseAbs().maxCoeff()) worstThin = std::max(worstThin, diff / dj);
              ++checked;
            }
        };
        check(u.randomVertex(rng), -1, -1);
        check(u.randomVertex(rng), -1, -1);
        for (int k = 0; k < 6; ++k)
          for (int j = 0; j < 6; ++j) {
            // dJ_kj / dg_p = -(J0 dM_p J0)_kj: the vertex raising J_kj - J0_kj or lowering it, whichever is larger.
            Geometry up(u.count()), down(u.count());
            for (int p = 0; p < u.count(); ++p) {
              const double slope = -(j0.row(k) * dM[p] * j0.col(j))(0, 0);
              up[p] = slope >= 0.0 ? u.hi[p] : u.lo[p];
              down[p] = slope >= 0.0 ? u.lo[p] : u.hi[p];
            }
            check(up, k, j);
            check(down, k, j);
          }
      }
    }
  }
  EXPECT_GE(ready, 16);
  EXPECT_GT(checked, 3000);
  EXPECT_GT(worstThin, 0.8);
  std::cout << "[ info     ] largest |Delta J_kj| / DJ_kj on thin boxes: " << worstThin << "\n";
}

TEST(UncertaintyEnclosure, PipelineBoundsHoldAgainstDenseSamplesAtWideGeometryRanges) {
  // The geometry increment and the per-box bound as the default pipeline composes them (the nominal expansion's
  // forms of J0 = N C tightened by their residual radius, then GeometryIncrement; second_order with the decomposed
  // geometry form), at +-1 to 3 mm on boxes of 1/16 and 1/8 of the paper workspace, where the residual tightening
  // lowers most radii: DJ_kj >= |J_kj(t, g) - J_kj(t, g0)| and f_k(t, g) <= upper_k at dense samples of pose x
  // geometry (box vertices and random points; geometry vertices, random interior points and the worst vertex by the
  // gradient's signs).
  const io::RobotFile rf = test::ref6File();
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const auto method = enclosure::makeEnclosure("second_order");
  std::mt19937_64 rng(4811);
  int increments = 0, bounds = 0, tightenedColumns = 0;
  double worstIncrement = 0.0, worstBound = 0.0;  // largest sampled / certified
  for (const double h : {0.001, 0.002, 0.003}) {
    const Uncertain u(withUncertainty(h));
    const model::GoughPlatform robot(u.geometry);
    for (int trial = 0; trial < 8; ++trial) {
      const IVec box = randomSubBox(ws.initialBox(), trial % 2 ? 1.0 / 8.0 : 1.0 / 16.0, rng);
      enclosure::BoxInput in;
      ws.poseView(box, true, in);
      enclosure::PreconditionedInverseEnclosure act;
      ASSERT_TRUE(act.prepare(robot, in, enclosure::PreconditionedInverseEnclosure::GeometryTerms::AtCentre))
          << "trial " << trial;
      enclosure::PreconditionedInverseEnclosure::AffineMatrix jac;
      ASSERT_TRUE(nominalJ0(act, true, jac));
      for (int j = 0; j < 6; ++j)
        tightenedColumns += (jac.radius.col(j).array() < jac.splitRadius.col(j).array()).any();
      enclosure::GeometryIncrement increment;
      const bool ready = increment.prepare(robot, in, act, jac) == enclosure::GeometryIncrement::Preparation::Ready;
      in.decomposeGeometry = true;
      enclosure::ErrorBounds b;
      method->enclose(robot, in, b);
      for (int s = 0; s < 24; ++s) {
        const DVec q = s % 3 ? randomVertexOf(box, rng) : test::randomPoint(box, rng);
        const DMat j0 = model::GoughPlatform(u.at(u.nominal)).jacobian(q);
        const Eigen::MatrixXd grad = u.gradient(u.nominal, q);
        std::vector<Geometry> geometries = {u.randomVertex(rng), u.randomVertex(rng), u.randomInterior(rng)};
        for (int k = 0; k < 6; ++k) geometries.push_back(u.vertexBySigns(grad, k, 1.0));
        for (const Geometry& g : geometries) {
          const model::GoughPlatform at(u.at(g));
          if (ready) {
            const DMat jg = at.jacobian(q);
            for (int k = 0; k < 6; ++k)
              for (int j = 0; j < 6; ++j) {
                const double diff = std::abs(jg(k, j) - j0(k, j)), dj = increment.entryIncrease(k, j);
                EXPECT_LE(diff, dj * (1.0 + 1e-9) + 1e-12 * std::abs(j0(k, j)))
                    << "DJ(" << k << "," << j << ") h=" << h << " trial " << trial << " " << where(q);
                if (dj > 0.0) worstIncrement = std::max(worstIncrement, diff / dj);
                ++increments;
              }
          }
          if (!b.bounded()) continue;
          const DVec f = at.worstErrorAt(q);
          for (int k = 0; k < 6; ++k) {
            EXPECT_LE(f[k], b.upper[k] * (1.0 + 1e-12))
                << "f_" << k << " h=" << h << " trial " << trial << " " << where(q);
            worstBound = std::max(worstBound, f[k] / b.upper[k]);
            ++bounds;
          }
        }
      }
    }
  }
  std::cout << "[ info     ] wide geometry ranges: " << increments << " increments (largest |Delta J| / DJ "
            << worstIncrement << "), " << bounds << " bounds (largest f / upper " << worstBound << "), "
            << tightenedColumns << " columns of J0 tightened\n";
  EXPECT_GT(increments, 20000);
  EXPECT_GT(bounds, 3000);
  EXPECT_GT(tightenedColumns, 48);
  EXPECT_GT(worstIncrement, 0.3);
  EXPECT_GT(worstBound, 0.5);
}
