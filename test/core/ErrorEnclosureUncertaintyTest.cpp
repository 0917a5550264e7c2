// The second_order enclosure and errorAtPose under bounded anchor and tool-point uncertainty (docs/uncertainty.md):
// soundness over pose boxes x geometries (double and MPFR), the combined and decomposed geometry forms, the row mask,
// the monotone face bounds, the centre estimate, the tool point's box; regression tests for problems once found.
#include <gtest/gtest.h>
#include <mpfr.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "MpfrGough.hpp"
#include "TestRobots.hpp"
#include "UncertaintyFixtures.hpp"
#include "pkm_accuracy/core/domain/Workspace.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/enclosure/PreconditionedInverseEnclosure.hpp"
#include "pkm_accuracy/core/interval/AffineForm.hpp"

using namespace pkm_accuracy;
using namespace pkm_accuracy::test;               // the MPFR reference toolkit (MpfrGough.hpp)
using namespace pkm_accuracy::test::uncertainty;  // the uncertain robot (UncertaintyFixtures.hpp)

// =====================================================================================================================
// Soundness of the second_order enclosure and of errorAtPose under uncertainty
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

TEST(UncertaintyRegression, FallbackToIntervalCoefficientsLeavesNoZeroGeometryHints) {
  // A box of the centred 1/16 paper sub-box at h = 1 mm where PreconditionedInverseEnclosure::apply() accepts J = N C
  // but rejects 2 of the 64 sign columns (its Neumann verification), so encloseWithGeometry() returns false after
  // having set geometrySmear / geometrySensitivity to zero matrices of full size; the interval-coefficient path then
  // leaves them so. ErrorBounds documents them as empty outside the second-order geometry form; a zero 6 x 36 matrix
  // makes SplitPolicy::chooseGeometrySplit() see valid-looking all-zero scores (no geometry split ever chosen for such
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
