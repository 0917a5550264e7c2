// KinematicModel<K>: the enclosures derived from a templated J^-1, checked against the hand-written Gough platform,
// against central differences (of the joint coordinates, of J^-1, in the geometry), against sampled values on random
// boxes, and through the verifier against a plain double sampler (delta3, generic gough).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <iostream>
#include <random>

#include "KinematicModelChecks.hpp"
#include "TestRobots.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/PoseBox.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/core/model/KinematicModel.hpp"
#include "pkm_accuracy/core/model/ModelRegistry.hpp"
#include "pkm_accuracy/core/model/robots/Delta3Kinematics.hpp"
#include "pkm_accuracy/core/model/robots/GoughKinematics.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"
#include "pkm_accuracy/io/ModelFile.hpp"

using namespace pkm_accuracy;

namespace {

std::shared_ptr<const model::RobotModel> delta() {
  static const io::ModelFile file = io::loadModelFile(test::configPath("delta3.yaml"));
  return file.model;
}

const domain::Domain& deltaWorkspace() {
  static const io::ModelFile file = io::loadModelFile(test::configPath("delta3.yaml"));
  return *file.workspaces.at("reference");
}

IVec randomBox(const IVec& within, double fraction, std::mt19937_64& rng) {
  IVec b(within.size());
  for (int i = 0; i < within.size(); ++i) {
    const double w = within[i].upper() - within[i].lower();
    std::uniform_real_distribution<double> u(within[i].lower(), within[i].upper() - fraction * w);
    const double lo = u(rng);
    b[i] = Interval(lo, lo + fraction * w);
  }
  return b;
}

/// Central differences of the joint coordinates: an estimate of J^-1 independent of the templated J^-1.
DMat differencedJinv(const model::RobotModel& m, const DVec& pose, double h) {
  DMat out(m.dof(), m.dof());
  for (int a = 0; a < m.dof(); ++a) {
    DVec p = pose, q = pose;
    p[a] += h;
    q[a] -= h;
    out.col(a) = (m.legLengths(p) - m.legLengths(q)) / (2.0 * h);
  }
  return out;
}

bool contains(const Interval& enclosure, double v, double slack) {
  return enclosure.lower() - slack <= v && v <= enclosure.upper() + slack;
}

}  // namespace

TEST(KinematicModel, GenericGoughAgreesWithTheHandWrittenPlatform) {
  const model::GoughGeometry g = test::ref6File().geometry;
  const model::GoughPlatform hand(g);
  const auto generic = model::makeGenericGough(g);
  std::mt19937_64 rng(7);
  const IVec paper = test::ref6File().workspaces.at("paper").initialBox();
  for (int s = 0; s < 200; ++s) {
    const DVec q = test::randomPoint(paper, rng);
    EXPECT_LT((hand.inverseJacobian(q) - generic->inverseJacobian(q)).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_LT((hand.legLengths(q) - generic->legLengths(q)).cwiseAbs().maxCoeff(), 1e-14);
    const IVec box = randomBox(paper, 0.05, rng);
    const IMat eg = generic->inverseJacobian(box), eh = hand.inverseJacobian(box);
    const DVec inside = test::randomPoint(box, rng);
    const DMat v = hand.inverseJacobian(inside);
    for (int i = 0; i < 6; ++i) {
      for (int j = 0; j < 6; ++j) {
        EXPECT_TRUE(eg(i, j).contains(v(i, j))) << "box " << s << " entry " << i << "," << j;
        EXPECT_FALSE(intersect(eg(i, j), eh(i, j)).isEmpty());
      }
    }
  }
}

TEST(KinematicModel, JinvIsTheDerivativeOfTheJointCoordinates) {
  std::mt19937_64 rng(11);
  const auto d = delta();
  for (int s = 0; s < 200; ++s) {
    const DVec q = test::randomPoint(deltaWorkspace().initialBox(), rng);
    const DMat fd = differencedJinv(*d, q, 1e-6);
    EXPECT_LT((fd - d->inverseJacobian(q)).cwiseAbs().maxCoeff(), 1e-6 * (1.0 + fd.cwiseAbs().maxCoeff()));
  }
}

TEST(KinematicModel, Delta3InverseKinematicsClosesEveryLeg) {
  // Independent of the model's formulas: the elbow from the crank angle by Eigen, the forearm's length.
  const auto d = delta();
  std::mt19937_64 rng(3);
  for (int s = 0; s < 100; ++s) {
    const DVec q = test::randomPoint(deltaWorkspace().initialBox(), rng);
    const DVec theta = d->legLengths(q);
    for (int i = 0; i < 3; ++i) {
      const double phi = 2.0 * M_PI * i / 3.0;
      const Eigen::Vector3d u(std::cos(phi), std::sin(phi), 0.0), z = Eigen::Vector3d::UnitZ();
      const Eigen::Vector3d elbow = 0.2 * u + 0.2 * (std::cos(theta[i]) * u - std::sin(theta[i]) * z);
      const Eigen::Vector3d joint = Eigen::Vector3d(q[0], q[1], q[2]) + 0.05 * u;
      EXPECT_NEAR((joint - elbow).norm(), 0.5, 1e-12);
      EXPECT_GT((elbow - 0.2 * u).dot(u), 0.0) << "elbow-out branch";
    }
  }
}

TEST(KinematicModel, UnreachablePosesGiveUnboundedEnclosures) {
  const auto d = delta();
  DVec far(3);
  far << 0.0, 0.0, -2.0;  // beyond the arms' reach
  EXPECT_TRUE(std::isnan(d->legLengths(far)[0]));
  IVec box(3);
  box << Interval(-0.01, 0.01), Interval(-0.01, 0.01), Interval(-1.0, -0.4);  // partly unreachable
  const IMat e = d->inverseJacobian(box);
  EXPECT_FALSE(e(0, 0).isBounded());
}

TEST(KinematicModel, EnclosuresContainSampledValuesOnRandomBoxes) {
  const auto d = delta();
  std::mt19937_64 rng(5);
  const IVec& ws = deltaWorkspace().initialBox();
  for (int s = 0; s < 300; ++s) {
    const IVec box = randomBox(ws, s % 3 == 0 ? 0.3 : 0.05, rng);
    const IMat e = d->inverseJacobian(box);
    MatrixHessian h;
    ASSERT_TRUE(d->inverseJacobianHessianAtGeometryCentre(box, h, true));
    for (int k = 0; k < 20; ++k) {
      const DVec q = test::randomPoint(box, rng);
      const DMat v = d->inverseJacobian(q);
      const double step = 1e-5;
      for (int a = 0; a < 3; ++a) {
        DVec p = q, m = q;
        p[a] += step;
        m[a] -= step;
        const DMat first = (d->inverseJacobian(p) - d->inverseJacobian(m)) / (2.0 * step);
        for (int b = a; b < 3; ++b) {
          DVec pb = p, mb = m, pm = p, mp = m;
          pb[b] += step;
          mb[b] -= step;
          pm[b] -= step;
          mp[b] += step;
          const DMat second =
              (d->inverseJacobian(pb) - d->inverseJacobian(pm) - d->inverseJacobian(mp) + d->inverseJacobian(mb)) /
              (4.0 * step * step);
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
              EXPECT_TRUE(
                  contains(h.d[MatrixHessian::index(a, b)](i, j), second(i, j), 1e-3 * (1.0 + std::abs(second(i, j)))));
        }
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            EXPECT_TRUE(contains(h.first[a](i, j), first(i, j), 1e-6 * (1.0 + std::abs(first(i, j)))));
      }
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_TRUE(e(i, j).contains(v(i, j))) << "box " << s;
    }
  }
}

TEST(KinematicModel, GeometryDerivativesContainDifferencesInTheGeometry) {
  const model::ModelType* type = model::ModelRegistry::global().find("delta3");
  ASSERT_NE(type, nullptr);
  io::ModelFile file = io::loadModelFile(test::configPath("delta3.yaml"));
  model::RobotDescription desc = file.description;
  desc.setUncertainty("forearm_length", 1e-3);
  desc.setUncertainty("motor_angle[1]", 1e-3);
  const auto m = type->make(desc);
  ASSERT_EQ(m->geometryParameterCount(), 4);
  std::mt19937_64 rng(9);
  for (int s = 0; s < 50; ++s) {
    const IVec box = randomBox(deltaWorkspace().initialBox(), 0.05, rng);
    GeometryDerivatives gd;
    ASSERT_TRUE(m->geometryDerivatives(box, gd));
    EXPECT_EQ(gd.count, 4);  // each of these values moves one row
    for (int e = 0; e < gd.count; ++e) {
      const GeometryRowDerivative& entry = gd.entries[e];
      const DVec q = test::randomPoint(box, rng);
      GVec plus = GVec::Constant(4, std::nan("")), minus = plus;
      const double c = m->geometryParameterCentre(entry.parameter), h = 1e-6;
      plus[entry.parameter] = c + h;
      minus[entry.parameter] = c - h;
      const DMat diff =
          (m->fixGeometryParameters(plus)->inverseJacobian(q) - m->fixGeometryParameters(minus)->inverseJacobian(q)) /
          (2.0 * h);
      for (int l = 0; l < 3; ++l) {
        const Interval d(entry.d[l].mid() - entry.d[l].rad(), entry.d[l].mid() + entry.d[l].rad());
        EXPECT_TRUE(contains(d, diff(entry.row, l), 1e-5 * (1.0 + std::abs(diff(entry.row, l)))));
      }
      for (int r = 0; r < 3; ++r) {
        if (r != entry.row) {
          EXPECT_LT(diff.row(r).cwiseAbs().maxCoeff(), 1e-9) << "row not listed but moved";
        }
      }
    }
  }
}

TEST(KinematicModel, GeometryDerivativesAsAffineFormsInThePoseContainDifferences) {
  // The generic path's geometry derivatives as first-order affine forms in the pose (what the decomposed geometry
  // form and the combined form's correlated products use): at random poses of random boxes and random admissible
  // geometries, central differences in each geometry value lie in centre + slope . tau +- radius.
  std::mt19937_64 rng(31);
  model::GoughGeometry g = test::ref6File().geometry;
  g.setUniformAnchorUncertainty(5e-4);
  const auto generic = model::makeGenericGough(g);
  const auto* gough = dynamic_cast<const model::KinematicModel<model::GoughKinematics>*>(generic.get());
  ASSERT_NE(gough, nullptr);
  const IVec paper = test::ref6File().workspaces.at("paper").initialBox();
  for (int s = 0; s < 8; ++s) test::checkGeometryDerivatives(*gough, randomBox(paper, s % 2 ? 0.02 : 0.1, rng), 4, rng);

  io::ModelFile file = io::loadModelFile(test::configPath("delta3.yaml"));
  file.description.setUncertainty("forearm_length", 1e-3);
  file.description.setUncertainty("motor_angle[1]", 1e-3);
  const auto m = model::ModelRegistry::global().find("delta3")->make(file.description);
  const auto* delta3 = dynamic_cast<const model::KinematicModel<model::Delta3Kinematics>*>(m.get());
  ASSERT_NE(delta3, nullptr);
  for (int s = 0; s < 20; ++s)
    test::checkGeometryDerivatives(*delta3, randomBox(deltaWorkspace().initialBox(), 0.05, rng), 5, rng);
}

TEST(KinematicModel, UncertainGenericGoughBracketsSampledMaximaAsTheVerifierComposesIt) {
  // The generic path with geometry parameters through the default pipeline (second_order, decomposed geometry form
  // on the affine geometry derivatives, faces, geometry bisection): on 3/4 of `paper` (per range) with +-0.5 mm on
  // every anchor coordinate, the max-error bracket contains the maxima sampled over poses and vertex geometries,
  // overlaps the hand-written platform's bracket, and 5% above its upper bounds the verdict is SAFE.
  model::GoughGeometry g = test::ref6File().geometry;
  g.setUniformAnchorUncertainty(5e-4);
  const auto generic = model::makeGenericGough(g);
  const model::GoughPlatform hand(g);
  const IVec paper = test::ref6File().workspaces.at("paper").initialBox();
  IVec part(6);
  for (int i = 0; i < 6; ++i) {
    const double c = paper[i].mid(), r = paper[i].rad() / 2.0;
    part[i] = Interval(c - r, c + 2.0 * r);
  }
  const domain::PoseBox box({"x", "y", "z", "roll", "pitch", "yaw"}, part);
  std::mt19937_64 rng(41);
  DVec sampled = DVec::Zero(6);
  const int params = generic->geometryParameterCount();
  ASSERT_EQ(params, 36);
  for (int s = 0; s < 400; ++s) {
    GVec values(params);
    for (int p = 0; p < params; ++p) {
      const Interval r = generic->geometryParameterRange(p);
      values[p] = (rng() & 1u) ? r.lower() : r.upper();
    }
    const auto fixed = generic->fixGeometryParameters(values);
    for (int k = 0; k < 5; ++k) sampled = sampled.cwiseMax(fixed->worstErrorAt(test::randomPoint(part, rng)));
  }
  verify::VerifierOptions o;
  o.mode = verify::Mode::MaxError;
  o.alpha = 0.02;
  o.threads = 2;
  o.time_limit_s = 120.0;
  const verify::VerifierResult r = verify::Verifier::run(*generic, box, o);
  const verify::VerifierResult h = verify::Verifier::run(hand, box, o);
  ASSERT_TRUE(r.converged);
  ASSERT_TRUE(h.converged);
  for (int k = 0; k < 6; ++k) {
    EXPECT_GE(r.max_upper[k], sampled[k] * (1.0 - 1e-12)) << k;
    EXPECT_LE(r.max_lower[k], r.max_upper[k]) << k;
    EXPECT_LE(r.max_lower[k], h.max_upper[k]) << k;
    EXPECT_LE(h.max_lower[k], r.max_upper[k]) << k;
  }
  verify::VerifierOptions v;
  v.thresholds = r.max_upper * 1.05;
  v.threads = 2;
  v.time_limit_s = 120.0;
  EXPECT_EQ(verify::Verifier::run(*generic, box, v).verdict, verify::Verdict::Safe);
  std::cout << "[ figures  ] generic / hand-written boxes: max-error " << r.stats.boxes << " / " << h.stats.boxes
            << "\n";
}

TEST(KinematicModel, Delta3MaxErrorBracketsTheSampledMaximaAndVerdictsFollow) {
  const auto d = delta();
  const domain::Domain& ws = deltaWorkspace();
  std::mt19937_64 rng(1);
  DVec sampled = DVec::Zero(3);
  for (int s = 0; s < 20000; ++s) sampled = sampled.cwiseMax(d->worstErrorAt(test::randomPoint(ws.initialBox(), rng)));
  for (int c = 0; c < 8; ++c) {
    DVec q(3);
    for (int i = 0; i < 3; ++i) q[i] = (c >> i) & 1 ? ws.initialBox()[i].upper() : ws.initialBox()[i].lower();
    sampled = sampled.cwiseMax(d->worstErrorAt(q));
  }
  verify::VerifierOptions o;
  o.mode = verify::Mode::MaxError;
  o.alpha = 0.01;
  o.threads = 2;
  const auto t0 = std::chrono::steady_clock::now();
  const verify::VerifierResult r = verify::Verifier::run(*d, ws, o);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(r.converged);
  for (int k = 0; k < 3; ++k) {
    EXPECT_GE(r.max_upper[k], sampled[k]);              // no sampled pose exceeds the certified maximum
    EXPECT_LE(r.max_upper[k], 1.011 * r.max_lower[k]);  // bracketed to 1 %
    EXPECT_GE(r.max_lower[k], 0.99 * sampled[k]);       // and the lower bound is as good as the sampler
    // The lower bound is attained at the reported pose (double evaluation, up to round-off).
    EXPECT_GE(d->worstErrorAt(domain::centreOf(r.max_argmax_pose[k]))[k], r.max_lower[k] * (1.0 - 1e-9));
  }
  std::printf("delta3 reference: sampled maxima %.6g %.6g %.6g, max-error 1%% in %.3f s, %zu boxes\n", sampled[0],
              sampled[1], sampled[2], seconds, r.stats.boxes);
  verify::VerifierOptions v;
  v.threads = 2;
  v.thresholds = 1.05 * r.max_upper;
  EXPECT_EQ(verify::Verifier::run(*d, ws, v).verdict, verify::Verdict::Safe);
  v.thresholds = 0.95 * sampled;
  EXPECT_EQ(verify::Verifier::run(*d, ws, v).verdict, verify::Verdict::Unsafe);
}

TEST(KinematicModel, PreconditionedHessianBoundsHoldAtSampledPoints) {
  // |C H_il(t0 + s dt)| <= out + s linear + s^2 quadratic (and <= the unsplit bound) at sampled points of random
  // boxes (test::checkPreconditionedHessian), on delta3 and on the generic Gough platform.
  std::mt19937_64 rng(21);
  for (int s = 0; s < 40; ++s) {
    test::checkPreconditionedHessian(*delta(), randomBox(deltaWorkspace().initialBox(), s % 2 ? 0.05 : 0.2, rng), 10,
                                     rng);
  }
  const model::GoughGeometry g = test::ref6File().geometry;
  const auto generic = model::makeGenericGough(g);
  const IVec paper = test::ref6File().workspaces.at("paper").initialBox();
  for (int s = 0; s < 20; ++s)
    test::checkPreconditionedHessian(*generic, randomBox(paper, s % 2 ? 0.05 : 0.2, rng), 10, rng);
}

TEST(KinematicModel, GenericGoughHessianBoundsAreCloseToTheHandWrittenOnes) {
  // Both are rigorous; the generic one (nested duals of affine forms) should not be much looser than the analytic
  // one (the benchmark's box counts depend on it).
  const model::GoughGeometry g = test::ref6File().geometry;
  const model::GoughPlatform hand(g);
  const auto generic = model::makeGenericGough(g);
  std::mt19937_64 rng(4);
  const IVec paper = test::ref6File().workspaces.at("paper").initialBox();
  double worst = 0.0;
  for (int s = 0; s < 30; ++s) {
    const IVec box = randomBox(paper, 0.05, rng);
    const DMat c = hand.jacobian(domain::centreOf(box));
    std::array<DMat, MatrixHessian::kPairs> oh, og;
    ASSERT_TRUE(hand.preconditionedHessianMagnitude(box, c, oh));
    ASSERT_TRUE(generic->preconditionedHessianMagnitude(box, c, og));
    for (int p = 0; p < MatrixHessian::kPairs; ++p) worst = std::max(worst, og[p].sum() / oh[p].sum());
  }
  EXPECT_LT(worst, 1.5);
}
