// The geometry-parameter API of GoughPlatform under bounded anchor uncertainty (docs/uncertainty.md): count,
// names, ranges, centres, restrictGeometry, fixGeometryParameters, geometryDerivatives and their affine forms against
// finite differences, the inverse Jacobian's enclosures over every geometry and at the centre.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "TestRobots.hpp"
#include "UncertaintyFixtures.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/Workspace.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/enclosure/GeometryIncrement.hpp"
#include "pkm_accuracy/core/interval/AffineForm.hpp"

using namespace pkm_accuracy;
using namespace pkm_accuracy::test;               // the reference robots (TestRobots.hpp)
using namespace pkm_accuracy::test::uncertainty;  // the uncertain robot (UncertaintyFixtures.hpp)

// =====================================================================================================================
// The geometry-parameter API
// =====================================================================================================================

TEST(UncertaintyModel, NominalRobotHasNoGeometryParametersAndTheDefaultsThrow) {
  const model::GoughPlatform robot(withUncertainty(0.0));
  EXPECT_FALSE(robot.hasGeometryUncertainty());
  EXPECT_EQ(robot.geometryParameterCount(), 0);
  EXPECT_THROW(robot.geometryParameterName(0), InvalidArgument);
  EXPECT_THROW(robot.geometryParameterRange(0), InvalidArgument);
  EXPECT_THROW(robot.geometryParameterCentre(0), InvalidArgument);
  EXPECT_THROW(robot.restrictGeometry({}), InvalidArgument);
  EXPECT_THROW(robot.restrictGeometry({Interval(0.0)}), InvalidArgument);
  GeometryDerivatives d;
  d.count = 5;
  robot.geometryDerivatives(thinOf(DVec::Constant(6, 0.0) + DVec::Unit(6, 2) * 0.47), d);
  EXPECT_EQ(d.count, 0);
  // The centre-geometry enclosures are the plain ones.
  const IVec pose = thinOf((DVec(6) << 0.01, -0.02, 0.47, 0.05, -0.03, 0.1).finished());
  const IMat a = robot.inverseJacobian(pose), b = robot.inverseJacobianAtGeometryCentre(pose);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) EXPECT_TRUE(a(i, j) == b(i, j));
}

TEST(UncertaintyModel, ParametersNamesRangesAndCentresFollowTheDocumentedOrder) {
  static const char* kAxis[3] = {"x", "y", "z"};
  for (const double h : {0.0005, 0.001}) {
    const model::GoughGeometry g = withUncertainty(h);
    const model::GoughPlatform robot(g);
    EXPECT_TRUE(robot.hasGeometryUncertainty());
    ASSERT_EQ(robot.geometryParameterCount(), 36);
    for (int p = 0; p < 36; ++p) {
      const bool base = p < 18;
      const int leg = (p % 18) / 3, axis = p % 3;
      const std::string expected =
          std::string(base ? "base_anchors[" : "platform_anchors[") + std::to_string(leg) + "]." + kAxis[axis];
      EXPECT_EQ(robot.geometryParameterName(p), expected);
      const double v = base ? g.base_anchors[leg][axis] : g.platform_anchors[leg][axis];
      const Interval r = robot.geometryParameterRange(p);
      // Contains the admissible range, and not much more (outward rounding only).
      EXPECT_LE(r.lower(), v - h) << expected;
      EXPECT_GE(r.upper(), v + h) << expected;
      EXPECT_LE(r.upper() - r.lower(), 2.0 * h * (1 + 1e-12) + 1e-15) << expected;
      const double c = robot.geometryParameterCentre(p);
      EXPECT_TRUE(r.contains(c));
      EXPECT_NEAR(c, v, 1e-15) << expected;
    }
    for (const int bad : {-1, 36, 1000}) {
      EXPECT_THROW(robot.geometryParameterName(bad), InvalidArgument);
      EXPECT_THROW(robot.geometryParameterRange(bad), InvalidArgument);
      EXPECT_THROW(robot.geometryParameterCentre(bad), InvalidArgument);
    }
  }
  // Only the coordinates with a non-zero half-width are parameters; the tool point comes last.
  model::GoughGeometry g = withUncertainty(0.0);
  g.platform_anchor_halfwidth.assign(6, Eigen::Vector3d::Zero());
  g.platform_anchor_halfwidth[4] = Eigen::Vector3d(0.0, 0.002, 0.0);
  g.tool_point = Eigen::Vector3d(0.01, -0.02, 0.03);
  g.tool_point_halfwidth = Eigen::Vector3d(0.0003, 0.0, 0.0002);
  const model::GoughPlatform robot(g);
  ASSERT_EQ(robot.geometryParameterCount(), 3);
  EXPECT_EQ(robot.geometryParameterName(0), "platform_anchors[4].y");
  EXPECT_EQ(robot.geometryParameterName(1), "tool_point.x");
  EXPECT_EQ(robot.geometryParameterName(2), "tool_point.z");
  EXPECT_NEAR(robot.geometryParameterRange(2).lower(), 0.0298, 1e-15);
  EXPECT_NEAR(robot.geometryParameterRange(2).upper(), 0.0302, 1e-15);
}

TEST(UncertaintyModel, RestrictGeometryAcceptsSubIntervalsAndPointsAndRejectsTheRest) {
  const double h = 0.001;
  const Uncertain u(withUncertainty(h));
  const model::GoughPlatform robot(u.geometry);
  const int n = robot.geometryParameterCount();
  ASSERT_EQ(n, u.count());
  std::vector<Interval> full(n);
  for (int p = 0; p < n; ++p) full[p] = robot.geometryParameterRange(p);

  // Sub-intervals: kept exactly, numbering kept, centres inside, still uncertain; nested restriction works.
  std::mt19937_64 rng(101);
  std::vector<Interval> sub(n);
  for (int p = 0; p < n; ++p) {
    double a = std::uniform_real_distribution<double>(full[p].lower(), full[p].upper())(rng);
    double b = std::uniform_real_distribution<double>(full[p].lower(), full[p].upper())(rng);
    if (a > b) std::swap(a, b);
    sub[p] = p == 7 ? full[p] : Interval(a, b);
  }
  const auto restricted = robot.restrictGeometry(sub);
  ASSERT_EQ(restricted->geometryParameterCount(), n);
  EXPECT_TRUE(restricted->hasGeometryUncertainty());
  for (int p = 0; p < n; ++p) {
    EXPECT_EQ(restricted->geometryParameterName(p), robot.geometryParameterName(p));
    EXPECT_TRUE(restricted->geometryParameterRange(p) == sub[p]) << p;
    EXPECT_TRUE(sub[p].contains(restricted->geometryParameterCentre(p))) << p;
  }
  std::vector<Interval> halves = sub;
  for (int p = 0; p < n; ++p) halves[p] = sub[p].bisect().second;
  EXPECT_NO_THROW(restricted->restrictGeometry(halves));
  // ... but not back to the wider original ranges.
  try {
    restricted->restrictGeometry(full);
    ADD_FAILURE() << "widening a restricted range was accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("geometry ranges["), std::string::npos) << e.what();
  }

  // Points: the restricted model is that exact robot (double J^-1 bit for bit, enclosures contain it, tight).
  for (int trial = 0; trial < 3; ++trial) {
    const Geometry values = trial == 0 ? u.randomVertex(rng) : u.randomInterior(rng);
    std::vector<Interval> points(n);
    for (int p = 0; p < n; ++p) points[p] = Interval(values[p]);
    const auto pointModel = robot.restrictGeometry(points);
    EXPECT_FALSE(pointModel->hasGeometryUncertainty());
    ASSERT_EQ(pointModel->geometryParameterCount(), n);
    const model::GoughPlatform exact(u.at(values));
    const IVec ws = test::ref6File().workspaces.at("paper").initialBox();
    for (int s = 0; s < 20; ++s) {
      const DVec q = test::randomPoint(ws, rng);
      const DMat a = pointModel->inverseJacobian(q), b = exact.inverseJacobian(q);
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) EXPECT_EQ(a(i, j), b(i, j)) << i << "," << j;
      const DVec fa = pointModel->worstErrorAt(q), fb = exact.worstErrorAt(q);
      for (int k = 0; k < 6; ++k) EXPECT_EQ(fa[k], fb[k]);
      const IMat enc = pointModel->inverseJacobian(thinOf(q));
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) {
          EXPECT_TRUE(enc(i, j).contains(b(i, j)));
          EXPECT_LT(enc(i, j).upper() - enc(i, j).lower(), 1e-13);
        }
    }
  }

  // Bad input: typed errors naming the field.
  auto expectInvalid = [&](const std::vector<Interval>& ranges, const std::string& field) {
    try {
      robot.restrictGeometry(ranges);
      ADD_FAILURE() << "expected InvalidArgument naming " << field;
    } catch (const InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  expectInvalid(std::vector<Interval>(full.begin(), full.end() - 1), "geometry ranges");
  std::vector<Interval> longer = full;
  longer.push_back(Interval(0.0));
  expectInvalid(longer, "geometry ranges");
  expectInvalid({}, "geometry ranges");
  std::vector<Interval> bad = full;
  bad[5] = Interval(full[5].lower() - 1e-6, full[5].upper());
  expectInvalid(bad, "geometry ranges[5] (base_anchors[1].z)");
  bad = full;
  bad[20] = Interval(full[20].upper() + 1e-9);  // a point outside
  expectInvalid(bad, "geometry ranges[20] (platform_anchors[0].z)");
  bad = full;
  bad[33] = Interval::empty();
  expectInvalid(bad, "geometry ranges[33] (platform_anchors[5].x)");
}

TEST(UncertaintyModel, GeometryDerivativesContainFiniteDifferences) {
  // Uniform anchor uncertainty, and a case with an uncertain tool point (its parameters move every row).
  model::GoughGeometry withTool = withUncertainty(0.0005);
  withTool.tool_point = Eigen::Vector3d(0.01, -0.015, 0.04);
  withTool.tool_point_halfwidth = Eigen::Vector3d(0.0004, 0.0003, 0.0002);
  const IVec ws = test::ref6File().workspaces.at("paper").initialBox();
  std::mt19937_64 rng(202);
  int checked = 0;
  for (const auto& g : {withUncertainty(0.0005), withUncertainty(0.001), withTool}) {
    const Uncertain u(g);
    const model::GoughPlatform robot(g);
    const int n = robot.geometryParameterCount();
    ASSERT_EQ(n, u.count());
    const bool tool = g.tool_point_halfwidth.norm() > 0.0;
    EXPECT_EQ(n, tool ? 39 : 36);
    for (int trial = 0; trial < 6; ++trial) {
      // A thin pose or a small pose box, and a point geometry model (tight enclosures) next to the full one.
      const IVec box = randomSubBox(ws, trial % 2 == 0 ? 0.0 : 1.0 / 64.0, rng);
      const Geometry values = trial % 3 == 0 ? u.nominal : u.randomInterior(rng);
      std::vector<Interval> points(n);
      for (int p = 0; p < n; ++p) points[p] = Interval(values[p]);
      const auto pointModel = robot.restrictGeometry(points);
      GeometryDerivatives whole, atPoint;
      ASSERT_TRUE(robot.geometryDerivatives(box, whole));
      const DVec q = test::randomPoint(box, rng);
      ASSERT_TRUE(pointModel->geometryDerivatives(thinOf(q), atPoint));
      // Structure: one entry per (parameter, row it moves): an anchor moves the row of its leg, the tool point
      // every row.
      for (const GeometryDerivatives* d : {&whole, &atPoint}) {
        int expected = 0;
        for (int p = 0; p < n; ++p) expected += u.coords[p].kind == 2 ? 6 : 1;
        ASSERT_EQ(d->count, expected);
        std::vector<std::vector<int>> rows(n);
        for (int e = 0; e < d->count; ++e) {
          const GeometryRowDerivative& r = d->entries[e];
          ASSERT_GE(r.parameter, 0);
          ASSERT_LT(r.parameter, n);
          rows[r.parameter].push_back(r.row);
        }
        for (int p = 0; p < n; ++p) {
          std::sort(rows[p].begin(), rows[p].end());
          if (u.coords[p].kind == 2) {
            EXPECT_EQ(rows[p], std::vector<int>({0, 1, 2, 3, 4, 5})) << p;
          } else {
            EXPECT_EQ(rows[p], std::vector<int>({u.coords[p].leg})) << p;
          }
        }
      }
      // Values: central differences of the double J^-1 of the concrete geometry, in the whole-box enclosure at a
      // pose of the box, and in the point-geometry enclosure at that pose, which must be tight.
      const double tol = 2e-7;
      for (int p = 0; p < n; ++p) {
        const DMat fd = u.inverseJacobianDerivative(values, p, q);
        std::vector<bool> listed(6, false);
        for (const GeometryDerivatives* d : {&whole, &atPoint}) {
          for (int e = 0; e < d->count; ++e) {
            const GeometryRowDerivative& r = d->entries[e];
            if (r.parameter != p) continue;
            listed[r.row] = true;
            for (int j = 0; j < 6; ++j) {
              const double slack = tol * (1.0 + std::abs(fd(r.row, j)));
              EXPECT_LE(r.d[j].toInterval().lower() - slack, fd(r.row, j))
                  << robot.geometryParameterName(p) << " row " << r.row << " col " << j;
              EXPECT_GE(r.d[j].toInterval().upper() + slack, fd(r.row, j))
                  << robot.geometryParameterName(p) << " row " << r.row << " col " << j;
              if (d == &atPoint) {
                EXPECT_LT(r.d[j].toInterval().upper() - r.d[j].toInterval().lower(),
                          1e-12 * (1.0 + std::abs(fd(r.row, j))));
              }
              ++checked;
            }
          }
        }
        // Rows not listed do not move.
        for (int row = 0; row < 6; ++row)
          if (!listed[row]) {
            for (int j = 0; j < 6; ++j) EXPECT_LE(std::abs(fd(row, j)), 1e-9) << p << " row " << row;
          }
      }
    }
  }
  EXPECT_GT(checked, 3 * 6 * 36 * 6);
}

TEST(UncertaintyModel, CoordinateBoundsMoveToTheCentreAndContainTheRange) {
  // Offsets [lo, hi]: the coordinate moves to the centre of [v + lo, v + hi] and the half-width covers that range
  // (checked in long double, where these sums and differences of doubles of similar size are exact).
  std::mt19937_64 rng(204);
  std::uniform_real_distribution<double> value(-0.3, 0.3), offset(-2e-3, 2e-3);
  for (int trial = 0; trial < 2000; ++trial) {
    const double v = value(rng);
    double lo = offset(rng), hi = offset(rng);
    if (lo > hi) std::swap(lo, hi);
    if (trial % 7 == 0) {  // one-sided
      lo = 0.0;
      hi = std::abs(hi);
    }
    if (trial % 11 == 0) hi = lo;  // a single value
    double c = v, h = -1.0;
    model::applyCoordinateBound(model::CoordinateBound::offsets(lo, hi), c, h);
    EXPECT_GE(h, 0.0);
    EXPECT_LE(static_cast<long double>(c) - h, static_cast<long double>(v) + lo) << v << " " << lo << " " << hi;
    EXPECT_GE(static_cast<long double>(c) + h, static_cast<long double>(v) + hi) << v << " " << lo << " " << hi;
    EXPECT_NEAR(c, v + 0.5 * (lo + hi), 1e-15);
    EXPECT_NEAR(h, 0.5 * (hi - lo), 1e-15);
  }
  // A half-width keeps the value.
  double c = 0.1, h = 0.0;
  model::applyCoordinateBound(model::CoordinateBound::halfwidth(1e-3), c, h);
  EXPECT_EQ(c, 0.1);
  EXPECT_EQ(h, 1e-3);
  // Bad bounds throw, naming what was expected.
  const auto message = [](const model::CoordinateBound& b) {
    double x = 0.1, w = 0.0;
    try {
      model::applyCoordinateBound(b, x, w);
    } catch (const InvalidGeometry& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(model::CoordinateBound::offsets(1e-3, -1e-3)).find("lo <= hi"), std::string::npos);
  EXPECT_NE(message(model::CoordinateBound::halfwidth(-1e-3)).find(">= 0"), std::string::npos);
  EXPECT_NE(message(model::CoordinateBound::offsets(0.0, std::numeric_limits<double>::infinity())).find("finite"),
            std::string::npos);
  EXPECT_NE(message(model::CoordinateBound::halfwidth(std::nan(""))).find("finite"), std::string::npos);
}

TEST(UncertaintyModel, AffineGeometryDerivativesHoldAtEveryVertex) {
  // The anchors' entries carry first-order affine forms in the pose (GeometryRowDerivative::affine): at every pose t
  // of the box and every admissible geometry, component l of the derivative lies within radius[l] of
  // centre[l] + sum_m slope[l][m] tau_m, tau_m = (t_m - c_m) / a_m with (c_m, a_m) the model's scaling of pose
  // coordinate m (AffineForm::variable). Checked against central differences of the double J^-1 of the concrete
  // geometry (error ~ 1e-9 of the entries, far below the radii on these boxes) at the 64 vertices and 16 random
  // poses of boxes of 1/16 and 1/64 of the paper workspace, at vertex and interior geometries. The largest residual
  // must also reach a good part of its radius, so that a radius too small by a factor would fail.
  // With GeometryDerivatives::withParameterSlopes (what GeometryIncrement asks for), the forms also have terms in
  // the leg's anchor coordinates, sum_s parameterSlope[l][s] gamma_s, and the radius is only their remainder.
  using Aff = interval::AffineForm<kMaxDof>;
  const IVec ws = test::ref6File().workspaces.at("paper").initialBox();
  std::mt19937_64 rng(606);
  double worst[2] = {0.0, 0.0};  // the largest residual / radius, without and with the parameter terms
  double narrower = 0.0;         // the largest radius without the parameter terms / with them
  int checked = 0;
  for (const double h : {0.0005, 0.001})
    for (const bool withSlopes : {false, true}) {
      const Uncertain u(withUncertainty(h));
      const model::GoughPlatform robot(u.geometry);
      const int n = robot.geometryParameterCount();
      for (int trial = 0; trial < 4; ++trial) {
        const IVec box = randomSubBox(ws, trial % 2 == 0 ? 1.0 / 16.0 : 1.0 / 64.0, rng);
        GeometryDerivatives geo, plainGeo;
        geo.withParameterSlopes = withSlopes;
        ASSERT_TRUE(robot.geometryDerivatives(box, geo));
        ASSERT_TRUE(robot.geometryDerivatives(box, plainGeo));
        for (int e = 0; e < geo.count && withSlopes; ++e)
          for (int l = 0; l < 6; ++l)
            narrower = std::max(narrower, plainGeo.entries[e].radius[l] / geo.entries[e].radius[l]);
        double c[kMaxDof], a[kMaxDof];
        for (int m = 0; m < kMaxDof; ++m) {
          const Aff v = Aff::variable(box[m], m);
          c[m] = v.centre();
          a[m] = v.coefficient(m);
        }
        for (int sample = 0; sample < 80; ++sample) {
          DVec q(6);
          if (sample < 64) {
            for (int m = 0; m < 6; ++m) q[m] = (sample >> m) & 1 ? box[m].upper() : box[m].lower();
          } else {
            q = test::randomPoint(box, rng);
          }
          const Geometry values = sample % 2 == 0 ? u.randomVertex(rng) : u.randomInterior(rng);
          double tau[kMaxDof];
          for (int m = 0; m < kMaxDof; ++m) tau[m] = (q[m] - c[m]) / a[m];
          for (int p = 0; p < n; ++p) {
            const DMat fd = u.inverseJacobianDerivative(values, p, q);
            for (int e = 0; e < geo.count; ++e) {
              const GeometryRowDerivative& r = geo.entries[e];
              if (r.parameter != p) continue;
              ASSERT_TRUE(r.affine) << robot.geometryParameterName(p);
              ASSERT_EQ(r.parameterSlopes, withSlopes);
              for (int l = 0; l < 6; ++l) {
                double lin = r.centre[l];
                for (int m = 0; m < kMaxDof; ++m) lin += r.slope[l][m] * tau[m];
                for (int t = 0; t < kMaxDof && withSlopes; ++t) {
                  const int q = r.slopeParameter[t];
                  if (q < 0) continue;
                  ASSERT_GT(r.parameterScale[t], 0.0);
                  lin += r.parameterSlope[l][t] * (values[q] - robot.geometryParameterCentre(q)) / r.parameterScale[t];
                }
                const double residual = std::abs(fd(r.row, l) - lin);
                const double slack = 2e-7 * (1.0 + std::abs(fd(r.row, l)));
                ASSERT_LE(residual, r.radius[l] + slack)
                    << robot.geometryParameterName(p) << " component " << l << " at " << where(q) << ", h " << h;
                if (r.radius[l] > 1e3 * slack) worst[withSlopes] = std::max(worst[withSlopes], residual / r.radius[l]);
                // The range (the midpoint-radius enclosure) contains it too.
                EXPECT_LE(r.d[l].toInterval().lower() - slack, fd(r.row, l));
                EXPECT_GE(r.d[l].toInterval().upper() + slack, fd(r.row, l));
                ++checked;
              }
            }
          }
        }
      }
    }
  std::cout << "[ info     ] largest residual / radius: " << worst[0] << ", with the parameter terms " << worst[1]
            << " (radii up to " << narrower << "x narrower; " << checked << " checks)\n";
  EXPECT_GT(worst[0], 0.3);
  EXPECT_GT(worst[1], 0.3);
  EXPECT_GT(narrower, 2.0);
  EXPECT_EQ(checked, 2 * 2 * 4 * 80 * 36 * 6);
}

TEST(UncertaintyModel, EnclosuresOfTheInverseJacobianCoverEveryGeometryAndTheCentre) {
  const Uncertain u(withUncertainty(0.001));
  const model::GoughPlatform robot(u.geometry);
  const int n = robot.geometryParameterCount();
  Geometry centre(n);
  for (int p = 0; p < n; ++p) centre[p] = robot.geometryParameterCentre(p);
  const model::GoughPlatform centreRobot(u.at(centre));
  const domain::Workspace& ws = test::ref6File().workspaces.at("paper");
  std::mt19937_64 rng(303);
  for (int trial = 0; trial < 20; ++trial) {
    const IVec box = randomSubBox(ws.initialBox(), trial % 2 ? 1.0 / 32.0 : 0.0, rng);
    const IMat all = robot.inverseJacobian(box), atCentre = robot.inverseJacobianAtGeometryCentre(box);
    enclosure::BoxInput in;
    ws.poseView(box, true, in);
    MatrixWithGradient mg;
    robot.inverseJacobianAtGeometryCentre(in.dualPose, mg);
    for (int s = 0; s < 5; ++s) {
      const DVec q = test::randomPoint(box, rng);
      const DMat c = centreRobot.inverseJacobian(q);
      const DMat any =
          model::GoughPlatform(u.at(s % 2 ? u.randomVertex(rng) : u.randomInterior(rng))).inverseJacobian(q);
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) {
          EXPECT_TRUE(atCentre(i, j).contains(c(i, j))) << i << "," << j;
          EXPECT_TRUE(mg.value(i, j).contains(c(i, j))) << i << "," << j;
          EXPECT_TRUE(all(i, j).contains(any(i, j))) << i << "," << j;
        }
      // Pose derivatives at the centre geometry against central differences.
      for (int v = 0; v < 6; ++v) {
        const double step = 1e-7;
        DVec qp = q, qm = q;
        qp[v] += step;
        qm[v] -= step;
        if (!box[v].contains(qp[v]) || !box[v].contains(qm[v])) continue;
        const DMat fd = (centreRobot.inverseJacobian(qp) - centreRobot.inverseJacobian(qm)) / (2.0 * step);
        for (int i = 0; i < 6; ++i)
          for (int j = 0; j < 6; ++j) {
            const double slack = 2e-7 * (1.0 + std::abs(fd(i, j)));
            EXPECT_LE(mg.d[v](i, j).lower() - slack, fd(i, j));
            EXPECT_GE(mg.d[v](i, j).upper() + slack, fd(i, j));
          }
      }
    }
  }
}

TEST(UncertaintyModel, FixGeometryParametersKeepsTheFreeOnesInOrderAndRejectsTheRest) {
  const Uncertain u(withUncertainty(0.001));
  const model::GoughPlatform robot(u.geometry);
  const int params = robot.geometryParameterCount();
  ASSERT_EQ(params, 36);
  GVec values = GVec::Constant(params, std::numeric_limits<double>::quiet_NaN());
  values[0] = robot.geometryParameterRange(0).upper();
  values[7] = robot.geometryParameterRange(7).lower();
  values[35] = robot.geometryParameterCentre(35);
  const auto face = robot.fixGeometryParameters(values);
  ASSERT_EQ(face->geometryParameterCount(), 33);
  EXPECT_TRUE(face->hasGeometryUncertainty());
  for (int p = 0, q = 0; p < params; ++p) {
    if (!std::isnan(values[p])) continue;
    EXPECT_EQ(face->geometryParameterName(q), robot.geometryParameterName(p));
    EXPECT_EQ(face->geometryParameterRange(q).lower(), robot.geometryParameterRange(p).lower());
    EXPECT_EQ(face->geometryParameterRange(q).upper(), robot.geometryParameterRange(p).upper());
    ++q;
  }
  // Every parameter fixed: the robot of that geometry, without uncertainty (same J^-1 in double and intervals).
  std::mt19937_64 rng(707);
  const Geometry vertex = u.randomVertex(rng);
  GVec all(params);
  for (int p = 0; p < params; ++p) all[p] = vertex[p];
  const auto fixed = robot.fixGeometryParameters(all);
  EXPECT_EQ(fixed->geometryParameterCount(), 0);
  EXPECT_FALSE(fixed->hasGeometryUncertainty());
  const model::GoughPlatform reference(u.at(vertex));
  const DVec q = test::randomPoint(test::ref6File().workspaces.at("paper").initialBox(), rng);
  EXPECT_EQ(fixed->inverseJacobian(q), reference.inverseJacobian(q));
  const IMat a = fixed->inverseJacobian(thinOf(q)), b = reference.inverseJacobian(thinOf(q));
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      EXPECT_EQ(a(i, j).lower(), b(i, j).lower());
      EXPECT_EQ(a(i, j).upper(), b(i, j).upper());
    }
  // Bad input: wrong size, a value outside its range (named), a robot without parameters.
  EXPECT_THROW(robot.fixGeometryParameters(GVec::Constant(35, 0.0)), InvalidArgument);
  GVec outside = values;
  outside[3] = robot.geometryParameterRange(3).upper() + 1e-6;
  try {
    robot.fixGeometryParameters(outside);
    ADD_FAILURE() << "no exception";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find(robot.geometryParameterName(3)), std::string::npos) << e.what();
  }
  EXPECT_THROW(model::GoughPlatform(withUncertainty(0.0)).fixGeometryParameters(GVec()), InvalidArgument);
}
