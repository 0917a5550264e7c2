// Bounded geometric uncertainty on the anchor points (every anchor coordinate known to +-h; docs/uncertainty.md).
//
// The evidence is independent of the code under test: admissible geometries are built here as plain GoughGeometry
// values (nominal +- h per coordinate, in the documented parameter order), the worst error at a pose and a geometry
// is computed in MPFR (200 bits) or in double with a relative margin of 1e-12, and the worst geometries are found
// here by the signs of central finite differences of f_k with respect to the anchor coordinates (the "worst
// vertex", refined by single-coordinate flips where f_k is not smooth), plus random vertices and interior points of
// the uncertainty box.
//
//   UncertaintyModel*      geometry-parameter API of GoughPlatform (count, names, ranges, centres, restrictGeometry,
//                          geometryDerivatives against finite differences);
//   UncertaintyEnclosure*  soundness of the second_order enclosure and of errorAtPose over pose boxes x geometries;
//   UncertaintyPreconditionedInverse*
//                          PreconditionedInverseEnclosure: the affine forms (and combine()) contain N V computed in
//                          MPFR;
//   UncertaintyVerifier*   the verifier on the reference robot (max-error brackets, SAFE / UNSAFE /
//                          uncertainty-sensitive verdicts checked independently), strategy (b), nominal invariance;
//   UncertaintyRegression*: reproducers of problems once found in the core (fixed; kept as regression tests).
#include <gtest/gtest.h>
#include <mpfr.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <Eigen/LU>

#include "MpfrGough.hpp"
#include "TestRobots.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/Workspace.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/enclosure/GeometryIncrement.hpp"
#include "pkm_accuracy/core/enclosure/PreconditionedInverseEnclosure.hpp"
#include "pkm_accuracy/core/interval/AffineForm.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"

using namespace pkm_accuracy;
using namespace pkm_accuracy::test;  // the MPFR reference toolkit (MpfrGough.hpp)
using verify::UndecidedReason;
using verify::Verdict;

namespace {

// ---- admissible geometries, built here ------------------------------------------------------------------------------
using Geometry = std::vector<double>;  ///< one value per geometry parameter

/// The coordinates with a non-zero half-width, in the documented parameter order: base anchors leg-major x, y, z,
/// then platform anchors, then the tool point; each with its nominal value and half-width.
struct Coordinate {
  int kind;  // 0 base, 1 platform, 2 tool
  int leg, axis;
  double nominal, half;
};

std::vector<Coordinate> uncertainCoordinates(const model::GoughGeometry& g) {
  std::vector<Coordinate> out;
  for (int kind = 0; kind < 2; ++kind) {
    const auto& anchors = kind == 0 ? g.base_anchors : g.platform_anchors;
    const auto& halves = kind == 0 ? g.base_anchor_halfwidth : g.platform_anchor_halfwidth;
    for (int i = 0; i < 6; ++i)
      for (int a = 0; a < 3; ++a) {
        const double h = halves.empty() ? 0.0 : halves[i][a];
        if (h > 0.0) out.push_back({kind, i, a, anchors[i][a], h});
      }
  }
  for (int a = 0; a < 3; ++a)
    if (g.tool_point_halfwidth[a] > 0.0) out.push_back({2, 0, a, g.tool_point[a], g.tool_point_halfwidth[a]});
  return out;
}

/// An uncertain robot as seen by the tests: the model under test and, independently, the admissible box
/// [nominal - h, nominal + h] of every uncertain coordinate.
struct Uncertain {
  model::GoughGeometry geometry;  ///< with its half-widths
  std::vector<Coordinate> coords;
  Geometry lo, hi, nominal;
  explicit Uncertain(const model::GoughGeometry& g) : geometry(g), coords(uncertainCoordinates(g)) {
    for (const Coordinate& c : coords) {
      lo.push_back(c.nominal - c.half);
      hi.push_back(c.nominal + c.half);
      nominal.push_back(c.nominal);
    }
  }
  int count() const { return static_cast<int>(coords.size()); }

  /// The concrete geometry (no uncertainty left) with the uncertain coordinates at `values`.
  model::GoughGeometry at(const Geometry& values) const {
    model::GoughGeometry g = geometry;
    for (std::size_t p = 0; p < coords.size(); ++p) {
      const Coordinate& c = coords[p];
      if (c.kind == 0) g.base_anchors[c.leg][c.axis] = values[p];
      if (c.kind == 1) g.platform_anchors[c.leg][c.axis] = values[p];
      if (c.kind == 2) g.tool_point[c.axis] = values[p];
    }
    g.base_anchor_halfwidth.clear();
    g.platform_anchor_halfwidth.clear();
    g.tool_point_halfwidth = Eigen::Vector3d::Zero();
    return g;
  }
  /// Worst error of every component at pose q for geometry `values` (double; not certified).
  DVec error(const Geometry& values, const DVec& q) const { return model::GoughPlatform(at(values)).worstErrorAt(q); }
  /// d J^-1 / d g_p at (q, values) by central differences of the double J^-1 (step 1e-7: rounding error
  /// ~ 1e-16 / 1e-7 ~ 1e-9 times a small factor; truncation ~ 1e-14).
  DMat inverseJacobianDerivative(const Geometry& values, int p, const DVec& q) const {
    const double step = 1e-7;
    Geometry plus = values, minus = values;
    plus[p] += step;
    minus[p] -= step;
    return (model::GoughPlatform(at(plus)).inverseJacobian(q) - model::GoughPlatform(at(minus)).inverseJacobian(q)) /
           (2.0 * step);
  }

  Geometry randomVertex(std::mt19937_64& rng) const {
    Geometry g(coords.size());
    for (std::size_t p = 0; p < coords.size(); ++p) g[p] = (rng() & 1u) ? hi[p] : lo[p];
    return g;
  }
  Geometry randomInterior(std::mt19937_64& rng) const {
    Geometry g(coords.size());
    for (std::size_t p = 0; p < coords.size(); ++p) g[p] = std::uniform_real_distribution<double>(lo[p], hi[p])(rng);
    return g;
  }
  /// d f_k / d g_p at (q, values) by central differences (double, step 1e-7): 6 x count.
  Eigen::MatrixXd gradient(const Geometry& values, const DVec& q) const {
    const double step = 1e-7;
    Eigen::MatrixXd grad(6, count());
    for (int p = 0; p < count(); ++p) {
      Geometry plus = values, minus = values;
      plus[p] += step;
      minus[p] -= step;
      grad.col(p) = (error(plus, q) - error(minus, q)) / (2.0 * step);
    }
    return grad;
  }
  /// The vertex that the signs of a gradient row point to (direction +1: raising f_k, -1: lowering it).
  Geometry vertexBySigns(const Eigen::MatrixXd& grad, int k, double direction) const {
    Geometry g(coords.size());
    for (int p = 0; p < count(); ++p) g[p] = direction * grad(k, p) >= 0.0 ? hi[p] : lo[p];
    return g;
  }
  /// Local search over the vertices from `start`: flips single coordinates while that raises (direction +1) or
  /// lowers (-1) f_k at q. Where some J_kj changes sign inside the uncertainty box f_k is not smooth and the
  /// gradient-sign vertex can miss the extreme by several percent; the flips find it.
  Geometry vertexSearch(const DVec& q, int k, double direction, Geometry start) const {
    double best = direction * error(start, q)[k];
    for (int pass = 0; pass < 4; ++pass) {
      bool improved = false;
      for (int p = 0; p < count(); ++p) {
        Geometry t = start;
        t[p] = t[p] == hi[p] ? lo[p] : hi[p];
        const double v = direction * error(t, q)[k];
        if (v > best) {
          best = v;
          start = t;
          improved = true;
        }
      }
      if (!improved) break;
    }
    return start;
  }
};

model::GoughGeometry withUncertainty(double h) {
  model::GoughGeometry g = test::ref6File().geometry;
  g.setUniformAnchorUncertainty(h);
  return g;
}

/// A box of `fraction` of every width of `ws`, at a random place inside it (fraction 0: a single pose).
IVec randomSubBox(const IVec& ws, double fraction, std::mt19937_64& rng) {
  const DVec c = test::randomPoint(ws, rng);
  IVec box(ws.size());
  for (int i = 0; i < ws.size(); ++i) {
    const double half = 0.5 * fraction * (ws[i].upper() - ws[i].lower());
    const double mid = std::min(std::max(c[i], ws[i].lower() + half), ws[i].upper() - half);
    box[i] = Interval(mid - half, mid + half);
  }
  return box;
}

/// Each geometry parameter's centre g0_p and half-width h_p (gamma_p = (g_p - g0_p) / h_p in the affine forms).
void centresAndHalfWidths(const model::RobotModel& robot, std::vector<double>& gc, std::vector<double>& gh) {
  const int params = robot.geometryParameterCount();
  gc.assign(params, 0.0);
  gh.assign(params, 0.0);
  for (int p = 0; p < params; ++p) {
    gc[p] = robot.geometryParameterCentre(p);
    gh[p] = (robot.geometryParameterRange(p) - Interval(gc[p])).mag();
  }
}

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

DVec randomVertexOf(const IVec& box, std::mt19937_64& rng) {
  DVec q(box.size());
  for (int i = 0; i < box.size(); ++i) q[i] = (rng() & 1u) ? box[i].upper() : box[i].lower();
  return q;
}

IVec thinOf(const DVec& q) {
  IVec t(q.size());
  for (int i = 0; i < q.size(); ++i) t[i] = Interval(q[i]);
  return t;
}

std::string where(const DVec& q) {
  std::string s = "pose (";
  for (int i = 0; i < q.size(); ++i) s += (i ? ", " : "") + std::to_string(q[i]);
  return s + ")";
}

}  // namespace

// =====================================================================================================================
// 1. The geometry-parameter API
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

// =====================================================================================================================
// 2. Soundness of the second_order enclosure and of errorAtPose under uncertainty
// =====================================================================================================================

/// The second_order method's bounds on random boxes of the paper workspace against sampled poses and geometries
/// (double and MPFR), with the combined geometry form or the decomposed one (BoxInput::decomposeGeometry).
void checkSecondOrderOnRandomBoxes(bool decomposed) {
  SCOPED_TRACE(decomposed ? "decomposed" : "combined");
  const io::RobotFile rf = test::ref6File();
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const auto method = enclosure::makeEnclosure("second_order");
  const auto coefficients = enclosure::makeEnclosure("mean_value");  // geometry as interval coefficients only
  model::GoughGeometry withTool = withUncertainty(0.0005);
  withTool.tool_point = Eigen::Vector3d(0.0, 0.01, 0.05);
  withTool.tool_point_halfwidth = Eigen::Vector3d(0.0005, 0.0005, 0.0005);
  int run = 0;
  for (const auto& geometry : {withUncertainty(0.0005), withUncertainty(0.001), withTool}) {
    const Uncertain u(geometry);
    const double h = u.coords[0].half;
    const bool tool = u.count() > 36;
    SCOPED_TRACE("h = " + std::to_string(h) + (tool ? " with tool point" : ""));
    const model::GoughPlatform robot(u.geometry);
    std::mt19937_64 rng(404 + run++);
    int bounded = 0, checkedDouble = 0, checkedMpfr = 0, boxes = 0, signsChecked = 0, children = 0, differing = 0;
    int coarse = 0, nearTighter = 0, generousLooser = 0;
    double worstGap = 0.0;  // (upper - max sampled) / upper on single poses: a looseness measure
    for (int trial = 0; trial < (tool ? 36 : 96); ++trial) {
      // Thin, 1/256 .. 1/16 of the paper workspace, in random places.
      const int size = trial % 6;
      const double fraction = size == 0 ? 0.0 : std::pow(0.5, 9 - size);
      const IVec box = randomSubBox(ws.initialBox(), fraction, rng);
      enclosure::BoxInput in;
      ws.poseView(box, true, in);
      enclosure::ErrorBounds b, plain, other;
      in.decomposeGeometry = decomposed;
      method->enclose(robot, in, b);
      ++boxes;
      // The form asked for is the one used (its bounds differ from the other form's).
      in.decomposeGeometry = !decomposed;
      method->enclose(robot, in, other);
      in.decomposeGeometry = decomposed;
      if (b.upper != other.upper) ++differing;
      // With targets halfway between the bounds every row misses them: the decomposed form then bounds the geometry's
      // increase of the columns whose nominal part misses too coarsely (GeometryIncrement::rowBound; not where the
      // nominal lower bound is above the target), the combined one skips its bilinear bounds after a miss; the
      // bounds must hold all the same.
      enclosure::ErrorBounds missing;
      in.targets = (b.upper + b.lower) * 0.5;
      method->enclose(robot, in, missing);
      // Targets just below / well above the bounds: the decomposed form then takes the full bound (and the exact
      // maximum at the pose vertices where a column misses), and the coarse increase for the columns it certifies
      // anyway (MeanValueEnclosure): bounds that may differ from the untargeted ones and must hold all the same.
      enclosure::ErrorBounds near, generous;
      in.targets = b.upper * (1.0 - 1e-3);
      method->enclose(robot, in, near);
      in.targets = b.upper * 1.5;
      method->enclose(robot, in, generous);
      in.targets.resize(0);
      if (missing.upper != b.upper) ++coarse;
      for (int k = 0; k < 6; ++k) {
        if (near.upper[k] < b.upper[k]) ++nearTighter;
        if (generous.upper[k] > b.upper[k]) ++generousLooser;
      }
      ASSERT_EQ(b.upper.size(), 6);
      ASSERT_EQ(b.lower.size(), 6);
      if (!b.bounded()) continue;
      ++bounded;
      EXPECT_EQ(b.geometrySensitivity.rows(), 6);
      EXPECT_EQ(b.geometrySensitivity.cols(), u.count());
      EXPECT_EQ(b.geometrySmear.cols(), u.count());
      // Tighter than interval coefficients on small boxes (the point of the geometry-aware form).
      coefficients->enclose(robot, in, plain);
      if (size <= 2) {
        for (int k = 0; k < 6; ++k) EXPECT_LE(b.upper[k], plain.upper[k]) << "k=" << k << " trial " << trial;
      }
      // A half of the box enclosed with the signs of J certified on the whole box (what the verifier hands down).
      IVec half = box;
      enclosure::BoxInput childIn;
      enclosure::ErrorBounds child;
      if (size > 0) {
        const int v = static_cast<int>(rng() % 6);
        half[v] = (rng() & 1u) ? box[v].bisect().first : box[v].bisect().second;
        ws.poseView(half, true, childIn);
        childIn.decomposeGeometry = decomposed;
        childIn.knownSigns = b.signs;
        method->enclose(robot, childIn, child);
        ++children;
      }
      DVec maxSampled = DVec::Zero(6);
      for (int s = 0; s < 3; ++s) {
        const DVec q = s == 0 ? test::randomPoint(box, rng) : randomVertexOf(box, rng);
        // Candidate geometries: per component the worst vertices (maximising and minimising, by the signs of the
        // finite-difference gradient at the nominal geometry; on single poses improved by vertex flips), random
        // vertices, an interior point, the nominal.
        const Eigen::MatrixXd grad = u.gradient(u.nominal, q);
        std::vector<Geometry> candidates;
        for (int k = 0; k < 6; ++k)
          for (const double dir : {1.0, -1.0}) {
            const Geometry g = u.vertexBySigns(grad, k, dir);
            candidates.push_back(size == 0 ? u.vertexSearch(q, k, dir, g) : g);
          }
        candidates.push_back(u.randomVertex(rng));
        candidates.push_back(u.randomVertex(rng));
        candidates.push_back(u.randomInterior(rng));
        candidates.push_back(u.nominal);
        bool inHalf = true;
        for (int i = 0; i < 6; ++i) inHalf = inHalf && half[i].contains(q[i]);
        for (std::size_t c = 0; c < candidates.size(); ++c) {
          const DVec f = u.error(candidates[c], q);
          for (int k = 0; k < 6; ++k) {
            maxSampled[k] = std::max(maxSampled[k], f[k]);
            EXPECT_LE(f[k], b.upper[k] * (1 + 1e-12))
                << "k=" << k << " trial " << trial << " cand " << c << " " << where(q);
            EXPECT_GE(f[k], b.lower[k] * (1 - 1e-12))
                << "k=" << k << " trial " << trial << " cand " << c << " " << where(q);
            EXPECT_LE(f[k], missing.upper[k] * (1 + 1e-12)) << "targets missed, k=" << k << " trial " << trial;
            EXPECT_GE(f[k], missing.lower[k] * (1 - 1e-12)) << "targets missed, k=" << k << " trial " << trial;
            EXPECT_LE(f[k], near.upper[k] * (1 + 1e-12)) << "targets near, k=" << k << " trial " << trial;
            EXPECT_GE(f[k], near.lower[k] * (1 - 1e-12)) << "targets near, k=" << k << " trial " << trial;
            EXPECT_LE(f[k], generous.upper[k] * (1 + 1e-12)) << "targets generous, k=" << k << " trial " << trial;
            EXPECT_GE(f[k], generous.lower[k] * (1 - 1e-12)) << "targets generous, k=" << k << " trial " << trial;
            if (size > 0 && inHalf && child.bounded()) {
              EXPECT_LE(f[k], child.upper[k] * (1 + 1e-12)) << "child, k=" << k << " trial " << trial;
              EXPECT_GE(f[k], child.lower[k] * (1 - 1e-12)) << "child, k=" << k << " trial " << trial;
            }
          }
          // The signs of J certified on the box hold at this pose and geometry.
          const DMat jac = model::GoughPlatform(u.at(candidates[c])).jacobian(q);
          for (int bit = 0; bit < 36; ++bit) {
            const double sign = b.signs.sign(bit);
            if (sign == 0.0) continue;
            EXPECT_GT(sign * jac(bit / 6, bit % 6), 0.0) << "J(" << bit / 6 << "," << bit % 6 << ") trial " << trial;
            ++signsChecked;
          }
          ++checkedDouble;
          // MPFR for the worst vertices at the first pose of every box (and everything on every 4th box).
          if ((s == 0 && c < 12) || trial % 4 == 0) {
            const auto exact = mpfrWorstError(u.at(candidates[c]), q);
            for (int k = 0; k < 6; ++k) {
              EXPECT_TRUE(mpLessEqual(exact[k], b.upper[k])) << "k=" << k << " trial " << trial;
              EXPECT_TRUE(mpGreaterEqual(exact[k], b.lower[k])) << "k=" << k << " trial " << trial;
            }
            ++checkedMpfr;
          }
        }
      }
      if (size == 0) {
        for (int k = 0; k < 6; ++k) worstGap = std::max(worstGap, (b.upper[k] - maxSampled[k]) / b.upper[k]);
      }
    }
    EXPECT_GE(bounded, boxes * 9 / 10);
    EXPECT_GT(checkedMpfr, tool ? 200 : 600);
    EXPECT_GT(checkedDouble, tool ? 1500 : 4000);
    EXPECT_GT(signsChecked, 10 * checkedDouble);  // most entries of J keep their sign on these boxes
    EXPECT_GT(children, boxes / 2);
    // (With the tool point, boxes are enclosed at its vertices, where the tool point is exact and the decomposed form
    // runs; on single poses the combined form runs either way, as the decomposed form needs the model's affine
    // geometry derivatives for every parameter and the tool point's entries have none.)
    EXPECT_GT(differing, tool ? boxes / 2 : boxes * 3 / 4);
    if (decomposed && !tool) {
      EXPECT_GT(coarse, boxes / 2);
      EXPECT_GT(generousLooser, boxes / 2);
    }
    if (decomposed) {
      std::cout << "[ info     ] rows tighter with targets just below the bounds: " << nearTighter
                << ", looser (coarse increase) with generous targets: " << generousLooser << " of " << 6 * boxes
                << "\n";
    }
    // Not vacuous: on a single pose the bound exceeds the worst geometry found by a second-order amount only
    // (measured, combined: 0.14% at h = 0.5 mm, 1.5% with the tool point too, 1.8% at h = 1 mm, where f_k itself
    // varies by +-8% and +-15%; decomposed: 0.12% and 1.2% with the sign-coupled second-order terms).
    EXPECT_LT(worstGap, tool ? 0.03 : (h == 0.0005 ? 0.015 : (decomposed ? 0.02 : 0.08)));
    std::cout << "[ info     ] " << (decomposed ? "decomposed" : "combined") << ", h=" << h
              << (tool ? " with tool point" : "")
              << ": largest excess of the bound over the worst geometry found on single poses " << worstGap * 100
              << "%\n";
  }
}

TEST(UncertaintyEnclosure, SecondOrderBoundsEveryAdmissibleGeometryOnRandomBoxes) {
  checkSecondOrderOnRandomBoxes(false);
}

TEST(UncertaintyEnclosure, DecomposedFormBoundsEveryAdmissibleGeometryOnRandomBoxes) {
  checkSecondOrderOnRandomBoxes(true);
}

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

TEST(UncertaintyEnclosure, RowMaskKeepsTheWantedComponentsBitForBit) {
  // BoxInput::rows (the verifier passes the components still undecided): the wanted components' bounds, lower
  // bounds and hints are exactly those of the full enclosure (every column is computed independently), also with
  // signs handed down from a containing box; the others are left at +inf (geometry-aware path) or at a valid,
  // looser bound (nominal path).
  const io::RobotFile rf = test::ref6File();
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const auto method = enclosure::makeEnclosure("second_order");
  std::mt19937_64 rng(515);
  for (const double h : {0.0, 0.0005, 0.001}) {
    SCOPED_TRACE("h = " + std::to_string(h));
    const model::GoughPlatform robot(withUncertainty(h));
    int compared = 0;
    for (int trial = 0; trial < 24; ++trial) {
      const double fraction = std::pow(0.5, 3 + trial % 5);
      const IVec box = randomSubBox(ws.initialBox(), fraction, rng);
      enclosure::BoxInput in;
      ws.poseView(box, true, in);
      enclosure::ErrorBounds parent;
      method->enclose(robot, in, parent);
      IVec half = box;
      const int v = trial % 6;
      half[v] = box[v].bisect().first;
      enclosure::BoxInput child;
      ws.poseView(half, true, child);
      if (trial % 2 == 0) child.knownSigns = parent.signs;
      enclosure::ErrorBounds full, masked;
      method->enclose(robot, child, full);
      const unsigned mask = 1u + static_cast<unsigned>(rng() % 63u);  // a non-empty proper or full subset
      child.rows = mask;
      method->enclose(robot, child, masked);
      ASSERT_EQ(masked.upper.size(), 6);
      for (int k = 0; k < 6; ++k) {
        if ((mask >> k) & 1u) {
          EXPECT_EQ(masked.upper[k], full.upper[k]) << "k=" << k << " trial " << trial;
          EXPECT_EQ(masked.lower[k], full.lower[k]) << "k=" << k << " trial " << trial;
          if (full.componentSmear.rows() == 6 && masked.componentSmear.rows() == 6) {
            for (int i = 0; i < 6; ++i) EXPECT_EQ(masked.componentSmear(k, i), full.componentSmear(k, i)) << k;
          }
          if (h > 0.0) {
            for (int p = 0; p < robot.geometryParameterCount(); ++p)
              EXPECT_EQ(masked.geometrySensitivity(k, p), full.geometrySensitivity(k, p)) << k << " " << p;
          }
          ++compared;
        } else if (h > 0.0) {
          EXPECT_EQ(masked.upper[k], std::numeric_limits<double>::infinity()) << "k=" << k;
        } else {
          EXPECT_GE(masked.upper[k], full.upper[k]) << "k=" << k;  // the first-order bound only
        }
      }
    }
    EXPECT_GT(compared, 24);
    // errorAtPose (the verifier's certified point evaluations) with the same mask.
    for (int trial = 0; trial < 8; ++trial) {
      const DVec q = test::randomPoint(ws.initialBox(), rng);
      IVec thin(6);
      for (int i = 0; i < 6; ++i) thin[i] = Interval(q[i]);
      const unsigned mask = 1u + static_cast<unsigned>(rng() % 63u);
      IVec full, masked;
      GMat sensFull, sensMasked;
      ASSERT_TRUE(enclosure::errorAtPose(robot, thin, full, &sensFull));
      ASSERT_TRUE(enclosure::errorAtPose(robot, thin, masked, &sensMasked, mask));
      for (int k = 0; k < 6; ++k) {
        if (!((mask >> k) & 1u)) continue;
        EXPECT_EQ(masked[k].lower(), full[k].lower()) << k;
        EXPECT_EQ(masked[k].upper(), full[k].upper()) << k;
        if (h > 0.0) {
          EXPECT_EQ(sensMasked.row(k), sensFull.row(k)) << k;
        }
      }
    }
  }
}

TEST(UncertaintyEnclosure, ErrorAtPoseEnclosesEveryGeometryAndItsSensitivitiesPointToTheWorstVertex) {
  const io::RobotFile rf = test::ref6File();
  const IVec ws = rf.workspaces.at("paper").initialBox();
  for (const double h : {0.0005, 0.001}) {
    SCOPED_TRACE("h = " + std::to_string(h));
    const Uncertain u(withUncertainty(h));
    const model::GoughPlatform robot(u.geometry);
    std::mt19937_64 rng(h == 0.0005 ? 505 : 506);
    int signsChecked = 0, stableRows = 0;
    double widest = 0.0;
    for (int trial = 0; trial < 50; ++trial) {
      const DVec q = trial % 2 ? test::randomPoint(ws, rng) : randomVertexOf(ws, rng);
      IVec f;
      GMat sensitivity;
      ASSERT_TRUE(enclosure::errorAtPose(robot, thinOf(q), f, &sensitivity)) << where(q);
      ASSERT_EQ(f.size(), 6);
      ASSERT_EQ(sensitivity.rows(), 6);
      ASSERT_EQ(sensitivity.cols(), 36);
      const Eigen::MatrixXd grad = u.gradient(u.nominal, q);
      const DMat jac = model::GoughPlatform(u.at(u.nominal)).jacobian(q);
      for (int k = 0; k < 6; ++k) {
        const Geometry up = u.vertexSearch(q, k, 1.0, u.vertexBySigns(grad, k, 1.0));
        const Geometry down = u.vertexSearch(q, k, -1.0, u.vertexBySigns(grad, k, -1.0));
        const auto exactUp = mpfrWorstError(u.at(up), q), exactDown = mpfrWorstError(u.at(down), q);
        EXPECT_TRUE(mpLessEqual(exactUp[k], f[k].upper())) << "k=" << k << " " << where(q);
        EXPECT_TRUE(mpGreaterEqual(exactDown[k], f[k].lower())) << "k=" << k << " " << where(q);
        for (int s = 0; s < 4; ++s) {
          const DVec v = u.error(s % 2 ? u.randomVertex(rng) : u.randomInterior(rng), q);
          EXPECT_LE(v[k], f[k].upper() * (1 + 1e-12));
          EXPECT_GE(v[k], f[k].lower() * (1 - 1e-12));
        }
        // Second-order tight: the width exceeds the spread of f_k over the geometries by O(h^2) (measured: up to
        // 1.35x at h = 0.5 mm, 1.75x at h = 1 mm; the remainder is symmetric while f_k is convex in g).
        const double spread = toDouble(exactUp[k]) - toDouble(exactDown[k]);
        widest = std::max(widest, (f[k].upper() - f[k].lower()) / spread);
        EXPECT_LE(f[k].upper() - f[k].lower(), (1.0 + 1250.0 * h) * spread) << "k=" << k << " " << where(q);
        // Sensitivities, where every J_kj keeps its sign over the uncertainty box (f_k smooth in g there): they say
        // which end of each parameter raises f_k, and their vertex is as bad as the worst one found.
        bool stable = true;
        for (int j = 0; j < 6; ++j) {
          const double jkj = jac(k, j);
          for (const Geometry* g : {&up, &down}) {
            const DMat other = model::GoughPlatform(u.at(*g)).jacobian(q);
            stable = stable && other(k, j) * jkj > 0.0 && std::abs(jkj) > 0.1 * jac.row(k).cwiseAbs().maxCoeff();
          }
        }
        if (!stable) continue;
        ++stableRows;
        const double scale = grad.row(k).cwiseAbs().maxCoeff();
        for (int p = 0; p < 36; ++p) {
          if (std::abs(grad(k, p)) < 0.1 * scale) continue;
          EXPECT_GT(sensitivity(k, p) * grad(k, p), 0.0)
              << robot.geometryParameterName(p) << " k=" << k << " " << where(q);
          ++signsChecked;
        }
        Geometry bySensitivity(36);
        for (int p = 0; p < 36; ++p) bySensitivity[p] = sensitivity(k, p) >= 0.0 ? u.hi[p] : u.lo[p];
        EXPECT_GE(u.error(bySensitivity, q)[k], toDouble(exactUp[k]) * (1 - 1e-3)) << "k=" << k << " " << where(q);
      }
    }
    EXPECT_GT(stableRows, 50);
    EXPECT_GT(signsChecked, 500);
    std::cout << "[ info     ] h=" << h << ": errorAtPose width / spread of f_k over the geometries <= " << widest
              << "\n";
  }
}

// =====================================================================================================================
// 3. PreconditionedInverseEnclosure directly
// =====================================================================================================================

TEST(UncertaintyPreconditionedInverse, AffineFormsContainNVComputedInMpfr) {
  const io::RobotFile rf = test::ref6File();
  const domain::Workspace& ws = rf.workspaces.at("paper");
  model::GoughGeometry withTool = withUncertainty(0.0005);
  withTool.tool_point = Eigen::Vector3d(0.0, 0.01, 0.05);
  withTool.tool_point_halfwidth = Eigen::Vector3d(0.0005, 0.0005, 0.0005);
  std::mt19937_64 rng(606);
  int prepared = 0, entriesChecked = 0, combinations = 0;
  double worstCross = 0.0;  // largest |S L y + L S y| / its bound
  for (const auto& g : {withUncertainty(0.0005), withUncertainty(0.001), withTool}) {
    const Uncertain u(g);
    const model::GoughPlatform robot(g);
    const int params = robot.geometryParameterCount();
    ASSERT_EQ(params, u.count());
    std::vector<double> gc, gh;
    centresAndHalfWidths(robot, gc, gh);
    for (int trial = 0; trial < 24; ++trial) {
      // Thin poses and boxes of 1/8, 1/32 and 1/128 of the ranges (1/8: where |S y| through y = v + (y - v) counts).
      const double fraction = trial % 4 == 0 ? 0.0 : std::pow(0.5, 1 + trial % 4 * 2);
      const IVec box = randomSubBox(ws.initialBox(), fraction, rng);
      enclosure::BoxInput in;
      ws.poseView(box, true, in);
      enclosure::PreconditionedInverseEnclosure act;
      if (!act.prepare(robot, in)) continue;
      ++prepared;
      EXPECT_EQ(act.parameters(), params);
      // V: n x m, random entries, some thin and some with a small radius.
      const int m = 1 + static_cast<int>(rng() % 6);
      IMat v(6, m);
      std::uniform_real_distribution<double> unit(-1.0, 1.0);
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < m; ++j) {
          const double c = unit(rng), r = (rng() % 3 == 0) ? 0.0 : 1e-4 * std::abs(unit(rng));
          v(i, j) = Interval(c - r, c + r);
        }
      enclosure::PreconditionedInverseEnclosure::AffineMatrix a;
      ASSERT_TRUE(act.apply(v, a)) << "trial " << trial;
      ASSERT_EQ(a.rows, 6);
      ASSERT_EQ(a.cols, m);
      EXPECT_EQ(a.params, params);
      // The bisection hints: every variable's share of the width is a part of the radius (with the remainder's pose
      // terms shared out, the shares still add up to at most the radius).
      for (int k = 0; k < 6; ++k)
        for (int j = 0; j < m; ++j) {
          double shares = 0.0;
          for (int i = 0; i < a.vars; ++i) {
            EXPECT_GE(a.poseSpread[i](k, j), 0.0);
            shares += a.poseSpread[i](k, j);
          }
          EXPECT_LE(shares, a.radius(k, j) * (1.0 + 1e-12)) << "entry " << k << "," << j << " trial " << trial;
        }
      const DMat& c = act.preconditioner();
      for (int s = 0; s < 4; ++s) {
        const DVec t = s % 2 ? randomVertexOf(box, rng) : test::randomPoint(box, rng);
        const Geometry gv = s < 2 ? u.randomVertex(rng) : u.randomInterior(rng);
        // A point of V (vertices and interior points).
        MpMat vp(6, std::vector<Mp>(m, Mp(0.0)));
        for (int i = 0; i < 6; ++i)
          for (int j = 0; j < m; ++j) {
            const double x = s == 0   ? v(i, j).lower()
                             : s == 1 ? v(i, j).upper()
                                      : std::uniform_real_distribution<double>(v(i, j).lower(), v(i, j).upper())(rng);
            vp[i][j] = Mp(x);
          }
        // N V = (C J^-1(t, g))^-1 V in MPFR.
        const MpMat jinv = mpInverseJacobian(u.at(gv), t);
        MpMat cj(6, std::vector<Mp>(6, Mp(0.0)));
        for (int i = 0; i < 6; ++i)
          for (int j = 0; j < 6; ++j)
            for (int l = 0; l < 6; ++l) cj[i][j] = cj[i][j] + Mp(c(i, l)) * jinv[l][j];
        const MpMat nv = mpSolve(cj, vp);
        // The remainder's parts, each against its own bound (apply(); every entry): with E = S + L, S = C J^-1(t, g0)
        // - I and L = C (J^-1(t, g) - J^-1(t, g0)), |S S y| <= ssy, |S L y + L S y| <= cross, |L L y| <= ll.
        {
          MpMat sm(6, std::vector<Mp>(6, Mp(0.0))), lm(6, std::vector<Mp>(6, Mp(0.0)));
          const MpMat jinv0 = mpInverseJacobian(u.at(gc), t);
          for (int i = 0; i < 6; ++i)
            for (int j = 0; j < 6; ++j) {
              Mp cs(0.0), cl(0.0);
              for (int l = 0; l < 6; ++l) {
                cs = cs + Mp(c(i, l)) * jinv0[l][j];
                cl = cl + Mp(c(i, l)) * (jinv[l][j] - jinv0[l][j]);
              }
              sm[i][j] = i == j ? cs - Mp(1.0) : cs;
              lm[i][j] = cl;
            }
          for (int j = 0; j < m; ++j) {
            std::vector<Mp> ly(6, Mp(0.0)), sy(6, Mp(0.0));
            for (int i = 0; i < 6; ++i)
              for (int l = 0; l < 6; ++l) {
                ly[i] = ly[i] + lm[i][l] * nv[l][j];
                sy[i] = sy[i] + sm[i][l] * nv[l][j];
              }
            for (int k = 0; k < 6; ++k) {
              Mp ss(0.0), cross(0.0), ll(0.0);
              for (int l = 0; l < 6; ++l) {
                ss = ss + sm[k][l] * sy[l];
                cross = cross + sm[k][l] * ly[l] + lm[k][l] * sy[l];
                ll = ll + lm[k][l] * ly[l];
              }
              EXPECT_TRUE(mpLessEqual(mpAbs(ss), a.ssy(k, j))) << "|S S y| " << k << "," << j << " trial " << trial;
              EXPECT_TRUE(mpLessEqual(mpAbs(cross), a.cross(k, j)))
                  << "|S L y + L S y| = " << toDouble(mpAbs(cross)) << " > " << a.cross(k, j) << ", entry " << k << ","
                  << j << " trial " << trial;
              EXPECT_TRUE(mpLessEqual(mpAbs(ll), a.ll(k, j))) << "|L L y| " << k << "," << j << " trial " << trial;
              worstCross = std::max(worstCross, toDouble(mpAbs(cross)) / a.cross(k, j));
            }
          }
        }
        // The affine variables of this (t, g): tau_i = (t_i - t0_i) / |dev_i|max, gamma_p = (g_p - g0_p) / h_p.
        std::vector<Mp> tau(6, Mp(0.0)), gamma(params, Mp(0.0));
        for (int i = 0; i < 6; ++i) {
          const double dm = in.deviation[i].mag();
          if (dm > 0.0) tau[i] = (Mp(t[i]) - Mp(in.centrePose[i].mid())) / Mp(dm);
        }
        for (int p = 0; p < params; ++p) gamma[p] = (Mp(gv[p]) - Mp(gc[p])) / Mp(gh[p]);
        auto form = [&](double centre, const double* pose, const double* geometry) {
          Mp x(centre);
          for (int i = 0; i < a.vars; ++i) x = x + Mp(pose[i]) * tau[i];
          for (int p = 0; p < params; ++p) x = x + Mp(geometry[p]) * gamma[p];
          return x;
        };
        for (int k = 0; k < 6; ++k)
          for (int j = 0; j < m; ++j) {
            const Interval e = a.entry(k, j);
            EXPECT_TRUE(mpGreaterEqual(nv[k][j], e.lower()) && mpLessEqual(nv[k][j], e.upper()))
                << "entry " << k << "," << j << " trial " << trial << ": " << toDouble(nv[k][j]) << " not in " << e;
            // The affine form itself (the correlations it claims): |NV - form(t, g)| <= radius.
            double pose[kMaxDof], geometry[kMaxGeometryParameters];
            for (int i = 0; i < a.vars; ++i) pose[i] = a.pose[i](k, j);
            for (int p = 0; p < params; ++p) geometry[p] = a.geometry[j](k, p);
            const Mp dev = mpAbs(nv[k][j] - form(a.centre(k, j), pose, geometry));
            EXPECT_TRUE(mpLessEqual(dev, a.radius(k, j)))
                << "entry " << k << "," << j << " trial " << trial << ": |NV - form| = " << toDouble(dev)
                << " > radius " << a.radius(k, j);
            ++entriesChecked;
          }
        // combine(): a random exact weight per column (some zero).
        for (int k = 0; k < 6; ++k) {
          double w[kMaxDof];
          for (int j = 0; j < m; ++j) w[j] = rng() % 4 == 0 ? 0.0 : std::ldexp(unit(rng), -3);
          enclosure::PreconditionedInverseEnclosure::Combination comb;
          enclosure::PreconditionedInverseEnclosure::combine(a, k, w, comb);
          Mp exact(0.0);
          for (int j = 0; j < m; ++j) exact = exact + Mp(w[j]) * nv[k][j];
          EXPECT_TRUE(mpGreaterEqual(exact, comb.lower()) && mpLessEqual(exact, comb.upper()))
              << "row " << k << " trial " << trial << ": " << toDouble(exact) << " not in [" << comb.lower() << ", "
              << comb.upper() << "]";
          const Mp dev = mpAbs(exact - form(comb.centre, comb.pose, comb.geometry));
          EXPECT_TRUE(mpLessEqual(dev, comb.radius)) << "row " << k << " trial " << trial;
          // add(): the sum of two combinations of the same row encloses the sum.
          double w2[kMaxDof];
          for (int j = 0; j < m; ++j) w2[j] = std::ldexp(unit(rng), -2);
          enclosure::PreconditionedInverseEnclosure::Combination other;
          enclosure::PreconditionedInverseEnclosure::combine(a, k, w2, other);
          Mp exact2(0.0);
          for (int j = 0; j < m; ++j) exact2 = exact2 + Mp(w2[j]) * nv[k][j];
          comb.add(other);
          const Mp sum = exact + exact2;
          EXPECT_TRUE(mpGreaterEqual(sum, comb.lower()) && mpLessEqual(sum, comb.upper())) << "row " << k;
          ++combinations;
        }
      }
      // Not vacuous: the geometry terms are there, and on a single pose the remainder is second order, small
      // next to the first-order terms (measured: radius / sum of |coefficients| <= 0.22 at h = 0.5 mm, 0.58 at 1 mm).
      for (int k = 0; k < 6; ++k)
        for (int j = 0; j < m; ++j) {
          double first = 0.0;
          for (int p = 0; p < params; ++p) first += std::abs(a.geometry[j](k, p));
          EXPECT_GT(first, 0.0);
          if (fraction == 0.0 && u.geometry.tool_point_halfwidth.norm() == 0.0) {
            EXPECT_LT(a.radius(k, j), (u.coords[0].half <= 0.0005 ? 0.35 : 0.9) * first) << k << "," << j;
          }
        }
    }
  }
  EXPECT_GE(prepared, 60);
  EXPECT_GT(entriesChecked, 1000);
  EXPECT_GT(combinations, 500);
  std::cout << "[ info     ] |S L y + L S y| up to " << worstCross << " of its bound\n";
}

TEST(UncertaintyPreconditionedInverse, RhoBoundsTheDotProductsOfYMinusV) {
  // AffineMatrix::rho(e, j) >= |d_e . (y_j - v_j)| for every pose and geometry of the box, y = N v: the bound that
  // |y - v| and the dot products d_e . (y - v) share through their joint fixed point (apply()) and that the
  // refinements of B, the monotone directions and the face bounds build on; also sigma >= |d_e . (S y)| and, for the
  // columns with the bilinear terms, dotRest >= |d_e . (S y) - sum_i (t_i - t0_i) q1[i]|. d_e by central differences of
  // the double J^-1 of the concrete geometry (error ~ 1e-9 of |d_e|), y - v in MPFR; both apply() variants (J's signs
  // and the columns that bound f_k). At +-1 mm the largest ratio must reach a good part of the bound, so that a bound
  // too small by a factor would fail.
  const io::RobotFile rf = test::ref6File();
  const domain::Workspace& ws = rf.workspaces.at("paper");
  std::mt19937_64 rng(911);
  int checked = 0;
  double worst = 0.0;       // the largest |d_e . (y - v)| / rho at +-1 mm
  double worstSigma = 0.0;  // the largest |d_e . (S y)| / sigma (columns that bound f_k)
  double worstRest = 0.0;   // the largest |d_e . (S y) - its q1 part| / dotRest
  int restChecked = 0;
  for (const double h : {0.0005, 0.001}) {
    const Uncertain u(withUncertainty(h));
    const model::GoughPlatform robot(u.geometry);
    for (int trial = 0; trial < 16; ++trial) {
      const double fraction =
          trial % 4 == 0 ? 1.0 / 8.0 : (trial % 4 == 1 ? 1.0 / 32.0 : (trial % 4 == 2 ? 0.0 : 0.25));
      const IVec box = randomSubBox(ws.initialBox(), fraction, rng);
      enclosure::BoxInput in;
      ws.poseView(box, true, in);
      enclosure::PreconditionedInverseEnclosure act;
      if (!act.prepare(robot, in)) continue;
      GeometryDerivatives geo;
      ASSERT_TRUE(robot.geometryDerivatives(in.pose, geo));
      const DMat& c = act.preconditioner();
      // V: the preconditioner's columns times the sensor signs of a random row, and random columns.
      IMat v(6, 3);
      for (int i = 0; i < 6; ++i) {
        v(i, 0) = Interval(c(i, 0) - c(i, 1) + c(i, 2) - c(i, 3) + c(i, 4) - c(i, 5));
        v(i, 1) = Interval(std::uniform_real_distribution<double>(-1.0, 1.0)(rng));
        v(i, 2) = Interval(c(i, trial % 6));
      }
      for (const bool forBounds : {false, true}) {
        enclosure::PreconditionedInverseEnclosure::AffineMatrix a;
        ASSERT_TRUE(act.apply(v, a,
                              forBounds ? enclosure::PreconditionedInverseEnclosure::Refinements::ForErrorBounds
                                        : enclosure::PreconditionedInverseEnclosure::Refinements::Standard));
        ASSERT_EQ(a.rho.rows(), geo.count);
        for (int s = 0; s < 4; ++s) {
          const DVec t = s % 2 ? randomVertexOf(box, rng) : test::randomPoint(box, rng);
          const Geometry gv = s < 2 ? u.randomVertex(rng) : u.randomInterior(rng);
          const MpMat jinv = mpInverseJacobian(u.at(gv), t);
          MpMat cj(6, std::vector<Mp>(6, Mp(0.0))), vp(6, std::vector<Mp>(3, Mp(0.0)));
          for (int i = 0; i < 6; ++i) {
            for (int j = 0; j < 6; ++j)
              for (int l = 0; l < 6; ++l) cj[i][j] = cj[i][j] + Mp(c(i, l)) * jinv[l][j];
            for (int j = 0; j < 3; ++j) vp[i][j] = Mp(v(i, j).mid());
          }
          const MpMat nv = mpSolve(cj, vp);
          // S y with S = C J^-1(t, g0) - I (the pose part of E, E0 included), for sigma >= |d_e . (S y)|.
          const MpMat jinv0 = mpInverseJacobian(u.at(u.nominal), t);
          std::vector<std::vector<double>> sy(6, std::vector<double>(3, 0.0));
          for (int i = 0; i < 6; ++i) {
            std::vector<Mp> row(6, Mp(0.0));
            for (int l = 0; l < 6; ++l) {
              for (int q = 0; q < 6; ++q) row[l] = row[l] + Mp(c(i, q)) * jinv0[q][l];
              if (l == i) row[l] = row[l] - Mp(1.0);
            }
            for (int j = 0; j < 3; ++j) {
              Mp acc(0.0);
              for (int l = 0; l < 6; ++l) acc = acc + row[l] * nv[l][j];
              sy[i][j] = toDouble(acc);
            }
          }
          for (int e = 0; e < geo.count; ++e) {
            const GeometryRowDerivative& r = geo.entries[e];
            const DMat fd = u.inverseJacobianDerivative(gv, r.parameter, t);
            for (int j = 0; j < 3; ++j) {
              double dot = 0.0, mag = 0.0, sdot = 0.0, smag = 0.0;
              for (int l = 0; l < 6; ++l) {
                const double yv = toDouble(nv[l][j] - vp[l][j]);
                dot += fd(r.row, l) * yv;
                mag += std::abs(fd(r.row, l) * yv);
                sdot += fd(r.row, l) * sy[l][j];
                smag += std::abs(fd(r.row, l) * sy[l][j]);
              }
              ASSERT_LE(std::abs(sdot), a.sigma(e, j) + 1e-6 * smag + 1e-300)
                  << "sigma, " << robot.geometryParameterName(r.parameter) << " column " << j << " at " << where(t)
                  << ", h " << h << ", box fraction " << fraction << (forBounds ? ", for bounds" : ", for signs");
              if (forBounds && a.sigma(e, j) > 1e3 * (1e-6 * smag + 1e-300))
                worstSigma = std::max(worstSigma, std::abs(sdot) / a.sigma(e, j));
              if (a.bilinear) {
                // d_e . (S y) less its part through the products c_e . (D_i v) (q1), which the bilinear form keeps
                // as coefficients: the rest is bounded by dotRest (third order).
                double rest = sdot, restMag = smag;
                for (int i = 0; i < a.vars; ++i) {
                  const double d = t[i] - in.centrePose[i].mid();
                  rest -= d * a.q1[i](e, j);
                  restMag += std::abs(d * a.q1[i](e, j));
                }
                ASSERT_LE(std::abs(rest), a.dotRest(e, j) + 1e-6 * restMag + 1e-300)
                    << "dotRest, " << robot.geometryParameterName(r.parameter) << " column " << j << " at " << where(t)
                    << ", h " << h << ", box fraction " << fraction;
                if (a.dotRest(e, j) > 1e3 * (1e-6 * restMag + 1e-300))
                  worstRest = std::max(worstRest, std::abs(rest) / a.dotRest(e, j));
                ++restChecked;
              }
              const double slack = 1e-6 * mag + 1e-300;  // the central differences' error, with a margin
              ASSERT_LE(std::abs(dot), a.rho(e, j) + slack)
                  << robot.geometryParameterName(r.parameter) << " column " << j << " at " << where(t) << ", h " << h
                  << ", box fraction " << fraction << (forBounds ? ", for bounds" : ", for signs");
              if (h == 0.001 && a.rho(e, j) > 1e3 * slack) worst = std::max(worst, std::abs(dot) / a.rho(e, j));
              ++checked;
            }
          }
        }
      }
    }
  }
  std::cout << "[ info     ] largest |d_e . (y - v)| / rho at +-1 mm: " << worst
            << ", |d_e . (S y)| / sigma: " << worstSigma << ", the rest beyond c_e . (D_i v) / dotRest: " << worstRest
            << " (" << checked << " checks, " << restChecked << " of dotRest)\n";
  EXPECT_GT(checked, 10000);
  EXPECT_GT(worst, 0.3);
  EXPECT_GT(worstSigma, 0.5);
  // (dotRest's part through |d_e^T S| |y - v| or |d_e^T S C| R(...) bounds a third-order quantity that stays below the
  // other parts' slack at these points: dropping it does not fail this check, only a far too small dotRest does.)
  EXPECT_GT(restChecked, 5000);
  EXPECT_GT(worstRest, 0.15);
}

TEST(UncertaintyPreconditionedInverse, BilinearFormAndItsBoundHoldInMpfr) {
  // The bilinear form of apply(v, a, Refinements::ForErrorBounds) (bilinearCoefficients(), upperBilinear()) at vertices
  // and interior points of pose boxes and of the geometry box, against N V and L L y computed in MPFR:
  //   |NV - (centre + pose . tau + sum_p (geometry_p + sum_i m_ip tau_i) gamma_p) - (L L y)_k| <= bilinearRadius
  //   + rounding, and NV <= upperBilinear(). Boxes at random places and at the paper workspace's corner (where the
  // maxima are), columns random and of the kind the enclosure uses (C w, w a sign pattern times the sensor bounds).
  const io::RobotFile rf = test::ref6File();
  const domain::Workspace& ws = rf.workspaces.at("paper");
  std::mt19937_64 rng(1212);
  int checked = 0;
  double worst = 0.0;               // largest |residual| / (bilinearRadius + rounding)
  double tighter = 0.0, old = 0.0;  // sums of (bound - centre): upperBilinear() and the plain upper end
  double worstPoly = -1.0;          // largest (polynomial part - centre) / (its bound - centre)
  for (const double h : {0.0005, 0.001}) {
    const Uncertain u(withUncertainty(h));
    const model::GoughPlatform robot(u.geometry);
    const int params = robot.geometryParameterCount();
    std::vector<double> gc, gh;
    centresAndHalfWidths(robot, gc, gh);
    for (int trial = 0; trial < 16; ++trial) {
      const double fraction = std::pow(0.5, 3 + trial % 4);  // 1/8 .. 1/64
      IVec box = randomSubBox(ws.initialBox(), fraction, rng);
      if (trial % 2) {  // at the workspace's (+, ..., +) corner
        for (int i = 0; i < 6; ++i) {
          const Interval& r = ws.initialBox()[i];
          box[i] = Interval(r.upper() - fraction * (r.upper() - r.lower()), r.upper());
        }
      }
      enclosure::BoxInput in;
      ws.poseView(box, true, in);
      enclosure::PreconditionedInverseEnclosure act;
      ASSERT_TRUE(act.prepare(robot, in)) << trial;
      const DMat& c = act.preconditioner();
      const int m = 4;
      IMat v(6, m);
      std::uniform_real_distribution<double> unit(-1.0, 1.0);
      for (int j = 0; j < m; ++j) {
        for (int i = 0; i < 6; ++i) {
          if (j < 2) {
            double x = 0.0;  // C w
            for (int l = 0; l < 6; ++l) x += c(i, l) * ((rng() & 1u) ? 1.0 : -1.0) * robot.sensorError()[l];
            v(i, j) = Interval(x);
          } else {
            const double x = unit(rng), r = j == 3 ? 1e-4 * std::abs(unit(rng)) : 0.0;
            v(i, j) = Interval(x - r, x + r);
          }
        }
      }
      enclosure::PreconditionedInverseEnclosure::AffineMatrix a;
      ASSERT_TRUE(act.apply(v, a, enclosure::PreconditionedInverseEnclosure::Refinements::ForErrorBounds)) << trial;
      ASSERT_TRUE(a.bilinear) << "workspace boxes with anchor uncertainty have the bilinear form";
      enclosure::PreconditionedInverseEnclosure::AffineMatrix plain;
      ASSERT_TRUE(act.apply(v, plain)) << trial;
      EXPECT_FALSE(plain.bilinear);
      for (int s = 0; s < 7; ++s) {
        DVec t = s % 2 ? randomVertexOf(box, rng) : test::randomPoint(box, rng);
        Geometry gv = s < 4 ? u.randomVertex(rng) : u.randomInterior(rng);
        if (s == 6) {
          // Where the bilinear part of entry (s % 6, 0) is largest: tau_i = sign(pose_i + sum_p sign(geometry_p)
          // m_ip), then gamma_p = sign(geometry_p + sum_i m_ip tau_i).
          const int k = trial % 6;
          double coef[kMaxDof][kMaxGeometryParameters];
          double rounding = 0.0;
          act.bilinearCoefficients(a, k, 0, coef, rounding);
          double tau[kMaxDof];
          for (int i = 0; i < 6; ++i) {
            double acc = a.pose[i](k, 0);
            for (int p = 0; p < params; ++p) acc += (a.geometry[0](k, p) >= 0.0 ? 1.0 : -1.0) * coef[i][p];
            tau[i] = acc >= 0.0 ? 1.0 : -1.0;
            t[i] = tau[i] > 0.0 ? box[i].upper() : box[i].lower();
          }
          for (int p = 0; p < params; ++p) {
            double up = a.geometry[0](k, p);
            for (int i = 0; i < 6; ++i) up += coef[i][p] * tau[i];
            gv[p] = up >= 0.0 ? robot.geometryParameterRange(p).upper() : robot.geometryParameterRange(p).lower();
          }
        }
        MpMat vp(6, std::vector<Mp>(m, Mp(0.0)));
        for (int i = 0; i < 6; ++i)
          for (int j = 0; j < m; ++j)
            vp[i][j] = Mp(s == 0 ? v(i, j).lower() : (s == 1 ? v(i, j).upper() : v(i, j).mid()));
        const MpMat jinv = mpInverseJacobian(u.at(gv), t);
        const MpMat jinv0 = mpInverseJacobian(u.at(gc), t);
        MpMat cj(6, std::vector<Mp>(6, Mp(0.0))), lm(6, std::vector<Mp>(6, Mp(0.0)));
        for (int i = 0; i < 6; ++i)
          for (int j = 0; j < 6; ++j)
            for (int l = 0; l < 6; ++l) {
              cj[i][j] = cj[i][j] + Mp(c(i, l)) * jinv[l][j];
              lm[i][j] = lm[i][j] + Mp(c(i, l)) * (jinv[l][j] - jinv0[l][j]);
            }
        const MpMat nv = mpSolve(cj, vp);
        std::vector<Mp> tau(6, Mp(0.0)), gamma(params, Mp(0.0));
        for (int i = 0; i < 6; ++i) {
          const double dm = in.deviation[i].mag();
          if (dm > 0.0) tau[i] = (Mp(t[i]) - Mp(in.centrePose[i].mid())) / Mp(dm);
        }
        for (int p = 0; p < params; ++p) gamma[p] = (Mp(gv[p]) - Mp(gc[p])) / Mp(gh[p]);
        for (int j = 0; j < m; ++j) {
          std::vector<Mp> ly(6, Mp(0.0));
          for (int i = 0; i < 6; ++i)
            for (int l = 0; l < 6; ++l) ly[i] = ly[i] + lm[i][l] * nv[l][j];
          for (int k = 0; k < 6; ++k) {
            Mp ll(0.0);
            for (int l = 0; l < 6; ++l) ll = ll + lm[k][l] * ly[l];
            double coef[kMaxDof][kMaxGeometryParameters];
            double rounding = 0.0;
            act.bilinearCoefficients(a, k, j, coef, rounding);
            Mp form(a.centre(k, j));
            for (int i = 0; i < 6; ++i) form = form + Mp(a.pose[i](k, j)) * tau[i];
            for (int p = 0; p < params; ++p) {
              Mp up(a.geometry[j](k, p));
              for (int i = 0; i < 6; ++i) up = up + Mp(coef[i][p]) * tau[i];
              form = form + up * gamma[p];
            }
            // The polynomial part alone (form + L L y, exact here) against the bound without the radius: what
            // upperBilinear() claims for it, with no slack from the remainder's magnitude bounds.
            const double polyBound = act.upperBilinear(a, k, j) - a.bilinearRadius(k, j) - rounding;
            const Mp poly = form + ll;
            EXPECT_TRUE(mpLessEqual(poly, polyBound + 1e-9 * std::abs(polyBound)))
                << "h " << h << " trial " << trial << " entry " << k << "," << j << ": " << toDouble(poly) << " > "
                << polyBound;
            if (s == 6 && k == trial % 6 && j == 0)
              worstPoly = std::max(worstPoly, toDouble(poly - Mp(a.centre(k, j))) / (polyBound - a.centre(k, j)));
            const Mp residual = mpAbs(nv[k][j] - form - ll);
            const double allowed = a.bilinearRadius(k, j) + rounding;
            EXPECT_TRUE(mpLessEqual(residual, allowed)) << "h " << h << " trial " << trial << " entry " << k << "," << j
                                                        << ": " << toDouble(residual) << " > " << allowed;
            worst = std::max(worst, toDouble(residual) / allowed);
            const double bound = act.upperBilinear(a, k, j);
            EXPECT_TRUE(mpLessEqual(nv[k][j], bound)) << "h " << h << " trial " << trial << " entry " << k << "," << j
                                                      << ": " << toDouble(nv[k][j]) << " > upperBilinear " << bound;
            if (s == 0) {
              tighter += bound - a.centre(k, j);
              old += a.entry(k, j).upper() - a.centre(k, j);
            }
            ++checked;
          }
        }
      }
    }
  }
  std::cout << "[ info     ] residual up to " << worst << " of the bilinear radius; polynomial part up to " << worstPoly
            << " of its bound (above the centre); upperBilinear - centre: " << tighter / old
            << " of the plain bound's (" << checked << " entries)\n";
  EXPECT_GT(checked, 4000);
  // Not vacuous: the residual uses a fair part of the radius, the polynomial part comes close to its bound where
  // it is largest, and the bound is tighter than the plain one.
  EXPECT_GT(worst, 0.2);
  EXPECT_GT(worstPoly, 0.95);
  EXPECT_LT(tighter, 0.95 * old);
}

TEST(UncertaintyPreconditionedInverse, BilinearCoefficientsAreTheMixedDerivatives) {
  // The coefficient of tau_i gamma_p in the bilinear form is dev_i h_p d^2 (N v)_k / dt_i dg_p at the box centre up
  // to terms of the box's size (midpoints of slopes over the box): checked against central differences of N v in
  // MPFR (200 bits, steps 1e-6) on 1/256 boxes at +-1 mm. Each of its three parts (P L v, L P v, the slopes of the
  // geometry derivatives in -L v) is a sizeable part of the largest coefficient, so dropping any fails this.
  const io::RobotFile rf = test::ref6File();
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const Uncertain u(withUncertainty(0.001));
  const model::GoughPlatform robot(u.geometry);
  const int params = robot.geometryParameterCount();
  std::vector<double> gc, gh;
  centresAndHalfWidths(robot, gc, gh);
  std::mt19937_64 rng(1313);
  double worst = 0.0;
  for (int trial = 0; trial < 2; ++trial) {
    const IVec box = randomSubBox(ws.initialBox(), 1.0 / 256.0, rng);
    enclosure::BoxInput in;
    ws.poseView(box, true, in);
    enclosure::PreconditionedInverseEnclosure act;
    ASSERT_TRUE(act.prepare(robot, in));
    const DMat& c = act.preconditioner();
    IMat v(6, 1);
    MpMat vp(6, std::vector<Mp>(1, Mp(0.0)));
    for (int i = 0; i < 6; ++i) {
      double x = 0.0;  // C w
      for (int l = 0; l < 6; ++l) x += c(i, l) * ((i + l + trial) % 3 ? 1.0 : -1.0) * robot.sensorError()[l];
      v(i, 0) = Interval(x);
      vp[i][0] = Mp(x);
    }
    enclosure::PreconditionedInverseEnclosure::AffineMatrix a;
    ASSERT_TRUE(act.apply(v, a, enclosure::PreconditionedInverseEnclosure::Refinements::ForErrorBounds));
    ASSERT_TRUE(a.bilinear);
    DVec t0(6);
    for (int i = 0; i < 6; ++i) t0[i] = in.centrePose[i].mid();
    auto y = [&](const DVec& t, const Geometry& g) {
      const MpMat jinv = mpInverseJacobian(u.at(g), t);
      MpMat cj(6, std::vector<Mp>(6, Mp(0.0)));
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
          for (int l = 0; l < 6; ++l) cj[i][j] = cj[i][j] + Mp(c(i, l)) * jinv[l][j];
      return mpSolve(cj, vp);
    };
    constexpr double kStep = 1e-6;
    // mixed[i][p][k] = dev_i h_p d^2 y_k / dt_i dg_p
    std::vector<std::vector<std::vector<double>>> mixed(
        6, std::vector<std::vector<double>>(params, std::vector<double>(6)));
    for (int i = 0; i < 6; ++i) {
      for (int p = 0; p < params; ++p) {
        MpMat corner[2][2];
        for (int si = 0; si < 2; ++si)
          for (int sp = 0; sp < 2; ++sp) {
            DVec t = t0;
            t[i] += si ? kStep : -kStep;
            Geometry g = gc;
            g[p] += sp ? kStep : -kStep;
            corner[si][sp] = y(t, g);
          }
        const double scale = in.deviation[i].mag() * gh[p] / (4.0 * kStep * kStep);
        for (int k = 0; k < 6; ++k) {
          const Mp d = corner[1][1][k][0] - corner[1][0][k][0] - corner[0][1][k][0] + corner[0][0][k][0];
          mixed[i][p][k] = toDouble(d) * scale;
        }
      }
    }
    for (int k = 0; k < 6; ++k) {
      double coef[kMaxDof][kMaxGeometryParameters];
      double rounding = 0.0;
      act.bilinearCoefficients(a, k, 0, coef, rounding);
      double largest = 0.0, error = 0.0;
      for (int i = 0; i < 6; ++i)
        for (int p = 0; p < params; ++p) {
          largest = std::max(largest, std::abs(mixed[i][p][k]));
          error = std::max(error, std::abs(coef[i][p] - mixed[i][p][k]));
        }
      ASSERT_GT(largest, 0.0);
      EXPECT_LT(error, 1e-3 * largest) << "trial " << trial << " row " << k;
      worst = std::max(worst, error / largest);
    }
  }
  std::cout << "[ info     ] bilinear coefficients within " << worst << " of the largest mixed derivative\n";
}

// =====================================================================================================================
// 4. Evidence on the reference robot
// =====================================================================================================================

namespace {

/// Independent sampling of the error over poses AND geometries of an uncertain robot on a pose box.
struct Sampled {
  DVec max = DVec::Zero(6);  ///< max over sampled poses and geometries
  std::vector<DVec> argmax = std::vector<DVec>(6);
  /// max over sampled poses of (min over the sampled geometries at that pose): where some pose seems to exceed for
  /// every geometry (an over-estimate of the true value at that pose).
  DVec maxOfMin = DVec::Zero(6);
  std::vector<DVec> argmaxOfMin = std::vector<DVec>(6);
};

/// The geometries sampled at one pose: the worst vertices of every component by gradient signs at the nominal
/// geometry (refined by vertex flips if asked), random vertices and interior points, the nominal.
std::vector<Geometry> sampleGeometries(const Uncertain& u, const DVec& q, std::mt19937_64& rng, bool refine) {
  std::vector<Geometry> out;
  const Eigen::MatrixXd grad = u.gradient(u.nominal, q);
  for (int k = 0; k < 6; ++k)
    for (const double dir : {1.0, -1.0}) {
      const Geometry g = u.vertexBySigns(grad, k, dir);
      out.push_back(g);
      if (refine) out.push_back(u.vertexSearch(q, k, dir, g));
    }
  for (int s = 0; s < 3; ++s) out.push_back(u.randomVertex(rng));
  for (int s = 0; s < 2; ++s) out.push_back(u.randomInterior(rng));
  out.push_back(u.nominal);
  return out;
}

Sampled sample(const Uncertain& u, const IVec& box, int randomPoses, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<DVec> poses;
  for (int corner = 0; corner < 64; ++corner) {
    DVec q(6);
    for (int i = 0; i < 6; ++i) q[i] = (corner >> i) & 1 ? box[i].upper() : box[i].lower();
    poses.push_back(q);
  }
  for (int s = 0; s < randomPoses; ++s) poses.push_back(test::randomPoint(box, rng));
  // Screen the poses with the nominal geometry; the best ones per component get the refined geometry search.
  std::vector<DVec> nominal;
  for (const DVec& q : poses) nominal.push_back(u.error(u.nominal, q));
  Sampled out;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    bool top = false;
    for (int k = 0; k < 6; ++k) {
      int better = 0;
      for (std::size_t j = 0; j < poses.size() && better < 4; ++j) better += nominal[j][k] > nominal[i][k];
      top = top || better < 4;
    }
    const std::vector<Geometry> geometries = sampleGeometries(u, poses[i], rng, top);
    DVec lowest = DVec::Constant(6, std::numeric_limits<double>::infinity());
    for (const Geometry& g : geometries) {
      const DVec f = u.error(g, poses[i]);
      for (int k = 0; k < 6; ++k) {
        if (f[k] > out.max[k]) {
          out.max[k] = f[k];
          out.argmax[k] = poses[i];
        }
        lowest[k] = std::min(lowest[k], f[k]);
      }
    }
    for (int k = 0; k < 6; ++k)
      if (lowest[k] > out.maxOfMin[k]) {
        out.maxOfMin[k] = lowest[k];
        out.argmaxOfMin[k] = poses[i];
      }
  }
  return out;
}

/// Smallest f_k over the geometries sampled at pose q (worst vertices for the minimum included).
double sampledMinimum(const Uncertain& u, const DVec& q, int k, std::mt19937_64& rng) {
  double lowest = std::numeric_limits<double>::infinity();
  for (const Geometry& g : sampleGeometries(u, q, rng, true)) lowest = std::min(lowest, u.error(g, q)[k]);
  for (int s = 0; s < 20; ++s)
    lowest = std::min(lowest, u.error(s % 2 ? u.randomVertex(rng) : u.randomInterior(rng), q)[k]);
  return lowest;
}

Geometry toGeometry(const std::vector<double>& v) { return Geometry(v.begin(), v.end()); }

/// Every value of a reported geometry is admissible as given: g_p in [nominal_p - h_p, nominal_p + h_p] as real
/// numbers (not merely in the model's ranges, which are rounded outward).
bool admissible(const Uncertain& u, const std::vector<double>& g) {
  if (static_cast<int>(g.size()) != u.count()) return false;
  for (int p = 0; p < u.count(); ++p)
    if (!test::withinHalfWidth(g[p], u.nominal[p], u.coords[p].half)) return false;
  return true;
}

/// The sub-box of `paper` with `fraction` of every width at its (+x, +y, +z, +angles) vertex. The error maxima of
/// `paper` are at its vertices (sampled: each component's maximum over the 1/16 corner box is 74-91% of its maximum
/// over `paper`, h = 0.5 and 1 mm), and the maxima over the corner box are at vertices of the box too, where the
/// search must close its bounds: a small problem with the structure of the whole one.
IVec cornerBox(double fraction) {
  const IVec paper = test::ref6File().workspaces.at("paper").initialBox();
  IVec box(6);
  for (int i = 0; i < 6; ++i) {
    const double w = (paper[i].upper() - paper[i].lower()) * fraction;
    box[i] = Interval(paper[i].upper() - w, paper[i].upper());
  }
  return box;
}

/// Checks a max-error result against independent evaluations: converged brackets of the sampled maxima, and the
/// lower bound attained at (argmax, argmax geometry) in double and MPFR, or, when no geometry is given (the bound
/// holds for every geometry), at every sampled geometry including the minimising vertices.
void checkMaxError(const verify::VerifierResult& r, const Uncertain& u, const IVec& box, const Sampled& s, double alpha,
                   std::mt19937_64& rng) {
  EXPECT_TRUE(r.converged) << r.message;
  ASSERT_EQ(r.max_lower.size(), 6);
  ASSERT_EQ(r.max_upper.size(), 6);
  ASSERT_EQ(r.max_argmax.size(), 6u);
  ASSERT_EQ(r.max_argmax_geometry.size(), 6u);
  for (int k = 0; k < 6; ++k) {
    EXPECT_GE(r.max_upper[k], s.max[k]) << k;
    EXPECT_LE(r.max_lower[k], r.max_upper[k]) << k;
    EXPECT_LE(r.max_upper[k] - r.max_lower[k], alpha * r.max_lower[k] * (1 + 1e-9)) << k;
    ASSERT_EQ(r.max_argmax[k].size(), 6) << k;
    for (int i = 0; i < 6; ++i) EXPECT_TRUE(box[i].contains(r.max_argmax[k][i])) << k;
    const std::vector<double>& g = r.max_argmax_geometry[k];
    if (!g.empty()) {
      ASSERT_TRUE(admissible(u, g)) << k;
      EXPECT_GE(u.error(toGeometry(g), r.max_argmax[k])[k], r.max_lower[k] * (1 - 1e-9)) << k;
      EXPECT_TRUE(mpGreaterEqual(mpfrWorstError(u.at(toGeometry(g)), r.max_argmax[k])[k], r.max_lower[k])) << k;
    } else {
      EXPECT_GE(sampledMinimum(u, r.max_argmax[k], k, rng), r.max_lower[k] * (1 - 1e-9)) << k;
    }
  }
}

/// Checks an uncertainty-sensitive pose independently: inside the box, its failing geometry admissible and above
/// the threshold (double and MPFR, and at least the certified failing_lower), its passing geometry (if any) below.
void checkSensitivePose(const verify::SensitivePose& sp, const Uncertain& u, const IVec& box, const DVec& thresholds) {
  const int k = sp.component;
  ASSERT_GE(k, 0);
  ASSERT_LT(k, 6);
  ASSERT_EQ(sp.point.size(), 6);
  ASSERT_EQ(sp.pose.size(), 6);
  for (int i = 0; i < 6; ++i) {
    EXPECT_TRUE(box[i].contains(sp.point[i]));
    EXPECT_TRUE(sp.pose[i].contains(sp.point[i]));
    EXPECT_TRUE(sp.region[i].contains(sp.point[i]));
  }
  ASSERT_TRUE(admissible(u, sp.failing_geometry));
  EXPECT_GT(sp.failing_lower, thresholds[k]);
  EXPECT_GT(u.error(toGeometry(sp.failing_geometry), sp.point)[k], thresholds[k]) << where(sp.point);
  EXPECT_TRUE(mpGreaterEqual(mpfrWorstError(u.at(toGeometry(sp.failing_geometry)), sp.point)[k], sp.failing_lower));
  if (!sp.passing_geometry.empty()) {
    ASSERT_TRUE(admissible(u, sp.passing_geometry));
    const DVec fp = u.error(toGeometry(sp.passing_geometry), sp.point);
    EXPECT_LE(fp[k], thresholds[k]) << where(sp.point);
    EXPECT_TRUE(mpLessEqual(mpfrWorstError(u.at(toGeometry(sp.passing_geometry)), sp.point)[k], sp.passing_upper));
    if (sp.passes_all) {
      for (int j = 0; j < 6; ++j) EXPECT_LE(fp[j], thresholds[j]) << j;
    }
  }
}

/// Checks an UNSAFE witness independently: inside the box, and above the threshold for every sampled geometry
/// (the minimising vertices included); every component's certified lower bound at most its sampled minimum.
void checkWitness(const verify::VerifierResult& r, const Uncertain& u, const IVec& box, const DVec& thresholds,
                  std::mt19937_64& rng) {
  ASSERT_EQ(r.verdict, Verdict::Unsafe) << r.message;
  const int k = r.witness_component;
  ASSERT_GE(k, 0);
  ASSERT_EQ(r.witness.size(), 6);
  for (int i = 0; i < 6; ++i) EXPECT_TRUE(box[i].contains(r.witness[i]));
  EXPECT_GT(r.witness_lower_bound, thresholds[k]);
  EXPECT_GT(sampledMinimum(u, r.witness, k, rng), thresholds[k]) << where(r.witness);
  ASSERT_EQ(r.witness_error_lower.size(), 6);
  for (int j = 0; j < 6; ++j) {
    EXPECT_LE(r.witness_error_lower[j], sampledMinimum(u, r.witness, j, rng) * (1 + 1e-9)) << j;
  }
}

}  // namespace

/// The reference evidence on a corner of the paper workspace (see the TESTs below), with the combined geometry form
/// or the decomposed one (VerifierOptions::decompose_geometry).
void checkReferenceAnswers(bool decomposed) {
  SCOPED_TRACE(decomposed ? "decomposed" : "combined");
  const io::RobotFile rf = test::ref6File();
  const IVec box = cornerBox(1.0 / 16.0);
  const domain::Workspace ws = domain::Workspace::fromRanges(test::toRanges(box));
  int cases = 0;
  for (const double h : rf.anchor_uncertainty_cases) {
    if (!(h > 0.0)) continue;
    ++cases;
    SCOPED_TRACE("h = " + std::to_string(h));
    const Uncertain u(withUncertainty(h));
    const model::GoughPlatform robot(u.geometry);
    const Sampled s = sample(u, box, 600, 707);
    std::mt19937_64 rng(708);

    // ---- max-error mode: brackets, and the lower bound attained at (argmax, argmax geometry) ----
    // alpha: 2% at h = 0.5 mm. At h = 1 mm the bound of a single pose exceeds the worst geometry by up to ~6%
    // (second-order remainder, see SecondOrderBoundsEveryAdmissibleGeometryOnRandomBoxes) and 2% (or 5%) does not
    // converge within 15 s even with strategy (b) (reported), so 10% there.
    verify::VerifierOptions o;
    o.tuning.decompose_geometry = decomposed;
    o.mode = verify::Mode::MaxError;
    o.alpha = h <= 0.0005 ? 0.02 : 0.1;
    o.time_limit_s = 30.0;  // a safety net: both converge in < 0.2 s
    checkMaxError(verify::Verifier::run(robot, ws, o), u, box, s, o.alpha, rng);

    // ---- verify mode: 10% above the sampled maxima (over poses and geometries) is SAFE ----
    verify::VerifierOptions v;
    v.tuning.decompose_geometry = decomposed;
    v.thresholds = s.max * 1.10;
    const auto safe = verify::Verifier::run(robot, ws, v);
    EXPECT_EQ(safe.verdict, Verdict::Safe) << safe.message;
    EXPECT_EQ(safe.undecided_box_count, 0u);
    EXPECT_EQ(safe.sensitive_count, 0u);
    EXPECT_NEAR(safe.stats.safe_fraction, 1.0, 1e-9);

    // ---- 5% below: UNSAFE (witness for every geometry) or UNDECIDED (uncertainty_sensitive) ----
    v.thresholds = s.max * 0.95;
    const auto below = verify::Verifier::run(robot, ws, v);
    ASSERT_NE(below.verdict, Verdict::Safe) << below.message;
    if (below.verdict == Verdict::Unsafe) {
      checkWitness(below, u, box, v.thresholds, rng);
    } else {
      ASSERT_EQ(below.reason, UndecidedReason::UncertaintySensitive) << below.message;
      EXPECT_EQ(toString(below.reason), "uncertainty_sensitive");
      ASSERT_GE(below.sensitive_count, 1u);
      ASSERT_FALSE(below.sensitive.empty());
      checkSensitivePose(below.sensitive.front(), u, box, v.thresholds);
    }
    // Which one our own sampling says. UNSAFE needs a pose where f_k exceeds for every geometry, certified by
    // errorAtPose whose lower end is below the true minimum over the geometries by a second-order amount (measured
    // <= 1.5% at h = 0.5 mm, <= 8% at 1 mm). So: a box corner (the pre-sampling grid holds every corner) exceeding
    // for every sampled geometry by more than 100 h (5%, 10%) makes UNSAFE certain; no sampled pose (all corners,
    // with vertex searches for the extremes, and 600 random poses) within 2% of exceeding for every sampled geometry
    // makes it impossible in practice, so the answer must be uncertainty_sensitive.
    bool cornerWitness = false, noWitness = true;
    for (int k = 0; k < 6; ++k) {
      const DVec& q = s.argmaxOfMin[k];
      bool corner = true;
      for (int i = 0; i < 6; ++i) corner = corner && (q[i] == box[i].lower() || q[i] == box[i].upper());
      if (corner && s.maxOfMin[k] > (1.0 + 100.0 * h) * v.thresholds[k]) cornerWitness = true;
      if (s.maxOfMin[k] > 0.98 * v.thresholds[k]) noWitness = false;
    }
    std::cout << "[ info     ] h=" << h << ": 5% below -> " << toString(below.verdict) << " (" << toString(below.reason)
              << "); sampled (max over poses of min over geometries) / (max over both):";
    for (int k = 0; k < 6; ++k) std::cout << " " << s.maxOfMin[k] / s.max[k];
    std::cout << "\n";
    EXPECT_TRUE(cornerWitness || noWitness) << "the sampling does not make the expected answer clear";
    if (cornerWitness) {
      EXPECT_EQ(below.verdict, Verdict::Unsafe) << below.message;
    }
    if (noWitness) {
      EXPECT_EQ(below.reason, UndecidedReason::UncertaintySensitive) << below.message;
    }

    // ---- clearly lower thresholds (30% below): UNSAFE with a witness checked for every sampled geometry ----
    v.thresholds = s.max * 0.70;
    checkWitness(verify::Verifier::run(robot, ws, v), u, box, v.thresholds, rng);

    // ---- the same without stopping at the first evidence (a box budget): every recorded sensitive pose checked,
    // whole boxes certified unsafe for every geometry, volume fractions adding up ----
    v.stop_at_first_witness = false;
    v.max_boxes = 2000;
    const auto all = verify::Verifier::run(robot, ws, v);
    checkWitness(all, u, box, v.thresholds, rng);
    EXPECT_GT(all.stats.unsafe_fraction, 0.0);
    EXPECT_NEAR(all.stats.safe_fraction + all.stats.unsafe_fraction + all.stats.undecided_fraction, 1.0, 1e-9);
    v.thresholds = s.max * 0.95;
    const auto sensitive = verify::Verifier::run(robot, ws, v);
    EXPECT_EQ(sensitive.reason, UndecidedReason::UncertaintySensitive) << sensitive.message;
    EXPECT_GE(sensitive.sensitive_count, sensitive.sensitive.size());
    EXPECT_GT(sensitive.sensitive.size(), 1u);
    for (std::size_t i = 0; i < sensitive.sensitive.size() && i < 25; ++i) {
      checkSensitivePose(sensitive.sensitive[i], u, box, v.thresholds);
    }
    EXPECT_NEAR(sensitive.stats.safe_fraction + sensitive.stats.unsafe_fraction + sensitive.stats.undecided_fraction,
                1.0, 1e-9);
  }
  EXPECT_EQ(cases, 2);
}

TEST(UncertaintyVerifier, MaxErrorAndVerdictsOnTheReferenceRobot) { checkReferenceAnswers(false); }

// VerifierOptions::decompose_geometry: the same answers (brackets that hold and close, SAFE 10% above the sampled
// maxima, UNSAFE or uncertainty_sensitive as the sampling says 5% below, witnesses for every geometry 30% below).
TEST(UncertaintyVerifier, DecomposedGeometryFormKeepsTheReferenceAnswers) { checkReferenceAnswers(true); }

// Verify mode without stopping at the first witness and without pre-sampling, on a box where every pose exceeds every
// threshold for every admissible geometry (half the smallest nominal error at its corners and centre): the root box's
// enclosure certifies that at once (ErrorBounds::lower). The verdict must be UNSAFE with a witness in the box that
// exceeds for every sampled geometry, not SAFE with the volume counted as unsafe.
TEST(UncertaintyVerifier, BoxCertifiedUnsafeWithoutPresamplingGivesAWitness) {
  const Uncertain u(withUncertainty(0.0005));
  const model::GoughPlatform robot(u.geometry);
  const IVec box = cornerBox(1.0 / 256.0);
  const domain::Workspace ws = domain::Workspace::fromRanges(test::toRanges(box));
  DVec smallest = DVec::Constant(6, std::numeric_limits<double>::infinity());
  for (int corner = 0; corner <= 64; ++corner) {
    DVec q(6);
    for (int i = 0; i < 6; ++i)
      q[i] = corner == 64 ? box[i].mid() : ((corner >> i) & 1 ? box[i].upper() : box[i].lower());
    smallest = smallest.cwiseMin(u.error(u.nominal, q));
  }
  std::mt19937_64 rng(1201);
  for (const int threads : {1, 2}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    verify::VerifierOptions o;
    o.thresholds = 0.5 * smallest;
    o.presample_points = 0;
    o.stop_at_first_witness = false;
    o.threads = threads;
    const auto r = verify::Verifier::run(robot, ws, o);
    checkWitness(r, u, box, o.thresholds, rng);
    EXPECT_GT(r.stats.unsafe_fraction, 0.0);
    EXPECT_NEAR(r.stats.safe_fraction + r.stats.unsafe_fraction + r.stats.undecided_fraction, 1.0, 1e-9);
  }
}

// The geometries a result reports (max-error argmax geometries; sensitive poses' failing and passing geometries) lie
// in the admissible set as given, nominal +- h as real numbers (the model's ranges are rounded outward, their ends an
// ulp outside), and each max-error lower bound is attained there: a plain double evaluation at (argmax, geometry)
// reproduces it to round-off.
TEST(UncertaintyVerifier, ReportedGeometriesAreAdmissibleExactlyAndAttainTheirBounds) {
  const Uncertain u(withUncertainty(0.0005));
  const model::GoughPlatform robot(u.geometry);
  const IVec box = cornerBox(1.0 / 16.0);
  const domain::Workspace ws = domain::Workspace::fromRanges(test::toRanges(box));
  verify::VerifierOptions o;
  o.mode = verify::Mode::MaxError;
  o.alpha = 0.02;
  o.time_limit_s = 30.0;  // a safety net
  const auto r = verify::Verifier::run(robot, ws, o);
  ASSERT_EQ(r.max_argmax_geometry.size(), 6u);
  int named = 0;
  for (int k = 0; k < 6; ++k) {
    SCOPED_TRACE("component " + std::to_string(k));
    const std::vector<double>& g = r.max_argmax_geometry[k];
    if (g.empty()) continue;  // (the bound holds for every geometry)
    ++named;
    ASSERT_EQ(static_cast<int>(g.size()), u.count());
    for (int p = 0; p < u.count(); ++p) {
      EXPECT_TRUE(test::withinHalfWidth(g[p], u.nominal[p], u.coords[p].half))
          << robot.geometryParameterName(p) << " = " << g[p] << " outside " << u.nominal[p] << " +- "
          << u.coords[p].half;
    }
    const double value = u.error(g, r.max_argmax[k])[k];
    EXPECT_GE(value, r.max_lower[k] * (1.0 - 1e-12));
    EXPECT_LE(value, r.max_lower[k] * (1.0 + 1e-9));
  }
  EXPECT_GE(named, 1);

  verify::VerifierOptions v;
  v.thresholds = 0.95 * r.max_lower;
  v.stop_at_first_witness = false;
  v.max_boxes = 300;
  const auto sensitive = verify::Verifier::run(robot, ws, v);
  ASSERT_GE(sensitive.sensitive.size(), 1u) << sensitive.message;
  for (const verify::SensitivePose& s : sensitive.sensitive) {
    EXPECT_TRUE(admissible(u, s.failing_geometry));
    EXPECT_TRUE(s.passing_geometry.empty() || admissible(u, s.passing_geometry));
  }
}

// =====================================================================================================================
// 5. Strategy (b): bisecting the geometry
// =====================================================================================================================

TEST(UncertaintyEnclosure, MonotoneFaceBoundHoldsAndTightensNearTheWorstCorner) {
  // Where f_k is certified monotone in some geometry parameters over the box, the bound is also taken on the face
  // of the geometry box with those parameters at their raising ends, where |L L y| keeps its signs
  // (PreconditionedInverseEnclosure::upperOnFace). BoxInput::targets at +inf skips that refinement (every bound is then
  // "good enough"): the face bound must be no larger, strictly smaller somewhere near the worst corner at 1 mm, and
  // still above the true maxima (worst vertices by vertex search, in double and MPFR).
  const io::RobotFile rf = test::ref6File();
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const auto method = enclosure::makeEnclosure("second_order");
  for (const double h : {0.0005, 0.001}) {
    SCOPED_TRACE("h = " + std::to_string(h));
    const Uncertain u(withUncertainty(h));
    const model::GoughPlatform robot(u.geometry);
    std::mt19937_64 rng(616);
    int tighter = 0, checked = 0;
    for (const double fraction : {0.0, 1.0 / 512.0, 1.0 / 128.0, 1.0 / 64.0}) {
      const IVec box = cornerBox(fraction);
      enclosure::BoxInput in;
      ws.poseView(box, true, in);
      enclosure::ErrorBounds face, plain;
      method->enclose(robot, in, face);
      in.targets = DVec::Constant(6, std::numeric_limits<double>::infinity());
      method->enclose(robot, in, plain);
      ASSERT_TRUE(face.bounded());
      ASSERT_TRUE(plain.bounded());
      for (int k = 0; k < 6; ++k) {
        EXPECT_LE(face.upper[k], plain.upper[k]) << k;
        tighter += face.upper[k] < plain.upper[k] * (1 - 1e-3) ? 1 : 0;
      }
      for (int s = 0; s < 3; ++s) {
        DVec q(6);
        for (int i = 0; i < 6; ++i) q[i] = s == 0 ? box[i].upper() : test::randomPoint(box, rng)[i];
        const Eigen::MatrixXd grad = u.gradient(u.nominal, q);
        for (int k = 0; k < 6; ++k) {
          const Geometry worst = u.vertexSearch(q, k, 1.0, u.vertexBySigns(grad, k, 1.0));
          EXPECT_LE(u.error(worst, q)[k], face.upper[k] * (1 + 1e-12)) << "k=" << k << " fraction " << fraction;
          const auto exact = mpfrWorstError(u.at(worst), q);
          EXPECT_TRUE(mpLessEqual(exact[k], face.upper[k])) << "k=" << k << " fraction " << fraction;
          ++checked;
        }
      }
    }
    EXPECT_EQ(checked, 72);
    if (h == 0.001) {
      EXPECT_GT(tighter, 4);
    }
    std::cout << "[ info     ] h=" << h << ": face bound tighter by more than 0.1% for " << tighter
              << " of 24 (box, component) pairs at the worst corner\n";
  }
}

TEST(UncertaintyEnclosure, AffineGeometryDotsKeepTheCornerBoundsTight) {
  // The affine geometry derivatives (PreconditionedInverseEnclosure's dot products d_e . v from the model's affine
  // forms) are part of what keeps the +-1 mm bounds tight on mid-sized boxes. On the 1/16 and 1/8 boxes at the paper
  // workspace's upper corner, the bounds' excesses over the maxima sampled over poses and geometries add up to
  // 0.352 and 1.629 over the six components (bounds 1.036-1.084 and 1.143-1.416 x the maxima); with the dot products
  // as interval products of d_e's enclosure instead (PreconditionedInverseEnclosure without the affine forms), 0.400
  // and 1.765 (measured). The limits lie in between; every bound must also be above its sampled maximum.
  const io::RobotFile rf = test::ref6File();
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const auto method = enclosure::makeEnclosure("second_order");
  const Uncertain u(withUncertainty(0.001));
  const model::GoughPlatform robot(u.geometry);
  for (const double fraction : {1.0 / 16.0, 1.0 / 8.0}) {
    const IVec box = cornerBox(fraction);
    const Sampled s = sample(u, box, 60, 909);
    enclosure::BoxInput in;
    ws.poseView(box, true, in);
    enclosure::ErrorBounds b;
    method->enclose(robot, in, b);
    ASSERT_TRUE(b.bounded());
    std::cout << "[ info     ] 1/" << 1.0 / fraction << " corner box, bound / sampled maximum:";
    double excess = 0.0;
    for (int k = 0; k < 6; ++k) {
      std::cout << " " << b.upper[k] / s.max[k];
      EXPECT_GE(b.upper[k], s.max[k]) << k;
      excess += b.upper[k] / s.max[k] - 1.0;
    }
    std::cout << "\n";
    EXPECT_LT(excess, fraction < 0.1 ? 0.37 : 1.69) << "1/" << 1.0 / fraction;
  }
}

TEST(UncertaintyVerifier, StrategyBSwitchesOnStallsAndKeepsTheVerdict) {
  // h = 1 mm on the 1/32 corner box. At +0.4% of the sampled maxima strategy (a) alone does not conclude within 3 000
  // boxes (the plain bound stays above the worst geometry by its second-order geometry remainder), while stalled paths
  // (stall_levels = 1) that switch to bisecting the geometry prove SAFE (measured: 81 boxes, 18 geometry splits; at
  // +0.75% strategy (a) settles the box in 5 boxes, at +0.2% neither within 2e4). 1% below the maxima every mode must
  // find the same uncertainty-sensitive answer. The faces step, which stalled paths take first, is off here (its own
  // tests are in section 7).
  const Uncertain u(withUncertainty(0.001));
  const model::GoughPlatform robot(u.geometry);
  const IVec box = cornerBox(1.0 / 32.0);
  const domain::Workspace ws = domain::Workspace::fromRanges(test::toRanges(box));
  const Sampled s = sample(u, box, 100, 808);
  for (const double factor : {1.004, 0.99}) {
    SCOPED_TRACE("thresholds x " + std::to_string(factor));
    verify::VerifierOptions o;
    o.thresholds = s.max * factor;
    o.threads = 1;
    o.max_boxes = 3000;
    o.tuning.faces = false;
    o.geometry_splitting = verify::GeometrySplitting::Never;
    const auto never = verify::Verifier::run(robot, ws, o);
    EXPECT_EQ(never.stats.geometry_switches, 0u);
    EXPECT_EQ(never.stats.geometry_splits, 0u);
    o.max_boxes = 20000;  // a safety net
    o.geometry_splitting = verify::GeometrySplitting::Auto;
    o.tuning.stall_levels = 1;
    const auto autoRun = verify::Verifier::run(robot, ws, o);
    std::cout << "[ info     ] x" << factor << ": strategy (a) " << never.stats.boxes << " boxes, auto "
              << autoRun.stats.boxes << " boxes, " << autoRun.stats.geometry_switches << " switches, "
              << autoRun.stats.geometry_splits << " geometry splits\n";
    EXPECT_GE(autoRun.stats.geometry_splits, autoRun.stats.geometry_switches);
    // Threads: same verdict.
    o.threads = 2;
    const auto two = verify::Verifier::run(robot, ws, o);
    EXPECT_EQ(two.verdict, autoRun.verdict) << two.message;
    EXPECT_EQ(two.reason, autoRun.reason);
    EXPECT_EQ(two.stats.threads, 2);
    if (factor > 1.0) {
      EXPECT_EQ(never.verdict, Verdict::Undecided) << never.message;
      EXPECT_EQ(never.reason, UndecidedReason::BoxBudget) << never.message;
      EXPECT_EQ(autoRun.verdict, Verdict::Safe) << autoRun.message;
      EXPECT_GT(autoRun.stats.geometry_switches, 0u);
      EXPECT_EQ(autoRun.undecided_box_count, 0u);
      EXPECT_NEAR(autoRun.stats.safe_fraction, 1.0, 1e-9);  // the geometry halves' volumes add up
    } else {
      // The sampled maximum is a real error value (a pose and an admissible geometry) above the thresholds: no
      // mode may prove SAFE, and no pose exceeds for every sampled geometry (max-of-min is ~85% of the max).
      EXPECT_EQ(never.verdict, Verdict::Undecided) << never.message;
      EXPECT_EQ(never.reason, UndecidedReason::UncertaintySensitive) << never.message;
      EXPECT_EQ(autoRun.verdict, never.verdict) << autoRun.message;
      EXPECT_EQ(autoRun.reason, never.reason);
      o.threads = 1;
      o.geometry_splitting = verify::GeometrySplitting::Always;
      o.tuning.stall_levels = 0;
      const auto always = verify::Verifier::run(robot, ws, o);
      EXPECT_EQ(always.verdict, never.verdict) << always.message;
      EXPECT_EQ(always.reason, never.reason);
    }
  }

  // A tiny box budget: the undecided records searched on a geometry sub-box carry sub-intervals of the ranges (at
  // +0.4% with 60 boxes, where the run above needs 81).
  verify::VerifierOptions o;
  o.thresholds = s.max * 1.004;
  o.geometry_splitting = verify::GeometrySplitting::Auto;
  o.tuning.faces = false;
  o.tuning.stall_levels = 1;
  o.threads = 1;
  o.max_boxes = 60;
  o.presample_points = 0;
  const auto partial = verify::Verifier::run(robot, ws, o);
  std::cout << "[ info     ] x1.004, 60 boxes: " << partial.stats.geometry_switches << " switches, "
            << partial.undecided_boxes.size() << " undecided boxes listed\n";
  EXPECT_EQ(partial.verdict, Verdict::Undecided);
  EXPECT_EQ(partial.reason, UndecidedReason::BoxBudget);
  EXPECT_NEAR(partial.stats.safe_fraction + partial.stats.undecided_fraction + partial.stats.outside_fraction, 1.0,
              1e-9);
  EXPECT_GT(partial.stats.geometry_switches, 0u);
  int withGeometry = 0;
  for (const verify::BoxRecord& b : partial.undecided_boxes) {
    if (b.geometry.empty()) continue;
    ++withGeometry;
    ASSERT_EQ(static_cast<int>(b.geometry.size()), robot.geometryParameterCount());
    bool narrower = false;
    for (int p = 0; p < robot.geometryParameterCount(); ++p) {
      const Interval full = robot.geometryParameterRange(p);
      EXPECT_TRUE(b.geometry[p].isSubsetOf(full)) << p;
      EXPECT_FALSE(b.geometry[p].isEmpty()) << p;
      narrower = narrower || b.geometry[p].width() < full.width();
    }
    EXPECT_TRUE(narrower);
  }
  EXPECT_GT(withGeometry, 0);
}

TEST(UncertaintyEnclosure, CentreEstimateIsNotBelowTheWorstSampledGeometryAtTheBoxCentre) {
  // ErrorBounds::centreEstimate is not certified; the verifier skips a box's centre evaluation when every estimate
  // is below 0.98 x its threshold. That must not hide a centre whose error exceeds for some geometry: the estimate
  // may not fall more than 1% below the error at the worst sampled geometry there (the first-order geometry terms
  // make up the 5-18% by which that exceeds the centre geometry's error).
  const IVec paper = test::ref6File().workspaces.at("paper").initialBox();
  const domain::Workspace ws = domain::Workspace::fromRanges(test::toRanges(paper));
  const auto method = enclosure::makeEnclosure("second_order");
  std::mt19937_64 rng(1212);
  int checked = 0;
  double lowest = std::numeric_limits<double>::infinity();
  for (const double h : {0.0005, 0.001}) {
    const Uncertain u(withUncertainty(h));
    const model::GoughPlatform robot(u.geometry);
    for (int trial = 0; trial < 24; ++trial) {
      const IVec box = randomSubBox(paper, std::pow(0.5, 3 + trial % 4), rng);
      enclosure::BoxInput in;
      ws.poseView(box, true, in);
      enclosure::ErrorBounds out;
      method->enclose(robot, in, out);
      ASSERT_EQ(out.centreEstimate.size(), 6);
      DVec q(6);
      for (int i = 0; i < 6; ++i) q[i] = in.centrePose[i].mid();
      DVec worst = DVec::Zero(6);
      for (const Geometry& g : sampleGeometries(u, q, rng, true)) worst = worst.cwiseMax(u.error(g, q));
      for (int k = 0; k < 6; ++k) {
        if (!std::isfinite(out.centreEstimate[k])) continue;
        EXPECT_GE(out.centreEstimate[k], 0.99 * worst[k]) << "h " << h << " trial " << trial << " k " << k;
        lowest = std::min(lowest, out.centreEstimate[k] / worst[k]);
        ++checked;
      }
    }
  }
  std::cout << "[ info     ] centre estimate / worst sampled geometry >= " << lowest << " (" << checked << ")\n";
  EXPECT_GT(checked, 200);
}

TEST(UncertaintyVerifier, PresamplingCertifiesTheGridsWorstPointsOverEveryGeometry) {
  // +-0.5 mm on the whole paper workspace, thresholds 1% below the sampled maxima over poses and geometries (at
  // workspace corners, which the sampling grid contains). At the centre geometry the errors stay 5-8% below those
  // maxima, so the grid's double screening alone certifies no point; the grid's worst point of each component,
  // certified over every geometry, shows an uncertainty-sensitive pose before any box is enclosed (without it the
  // search ran out of a 60 s budget).
  const Uncertain u(withUncertainty(0.0005));
  const model::GoughPlatform robot(u.geometry);
  const io::RobotFile rf = test::ref6File();
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const Sampled s = sample(u, ws.initialBox(), 20, 909);
  verify::VerifierOptions o;
  o.thresholds = s.max * 0.99;
  o.threads = 1;
  o.time_limit_s = 20.0;  // a safety net
  const auto r = verify::Verifier::run(robot, ws, o);
  EXPECT_EQ(r.verdict, Verdict::Undecided) << r.message;
  EXPECT_EQ(r.reason, UndecidedReason::UncertaintySensitive) << r.message;
  EXPECT_EQ(r.stats.boxes, 0u);
  ASSERT_GE(r.sensitive_count, 1u);
  ASSERT_FALSE(r.sensitive.empty());
  checkSensitivePose(r.sensitive.front(), u, ws.initialBox(), o.thresholds);
}

TEST(UncertaintyVerifier, StrategyBProvesWhatIntervalCoefficientsCannot) {
  // h = 1 mm on the 1/128 corner box at +0.4% of the sampled maxima: the single-pose bound exceeds the worst
  // geometry by more than that at the corner (second-order remainder), so strategy (a) alone cannot conclude;
  // bisecting the geometry does (the faces off), and so do the faces. (At +0.75% strategy (a) settles the box at
  // once.)
  const Uncertain u(withUncertainty(0.001));
  const model::GoughPlatform robot(u.geometry);
  const IVec box = cornerBox(1.0 / 128.0);
  const domain::Workspace ws = domain::Workspace::fromRanges(test::toRanges(box));
  const Sampled s = sample(u, box, 100, 809);
  std::mt19937_64 rng(810);
  verify::VerifierOptions o;
  o.thresholds = s.max * 1.004;
  o.threads = 1;
  o.tuning.faces = false;
  o.geometry_splitting = verify::GeometrySplitting::Never;
  o.max_boxes = 3000;
  const auto never = verify::Verifier::run(robot, ws, o);
  EXPECT_EQ(never.verdict, Verdict::Undecided) << never.message;
  EXPECT_EQ(never.reason, UndecidedReason::BoxBudget);
  // The faces alone (no geometry bisection, stalled paths after 1 level): SAFE.
  o.tuning.faces = true;
  o.tuning.stall_levels = 1;
  const auto faced = verify::Verifier::run(robot, ws, o);
  EXPECT_EQ(faced.verdict, Verdict::Safe) << faced.message;
  EXPECT_GT(faced.stats.face_switches, 0u);
  EXPECT_EQ(faced.stats.geometry_splits, 0u);
  std::cout << "[ info     ] faces, no geometry bisection: " << faced.stats.boxes << " boxes\n";
  o.tuning.faces = false;
  o.tuning.stall_levels = 0;
  o.max_boxes = 20000;  // a safety net: a few hundred boxes are measured (Always) and a few dozen (Auto)
  for (const auto mode : {verify::GeometrySplitting::Always, verify::GeometrySplitting::Auto}) {
    o.geometry_splitting = mode;
    o.tuning.stall_levels = mode == verify::GeometrySplitting::Auto ? 1 : 0;
    for (const int threads : {1, 2}) {
      o.threads = threads;
      const auto r = verify::Verifier::run(robot, ws, o);
      EXPECT_EQ(r.verdict, Verdict::Safe) << r.message;
      EXPECT_GT(r.stats.geometry_splits, 0u);
      EXPECT_NEAR(r.stats.safe_fraction, 1.0, 1e-9);
    }
  }
  // Max-error mode with geometry bisection: brackets checked independently (alpha 0.5%: at 1% the bounds converge
  // without any geometry split; at 0.3% not within 20 s).
  verify::VerifierOptions m;
  m.mode = verify::Mode::MaxError;
  m.alpha = 0.005;
  m.geometry_splitting = verify::GeometrySplitting::Always;
  m.tuning.faces = false;
  m.time_limit_s = 20.0;
  const auto r = verify::Verifier::run(robot, ws, m);
  EXPECT_GT(r.stats.geometry_splits, 0u);
  checkMaxError(r, u, box, s, m.alpha, rng);
}

// =====================================================================================================================
// 6. Nominal robot: the geometry options change nothing
// =====================================================================================================================

TEST(UncertaintyVerifier, NominalRobotIgnoresTheGeometryOptionsBitForBit) {
  const io::RobotFile rf = test::ref6File();
  const model::GoughPlatform robot(withUncertainty(0.0));
  ASSERT_EQ(robot.geometryParameterCount(), 0);
  const IVec box = test::centredSubBox(rf.workspaces.at("paper").initialBox(), 1.0 / 32.0);
  const domain::Workspace ws = domain::Workspace::fromRanges(test::toRanges(box));
  const Uncertain nominal(withUncertainty(0.0));
  const Sampled s = sample(nominal, box, 200, 909);
  auto same = [](const verify::VerifierResult& a, const verify::VerifierResult& b, const std::string& what) {
    SCOPED_TRACE(what);
    EXPECT_EQ(a.verdict, b.verdict);
    EXPECT_EQ(a.reason, b.reason);
    EXPECT_EQ(a.message, b.message);
    EXPECT_EQ(a.stats.boxes, b.stats.boxes);
    EXPECT_EQ(a.stats.max_depth, b.stats.max_depth);
    EXPECT_EQ(a.stats.safe_fraction, b.stats.safe_fraction);
    EXPECT_EQ(a.stats.undecided_fraction, b.stats.undecided_fraction);
    EXPECT_EQ(a.stats.geometry_switches, 0u);
    EXPECT_EQ(b.stats.geometry_switches, 0u);
    EXPECT_EQ(a.stats.geometry_splits, 0u);
    EXPECT_EQ(b.stats.geometry_splits, 0u);
    EXPECT_EQ(a.sensitive_count, 0u);
    EXPECT_EQ(b.sensitive_count, 0u);
    EXPECT_EQ(a.undecided_box_count, b.undecided_box_count);
    ASSERT_EQ(a.witness.size(), b.witness.size());
    for (int i = 0; i < a.witness.size(); ++i) EXPECT_EQ(a.witness[i], b.witness[i]);
    EXPECT_EQ(a.witness_component, b.witness_component);
    EXPECT_EQ(a.witness_lower_bound, b.witness_lower_bound);
    ASSERT_EQ(a.max_lower.size(), b.max_lower.size());
    for (int k = 0; k < a.max_lower.size(); ++k) {
      EXPECT_EQ(a.max_lower[k], b.max_lower[k]);
      EXPECT_EQ(a.max_upper[k], b.max_upper[k]);
      EXPECT_EQ(a.max_argmax[k], b.max_argmax[k]);
    }
    EXPECT_TRUE(a.max_argmax_geometry.empty() || a.max_argmax_geometry == b.max_argmax_geometry);
    ASSERT_EQ(a.undecided_boxes.size(), b.undecided_boxes.size());
    for (std::size_t i = 0; i < a.undecided_boxes.size(); ++i) {
      EXPECT_TRUE(a.undecided_boxes[i].geometry.empty());
      EXPECT_TRUE(b.undecided_boxes[i].geometry.empty());
    }
  };
  for (const double factor : {1.10, 0.95, 0.0}) {
    verify::VerifierOptions plain;
    plain.threads = 1;
    if (factor > 0.0) {
      plain.thresholds = s.max * factor;
    } else {
      plain.mode = verify::Mode::MaxError;
      plain.alpha = 0.05;
    }
    const auto reference = verify::Verifier::run(robot, ws, plain);
    if (factor > 1.0) {
      EXPECT_EQ(reference.verdict, Verdict::Safe);
    }
    if (factor > 0.0 && factor < 1.0) {
      EXPECT_EQ(reference.verdict, Verdict::Unsafe);
    }
    for (const auto mode :
         {verify::GeometrySplitting::Never, verify::GeometrySplitting::Always, verify::GeometrySplitting::Auto}) {
      for (const int stall : {0, 1, 5}) {
        verify::VerifierOptions o = plain;
        o.geometry_splitting = mode;
        o.tuning.stall_levels = stall;
        same(reference, verify::Verifier::run(robot, ws, o),
             "factor " + std::to_string(factor) + " mode " + std::to_string(static_cast<int>(mode)) + " stall " +
                 std::to_string(stall));
      }
    }
  }
}

// =====================================================================================================================
// Regression tests for problems found while writing these tests (fixed in the core; the comments describe the cause)
// =====================================================================================================================

namespace {

/// The box of the centred 1/16 paper sub-box at h = 1 mm where two of the problems below showed, as the enclosures see
/// it (ReproducerBox::in).
struct ReproducerBox {
  model::GoughPlatform robot{withUncertainty(0.001)};
  enclosure::BoxInput in;
  ReproducerBox() {
    const domain::Workspace ws = domain::Workspace::fromRanges(
        test::toRanges(test::centredSubBox(test::ref6File().workspaces.at("paper").initialBox(), 1.0 / 16.0)));
    IVec b(6);
    b << Interval(-0.00498047, -0.00483398), Interval(0.00761719, 0.00820312), Interval(0.475781, 0.475977),
        Interval(-0.0122718, -0.0102265), Interval(-0.00818123, 0), Interval(-0.0102265, -0.00920388);
    ws.poseView(b, true, in);
  }
};

}  // namespace

TEST(UncertaintyRegression, FallbackToIntervalCoefficientsLeavesNoZeroGeometryHints) {
  // A box of the centred 1/16 paper sub-box at h = 1 mm where PreconditionedInverseEnclosure::apply() accepts J = N C
  // but rejects 2 of the 64 sign columns (its Neumann verification), so encloseWithGeometry() returns false after
  // having set geometrySmear / geometrySensitivity to zero matrices of full size; the interval-coefficient path then
  // leaves them so. ErrorBounds documents them as empty outside the second-order geometry form; a zero 6 x 36 matrix
  // makes Verifier::chooseGeometrySplit() see valid-looking all-zero scores (no geometry split ever chosen for such
  // boxes) and errorAtPose() report zero sensitivities (vertexModel() then picks the all-upper vertex).
  const ReproducerBox r;
  enclosure::ErrorBounds eb;
  enclosure::makeEnclosure("second_order")->enclose(r.robot, r.in, eb);
  ASSERT_TRUE(eb.bounded());
  if (eb.geometrySmear.size() > 0) {
    EXPECT_GT(eb.geometrySmear.cwiseAbs().maxCoeff(), 0.0);
    EXPECT_GT(eb.geometrySensitivity.cwiseAbs().maxCoeff(), 0.0);
  }
}

TEST(UncertaintyRegression, SmearBisectionProvesSafeWhereItOnceStalled) {
  // h = 1 mm, centred 1/16 paper sub-box, thresholds 1.10 x sampled maxima: Smear bisection is still UNDECIDED
  // after thousands of boxes (depth 36+) while LargestScaledWidth proves SAFE in 167 boxes, and thresholds 1.08 x
  // (tighter!) are proven SAFE in 31 boxes. The stuck boxes are ones where the geometry form falls back to interval
  // coefficients (the apply() problem below): a bound ~10% looser, zero geometry smear, and a pose smear that misses
  // the variable (pitch) whose bisection removes 11% of the bound.
  const Uncertain u(withUncertainty(0.001));
  const model::GoughPlatform robot(u.geometry);
  const IVec box = test::centredSubBox(test::ref6File().workspaces.at("paper").initialBox(), 1.0 / 16.0);
  const domain::Workspace ws = domain::Workspace::fromRanges(test::toRanges(box));
  const Sampled s = sample(u, box, 100, 808);
  verify::VerifierOptions o;
  o.threads = 1;
  o.max_boxes = 5000;
  o.thresholds = s.max * 1.08;
  EXPECT_EQ(verify::Verifier::run(robot, ws, o).verdict, Verdict::Safe);
  o.tuning.bisection = verify::Bisection::LargestScaledWidth;
  o.thresholds = s.max * 1.10;
  EXPECT_EQ(verify::Verifier::run(robot, ws, o).verdict, Verdict::Safe);
  o.tuning.bisection = verify::Bisection::Smear;
  const auto r = verify::Verifier::run(robot, ws, o);
  EXPECT_EQ(r.verdict, Verdict::Safe) << r.message;
}

TEST(UncertaintyRegression, ApplySuccessDoesNotDependOnTheRightHandSide) {
  // PreconditionedInverseEnclosure::apply() verifies the Neumann majorant |y| <= z with z ~ (I - |E|)^-1 w, w >= |v|,
  // slack z *= 1 + 1e-9. For an entry l with w_l << z_l (here v = C (1e-5, ..., 1e-5): |v_3| = 8e-11 while z_3 = 3e-7)
  // that slack (~1e-9 w_l) is below the 1e-12 relative inflation of up(), so next_l > z_l by 2e-12 relative; the repair
  // raises only the failing entries by 1%, which breaks the other entries through |E|, and 4 attempts ping-pong without
  // success. Here rho(|E|) = 0.22: the majorant exists for every v, apply(C) succeeds, but apply(C 1e-5 1) fails (and
  // so does MeanValueEnclosure's geometry form for this box, see above).
  const ReproducerBox r;
  enclosure::PreconditionedInverseEnclosure act;
  ASSERT_TRUE(act.prepare(r.robot, r.in));
  const DMat& c = act.preconditioner();
  IMat cols(6, 6), v(6, 1);
  for (int l = 0; l < 6; ++l) {
    Interval sum(0.0);
    for (int j = 0; j < 6; ++j) {
      cols(l, j) = Interval(c(l, j));
      sum += Interval(c(l, j)) * Interval(1e-5);
    }
    v(l, 0) = sum;
  }
  enclosure::PreconditionedInverseEnclosure::AffineMatrix a;
  ASSERT_TRUE(act.apply(cols, a));
  EXPECT_TRUE(act.apply(v, a));
}

// =====================================================================================================================
// 7. Faces: bounds on the faces of the geometry box where f_k is certified monotone (BoxInput::useFaces)
// =====================================================================================================================

namespace {

/// The ref6 `paper` pose box of the given half-widths (m, rad) at the vertex (+x, +y, -z, +roll, -pitch, -yaw),
/// where the pitch error is largest (sampled, h = 1 mm).
IVec pitchCorner(double position, double angle) {
  const IVec paper = test::ref6File().workspaces.at("paper").initialBox();
  const bool upper[6] = {true, true, false, true, false, false};
  IVec box(6);
  for (int i = 0; i < 6; ++i) {
    const double w = 2.0 * (i < 3 ? position : angle);
    box[i] =
        upper[i] ? Interval(paper[i].upper() - w, paper[i].upper()) : Interval(paper[i].lower(), paper[i].lower() + w);
  }
  return box;
}

}  // namespace

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

TEST(UncertaintyEnclosure, FaceBoundsHoldForEveryGeometryAndReachTheWorstVertex) {
  // With useFaces, the components certified monotone in some parameters are bounded on their faces, in turn on the
  // smaller faces these certify (here in one box, and inherited by a sub-box). The bounds must still cover every
  // admissible geometry (worst vertices by vertex search, random vertices and interior points; double and MPFR), and
  // at the worst corner pose they must be the error at the worst vertex itself, where the plain bound is 0.5-1.3%
  // above.
  const Uncertain u(withUncertainty(0.001));
  const model::GoughPlatform robot(u.geometry);
  const domain::Workspace& ws = test::ref6File().workspaces.at("paper");
  const auto method = enclosure::makeEnclosure("second_order");
  std::mt19937_64 rng(710);
  int checked = 0, atVertex = 0, tighter = 0;
  const std::vector<IVec> boxes = {cornerBox(0.0), pitchCorner(0.0, 0.0), cornerBox(1.0 / 512.0),
                                   pitchCorner(0.0005, 0.001), cornerBox(1.0 / 64.0)};
  for (const IVec& box : boxes) {
    enclosure::BoxInput in;
    ws.poseView(box, true, in);
    enclosure::ErrorBounds plain, faced, child;
    method->enclose(robot, in, plain);
    ASSERT_TRUE(plain.bounded());
    in.useFaces = true;
    in.targets = plain.upper * 0.9;  // never good enough: every refinement runs
    method->enclose(robot, in, faced);
    ASSERT_TRUE(faced.bounded());
    // A sub-box (the half at the upper end of x) with the faces certified on the box.
    IVec sub = box;
    sub[0] = Interval(box[0].mid(), box[0].upper());
    enclosure::BoxInput subIn;
    ws.poseView(sub, true, subIn);
    subIn.useFaces = true;
    subIn.faces = faced.faces;
    subIn.knownSigns = faced.signs;
    method->enclose(robot, subIn, child);
    ASSERT_TRUE(child.bounded());
    const bool thin = box[0].isPoint();
    for (int s = 0; s < 3; ++s) {
      const DVec q = s == 0 ? randomVertexOf(box, rng) : test::randomPoint(box, rng);
      const DVec qs = s == 0 ? randomVertexOf(sub, rng) : test::randomPoint(sub, rng);
      const Eigen::MatrixXd grad = u.gradient(u.nominal, q), gradSub = u.gradient(u.nominal, qs);
      for (int k = 0; k < 6; ++k) {
        const Geometry worst = u.vertexSearch(q, k, 1.0, u.vertexBySigns(grad, k, 1.0));
        const Geometry worstSub = u.vertexSearch(qs, k, 1.0, u.vertexBySigns(gradSub, k, 1.0));
        EXPECT_TRUE(mpLessEqual(mpfrWorstError(u.at(worst), q)[k], faced.upper[k])) << k;
        EXPECT_TRUE(mpLessEqual(mpfrWorstError(u.at(worstSub), qs)[k], child.upper[k])) << k;
        for (int r = 0; r < 4; ++r) {
          const Geometry g = r % 2 ? u.randomVertex(rng) : u.randomInterior(rng);
          EXPECT_LE(u.error(g, q)[k], faced.upper[k] * (1 + 1e-12)) << k;
          EXPECT_LE(u.error(g, qs)[k], child.upper[k] * (1 + 1e-12)) << k;
        }
        ++checked;
        if (thin && s == 0) atVertex += faced.upper[k] <= u.error(worst, q)[k] * (1 + 1e-4) ? 1 : 0;
      }
    }
    if (thin) {
      for (int k = 0; k < 6; ++k) {
        EXPECT_LT(faced.upper[k], plain.upper[k]) << k;
        tighter += faced.upper[k] < plain.upper[k] * (1 - 2e-3) ? 1 : 0;
      }
    }
  }
  EXPECT_EQ(checked, 5 * 3 * 6);
  EXPECT_GE(atVertex, 10) << "of 12 (component, thin corner) pairs";
  // (The plain bound is 0.5-1.3% above the worst vertex there, with the fixed point of the B refinement.)
  EXPECT_GE(tighter, 10) << "of 12 (component, thin corner) pairs tighter than the plain bound by 0.2%";
}

TEST(UncertaintyVerifier, FacesCertifyMarginsBelowTheFirstOrderRemainder) {
  // h = 1 mm on a small box at the pitch corner, thresholds 0.2% above the sampled maximum of pitch (the others
  // out of reach): the plain geometry-aware bound stays ~0.4% above the maximum there whatever the pose box (its
  // second-order geometry remainder); stalled paths switch to the faces, whose bounds reach the worst vertex: SAFE.
  // 0.5% below the sampled maximum it must not be SAFE (the sampled maximum is attained at an admissible geometry).
  // Both geometry forms (the decomposed default switches stalled paths to the combined form for the faces). Measured
  // (+0.2%): see the info line; (+0.5%): 31 boxes each (255 with 6 stall levels instead of the default 3); with a 10%
  // progress step in the stall test the decomposed default's paths reach the faces only at the precision limit
  // (UNDECIDED after 200 001 boxes) and the combined form needs 2 439.
  const Uncertain u(withUncertainty(0.001));
  const model::GoughPlatform robot(u.geometry);
  const IVec box = pitchCorner(0.0001, 0.00015);
  const domain::Workspace ws = domain::Workspace::fromRanges(test::toRanges(box));
  const Sampled s = sample(u, box, 50, 711);
  for (const bool decomposed : {true, false}) {
    SCOPED_TRACE(decomposed ? "decomposed" : "combined");
    verify::VerifierOptions o;
    o.threads = 2;
    o.max_boxes = 20000;
    o.tuning.decompose_geometry = decomposed;
    o.thresholds = DVec::Constant(6, 1.0);
    o.thresholds[4] = s.max[4] * 1.002;
    const auto safe = verify::Verifier::run(robot, ws, o);
    EXPECT_EQ(safe.verdict, Verdict::Safe) << safe.message;
    EXPECT_GT(safe.stats.face_switches, 0u);
    EXPECT_GT(safe.stats.face_boxes, 0u);
    std::cout << "[ info     ] " << (decomposed ? "decomposed" : "combined") << ", SAFE at +0.2%: " << safe.stats.boxes
              << " boxes, " << safe.stats.face_switches << " face switches\n";
    o.thresholds[4] = s.max[4] * 0.995;
    const auto below = verify::Verifier::run(robot, ws, o);
    EXPECT_NE(below.verdict, Verdict::Safe) << below.message;
  }
}

// The tool point's box is bounded at its vertices (RobotModel::toolPointCoordinate, MeanValueEnclosure): the
// rotation components once (they do not depend on the tool point), the translation components at each of the 8
// vertices (they are convex in it), each time with the tool point exact and the anchors still uncertain. Checked: the
// bounds are those of the exact-tool models at the vertices, bit for bit; they hold at sampled poses and geometries,
// interior tool points included (MPFR on some); lower bounds and certified signs too.
TEST(UncertaintyEnclosure, ToolPointBoxIsBoundedAtItsVertices) {
  model::GoughGeometry g = withUncertainty(0.0005);
  g.tool_point = Eigen::Vector3d(0.0, 0.01, 0.05);
  g.tool_point_halfwidth = Eigen::Vector3d(0.005, 0.004, 0.003);
  const Uncertain u(g);
  ASSERT_EQ(u.count(), 39);
  const model::GoughPlatform robot(u.geometry);
  for (int p = 0; p < 39; ++p) EXPECT_EQ(robot.toolPointCoordinate(p), p < 36 ? -1 : p - 36);
  const io::RobotFile rf = test::ref6File();
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const auto method = enclosure::makeEnclosure("second_order");
  std::mt19937_64 rng(3131);
  int checked = 0, mpfr = 0, signs = 0, lowers = 0;
  for (int trial = 0; trial < 12; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const IVec box = randomSubBox(ws.initialBox(), std::pow(0.5, 4 + trial % 4), rng);  // 1/16 .. 1/128
    enclosure::BoxInput in;
    ws.poseView(box, true, in);
    in.decomposeGeometry = trial % 2 == 0;
    enclosure::ErrorBounds b;
    method->enclose(robot, in, b);
    ASSERT_TRUE(b.bounded());
    DVec worst = DVec::Constant(6, -1.0);
    for (int v = 0; v < 8; ++v) {
      GVec values = GVec::Constant(39, std::numeric_limits<double>::quiet_NaN());
      for (int a = 0; a < 3; ++a) {
        const Interval r = robot.geometryParameterRange(36 + a);
        values[36 + a] = ((v >> a) & 1) ? r.upper() : r.lower();
      }
      enclosure::ErrorBounds at;
      method->enclose(*robot.fixGeometryParameters(values), in, at);
      for (int k = 0; k < 3; ++k) worst[k] = std::max(worst[k], at.upper[k]);
      if (v == 0) {
        for (int k = 3; k < 6; ++k) EXPECT_EQ(b.upper[k], at.upper[k]) << "rotation k=" << k;
      }
    }
    for (int k = 0; k < 3; ++k) EXPECT_EQ(b.upper[k], worst[k]) << "translation k=" << k;
    for (int k = 0; k < 6; ++k) lowers += b.lower[k] > 0.0;
    for (int s = 0; s < 8; ++s) {
      const DVec q = s % 2 ? randomVertexOf(box, rng) : test::randomPoint(box, rng);
      for (int c = 0; c < 6; ++c) {
        Geometry geo = c % 2 ? u.randomVertex(rng) : u.randomInterior(rng);
        if (c == 4) {  // anchors at a vertex, the tool point inside its box
          const Geometry inside = u.randomInterior(rng);
          for (int p = 36; p < 39; ++p) geo[p] = inside[p];
        }
        const DVec f = u.error(geo, q);
        for (int k = 0; k < 6; ++k) {
          EXPECT_LE(f[k], b.upper[k] * (1 + 1e-12)) << "k=" << k << " sample " << s << "/" << c;
          EXPECT_GE(f[k], b.lower[k] * (1 - 1e-12)) << "k=" << k << " sample " << s << "/" << c;
        }
        const DMat jac = model::GoughPlatform(u.at(geo)).jacobian(q);
        for (int bit = 0; bit < 36; ++bit) {
          const double sign = b.signs.sign(bit);
          if (sign == 0.0) continue;
          EXPECT_GT(sign * jac(bit / 6, bit % 6), 0.0) << "J(" << bit / 6 << "," << bit % 6 << ")";
          ++signs;
        }
        ++checked;
        if (s == 0 && c < 3) {
          const auto exact = mpfrWorstError(u.at(geo), q);
          for (int k = 0; k < 6; ++k) {
            EXPECT_TRUE(mpLessEqual(exact[k], b.upper[k])) << "k=" << k;
            EXPECT_TRUE(mpGreaterEqual(exact[k], b.lower[k])) << "k=" << k;
          }
          ++mpfr;
        }
      }
    }
  }
  EXPECT_EQ(checked, 12 * 48);
  EXPECT_EQ(mpfr, 36);
  EXPECT_GT(signs, 10 * checked);  // most entries of J keep their sign on these boxes
  EXPECT_GT(lowers, 36);           // (the translation components' lower bounds lose 2 |c - c_v| (f_a + f_b))
}

// The tool point's box at +-5 mm on a 2 cm box: max-error to 2% converges in a few boxes (with the tool point as a
// first-order parameter: not within 57 000 boxes and 10 s, every component's bracket 2-5% wide), and the bracket
// holds against the exact-tool robots at the tool vertices (3^6 poses each) and at the argmax geometries.
TEST(UncertaintyVerifier, ToolPointUncertaintyConvergesAtItsVertices) {
  model::GoughGeometry g = test::ref6File().geometry;
  g.tool_point_halfwidth = Eigen::Vector3d::Constant(0.005);
  const Uncertain u(g);
  ASSERT_EQ(u.count(), 3);
  const model::GoughPlatform robot(u.geometry);
  const double ranges[12] = {-0.01, 0.01, -0.01, 0.01, 0.47, 0.48, -0.01, 0.01, -0.01, 0.01, -0.01, 0.01};
  IVec box(6);
  for (int i = 0; i < 6; ++i) box[i] = Interval(ranges[2 * i], ranges[2 * i + 1]);
  const domain::Workspace ws = domain::Workspace::fromRanges(test::toRanges(box));
  verify::VerifierOptions o;
  o.threads = 2;
  o.mode = verify::Mode::MaxError;
  o.alpha = 0.02;
  o.max_boxes = 5000;
  const auto r = verify::Verifier::run(robot, ws, o);
  EXPECT_TRUE(r.converged) << r.message;
  EXPECT_LE(r.stats.boxes, 16u);
  DVec sampled = DVec::Zero(6);
  for (int v = 0; v < 8; ++v) {
    Geometry tool(3);
    for (int a = 0; a < 3; ++a) tool[a] = ((v >> a) & 1) ? u.hi[a] : u.lo[a];
    const model::GoughPlatform at(u.at(tool));
    for (int idx = 0; idx < 729; ++idx) {
      DVec q(6);
      for (int i = 0, rest = idx; i < 6; ++i, rest /= 3) q[i] = box[i].lower() + 0.5 * (rest % 3) * box[i].width();
      sampled = sampled.cwiseMax(at.worstErrorAt(q));
    }
  }
  ASSERT_EQ(r.max_upper.size(), 6);
  for (int k = 0; k < 6; ++k) {
    SCOPED_TRACE("k=" + std::to_string(k));
    EXPECT_GE(r.max_upper[k], sampled[k]);
    // (An empty argmax geometry: the lower bound holds for every geometry, the nominal one and the vertices too.)
    std::vector<Geometry> geometries = {r.max_argmax_geometry[k]};
    if (geometries[0].empty()) geometries = {u.nominal, u.lo, u.hi};
    for (const Geometry& geo : geometries) EXPECT_GE(u.error(geo, r.max_argmax[k])[k], r.max_lower[k] * (1 - 1e-12));
  }
}

TEST(UncertaintyVerify, SingularWorkspaceThroughTheNominalGeometry) {
  // paper_40deg at +-1 mm: det J^-1 changes sign over the workspace for the nominal geometry (not certifiably for
  // every admissible one at the corner where it is positive), which is enough for the maximum over poses and
  // geometries to be unbounded. The signs are checked in MPFR with the nominal geometry.
  const model::GoughPlatform robot(withUncertainty(0.001));
  const model::GoughGeometry nominal = test::ref6File().geometry;
  const domain::Workspace& ws = test::ref6File().workspaces.at("paper_40deg");
  verify::VerifierOptions o;
  o.threads = 2;
  o.mode = verify::Mode::MaxError;
  o.time_limit_s = 20.0;
  const auto r = verify::Verifier::run(robot, ws, o);
  ASSERT_TRUE(r.singular) << r.message;
  EXPECT_FALSE(r.converged);
  EXPECT_LT(r.stats.boxes, 1000u);
  std::vector<double> gc, gh;
  centresAndHalfWidths(robot, gc, gh);
  EXPECT_EQ(r.singular_geometry, gc);
  const int a = test::mpDeterminantSign(test::mpInverseJacobian(nominal, r.singular_from));
  const int b = test::mpDeterminantSign(test::mpInverseJacobian(nominal, r.singular_to));
  EXPECT_NE(a, 0);
  EXPECT_EQ(a, -b);
  for (int k = 0; k < 6; ++k) EXPECT_EQ(r.max_upper[k], std::numeric_limits<double>::infinity()) << k;

  // Verify mode: not UNSAFE (not shown for every geometry), but SAFE is ruled out at once by an uncertainty-sensitive
  // pose next to the nominal geometry's singular pose, whose error exceeds thresholds of 1 km (checked in MPFR).
  o.mode = verify::Mode::Verify;
  o.thresholds = DVec::Constant(6, 1e3);
  const auto v = verify::Verifier::run(robot, ws, o);
  ASSERT_EQ(v.verdict, verify::Verdict::Undecided) << v.message;
  EXPECT_EQ(v.reason, verify::UndecidedReason::UncertaintySensitive) << v.message;
  EXPECT_LT(v.stats.boxes, 1000u);
  ASSERT_FALSE(v.sensitive.empty());
  const verify::SensitivePose& s = v.sensitive.front();
  EXPECT_EQ(s.failing_geometry, gc);
  ASSERT_GE(s.component, 0);
  EXPECT_GT(s.failing_lower, 1e3);
  for (int i = 0; i < 6; ++i) EXPECT_TRUE(s.region[i].contains(s.point[i])) << i;
  EXPECT_TRUE(mpGreaterEqual(mpfrWorstError(nominal, s.point)[s.component], s.failing_lower));
}
