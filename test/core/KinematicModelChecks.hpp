// Checks shared by the tests of the built-in models written as templated kinematics (KinematicModel<K>): a plain
// double sampler of the maximal errors, and the containment checks of every enclosure KinematicModel derives (J^-1
// over boxes, its gradient, its Hessian and its preconditioned affine bounds, its geometry derivatives) against values
// and central differences computed in double.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "TestRobots.hpp"
#include "pkm_accuracy/core/domain/PoseBox.hpp"
#include "pkm_accuracy/core/model/KinematicModel.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"

namespace pkm_accuracy {
namespace test {

inline IVec thinBox(const DVec& q) {
  IVec b(q.size());
  for (int i = 0; i < q.size(); ++i) b[i] = Interval(q[i]);
  return b;
}

inline domain::PoseBox poseBox(const model::RobotModel& robot, const IVec& box) {
  std::vector<std::string> names;
  for (int k = 0; k < robot.dof(); ++k) names.push_back(robot.componentName(k));
  return domain::PoseBox(names, box);
}

/// A random point of the box whose coordinates are each at the lower end, the upper end or inside with equal odds
/// (so that faces, edges and corners, where the maxima of the errors usually lie, are sampled too).
inline DVec randomFacePoint(const IVec& box, std::mt19937_64& rng) {
  DVec q = randomPoint(box, rng);
  std::uniform_int_distribution<int> pick(0, 2);
  for (int i = 0; i < box.size(); ++i) {
    const int p = pick(rng);
    if (p == 0) q[i] = box[i].lower();
    if (p == 1) q[i] = box[i].upper();
  }
  return q;
}

/// The plain double sampler: the maximum of each component of RobotModel::worstErrorAt over random points, random
/// points of the faces and the corners of a box (a lower estimate of the true maxima).
inline DVec sampledMaxima(const model::RobotModel& robot, const IVec& box, int samples, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  DVec best = DVec::Zero(robot.dof());
  auto account = [&](const DVec& q) {
    const DVec f = robot.worstErrorAt(q);
    for (int k = 0; k < robot.dof(); ++k) best[k] = std::max(best[k], f[k]);
  };
  for (int s = 0; s < samples; ++s) account(s % 2 ? randomPoint(box, rng) : randomFacePoint(box, rng));
  for (int corner = 0; corner < (1 << box.size()); ++corner) {
    DVec q(box.size());
    for (int i = 0; i < box.size(); ++i) q[i] = (corner >> i) & 1 ? box[i].upper() : box[i].lower();
    account(q);
  }
  return best;
}

/// A random sub-box of `box` around a random point, each half-width `scale` times the box's (0: a point), clipped.
inline IVec randomSubBox(const IVec& box, double scale, std::mt19937_64& rng) {
  const DVec c = randomPoint(box, rng);
  IVec b(box.size());
  for (int i = 0; i < box.size(); ++i) {
    const double h = scale * 0.5 * (box[i].upper() - box[i].lower());
    b[i] = Interval(c[i] - h, c[i] + h);
  }
  return b;
}

inline bool allFinite(const DMat& m) { return m.allFinite(); }

/// `v` lies in `x` up to `slack` (absolute), and x has no NaN end.
inline ::testing::AssertionResult encloses(const Interval& x, double v, double slack) {
  if (x.isEmpty()) return ::testing::AssertionFailure() << "empty enclosure of " << v;
  if (x.lower() - slack <= v && v <= x.upper() + slack) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << v << " outside [" << x.lower() << ", " << x.upper() << "] (slack " << slack
                                       << ")";
}

/// J^-1 (double) at `q` with pose coordinate `a` moved by `h`.
inline DMat jinvAt(const model::RobotModel& robot, DVec q, int a, double h) {
  q[a] += h;
  return robot.inverseJacobian(q);
}

/// Interval J^-1 and the dual (value + gradient) enclosures over `box` contain J^-1 and its central differences at
/// random points of the box where J^-1 is finite. @return whether every enclosure over the box was bounded.
inline bool checkInverseJacobianEnclosures(const model::RobotModel& robot, const IVec& box, int samples,
                                           std::mt19937_64& rng) {
  const int n = robot.dof();
  const IMat mi = robot.inverseJacobian(box);
  const IMat mc = robot.inverseJacobianAtGeometryCentre(box);
  MatrixWithGradient mg;
  DualPose dp;
  for (int i = 0; i < kMaxDof; ++i) dp[i] = i < n ? DualI::variable(box[i], i) : DualI(Interval(0.0));
  robot.inverseJacobian(dp, mg);
  bool bounded = true;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      EXPECT_FALSE(mi(i, j).isEmpty());
      EXPECT_FALSE(mg.value(i, j).isEmpty());
      bounded = bounded && mi(i, j).isBounded() && mg.value(i, j).isBounded();
    }
  }
  for (int s = 0; s < samples; ++s) {
    const DVec q = s == 0 ? domain::centreOf(box) : randomPoint(box, rng);
    const DMat m = robot.inverseJacobian(q);
    if (!allFinite(m)) continue;
    const double h = 1e-7;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        const double slack = 1e-12 * (1.0 + std::abs(m(i, j)));
        EXPECT_TRUE(encloses(mi(i, j), m(i, j), slack)) << "J^-1(" << i << "," << j << ")";
        EXPECT_TRUE(encloses(mc(i, j), m(i, j), slack)) << "J^-1(" << i << "," << j << ") at the geometry centre";
        EXPECT_TRUE(encloses(mg.value(i, j), m(i, j), slack)) << "dual J^-1(" << i << "," << j << ")";
      }
    }
    for (int a = 0; a < n; ++a) {
      if (box[a].isPoint()) continue;
      const DMat d = (jinvAt(robot, q, a, h) - jinvAt(robot, q, a, -h)) / (2 * h);
      if (!allFinite(d)) continue;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          EXPECT_TRUE(encloses(mg.d[a](i, j), d(i, j), 1e-6 * (1.0 + std::abs(d(i, j)))))
              << "d J^-1(" << i << "," << j << ") / d pose " << a;
    }
  }
  return bounded;
}

/// inverseJacobianHessianAtGeometryCentre over `box` contains central differences of J^-1 (first and second
/// derivatives in the pose coordinates) at random points of the box. @return whether it gave bounded enclosures.
inline bool checkHessianEnclosures(const model::RobotModel& robot, const IVec& box, int samples, std::mt19937_64& rng) {
  const int n = robot.dof();
  MatrixHessian withSecond, firstOnly;
  const bool boundedSecond = robot.inverseJacobianHessianAtGeometryCentre(box, withSecond, true);
  const bool boundedFirst = robot.inverseJacobianHessianAtGeometryCentre(box, firstOnly, false);
  for (int s = 0; s < samples; ++s) {
    const DVec q = s == 0 ? domain::centreOf(box) : randomPoint(box, rng);
    if (!allFinite(robot.inverseJacobian(q))) continue;
    const double h1 = 1e-7, h2 = 2e-4;
    for (int a = 0; a < n; ++a) {
      const DMat d = (jinvAt(robot, q, a, h1) - jinvAt(robot, q, a, -h1)) / (2 * h1);
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          const double tol = 1e-6 * (1.0 + std::abs(d(i, j)));
          EXPECT_TRUE(encloses(withSecond.first[a](i, j), d(i, j), tol))
              << "second: d/d" << a << " (" << i << "," << j << ")";
          EXPECT_TRUE(encloses(firstOnly.first[a](i, j), d(i, j), tol))
              << "first: d/d" << a << " (" << i << "," << j << ")";
        }
      }
      for (int b = a; b < n; ++b) {
        // Central second differences with steps h and h / 2, Richardson-extrapolated (error O(h^4)).
        auto second = [&](double h) {
          auto at = [&](double sa, double sb) {
            DVec p = q;
            p[a] += sa * h;
            p[b] += sb * h;
            return robot.inverseJacobian(p);
          };
          return DMat((at(1, 1) - at(1, -1) - at(-1, 1) + at(-1, -1)) / (4 * h * h));
        };
        const DMat dd = (4.0 * second(0.5 * h2) - second(h2)) / 3.0;
        if (!allFinite(dd)) continue;
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j)
            EXPECT_TRUE(
                encloses(withSecond.d[MatrixHessian::index(a, b)](i, j), dd(i, j), 1e-5 * (1.0 + std::abs(dd(i, j)))))
                << "d2/d" << a << "d" << b << " (" << i << "," << j << ")";
      }
    }
  }
  return boundedSecond && boundedFirst;
}

/// preconditionedHessianMagnitude over `box` for a random C bounds |C H(t)| entry by entry at random points t = t0 +
/// s dt of the box (t0 its midpoint, dt within the half-widths): by `out` alone, and by out + s linear + s^2 quadratic
/// with the split. H(t) is the model's interval Hessian over the single point t (checked against central differences
/// by checkHessianEnclosures); its width goes to the slack.
inline void checkPreconditionedHessian(const model::RobotModel& robot, const IVec& box, int samples,
                                       std::mt19937_64& rng) {
  const int n = robot.dof();
  const DMat c = DMat::Random(n, n);
  std::array<DMat, MatrixHessian::kPairs> plain, out, linear, quadratic;
  ASSERT_TRUE(robot.preconditionedHessianMagnitude(box, c, plain));
  ASSERT_TRUE(robot.preconditionedHessianMagnitude(box, c, out, &linear, &quadratic));
  std::uniform_real_distribution<double> unit(0.0, 1.0), sym(-1.0, 1.0);
  for (int k = 0; k < samples; ++k) {
    const double s = unit(rng);
    IVec point(n);
    for (int i = 0; i < n; ++i)
      point[i] = Interval(box[i].mid() + s * sym(rng) * 0.5 * (box[i].upper() - box[i].lower()));
    MatrixHessian h;
    ASSERT_TRUE(robot.inverseJacobianHessianAtGeometryCentre(point, h, true));
    for (int a = 0; a < n; ++a) {
      for (int b = a; b < n; ++b) {
        const int p = MatrixHessian::index(a, b);
        DMat hm(n, n);
        double slack = 0.0;
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j) {
            hm(i, j) = h.d[p](i, j).mid();
            slack = std::max(slack, h.d[p](i, j).rad());
          }
        const DMat ch = (c * hm).cwiseAbs();
        const double tol = 1e-9 + 10.0 * slack * c.cwiseAbs().sum();
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j) {
            EXPECT_LE(ch(i, j), plain[p](i, j) + tol) << "d2/d" << a << "d" << b << " (" << i << "," << j << ")";
            EXPECT_LE(ch(i, j), out[p](i, j) + s * linear[p](i, j) + s * s * quadratic[p](i, j) + tol)
                << "d2/d" << a << "d" << b << " (" << i << "," << j << "), s = " << s;
          }
      }
    }
  }
}

/// geometryDerivatives over `box` contains central differences (in each uncertain geometry value, computed with the
/// kinematics in double) of J^-1 at random poses of the box and random admissible geometries, and has an entry for
/// every row a parameter moves (no entry: the differences must vanish); so do the entries' affine forms in the pose
/// (GeometryRowDerivative::affine; required unless `requireAffine` is false: near unreachable poses they may be
/// unbounded).
template <typename K>
void checkGeometryDerivatives(const model::KinematicModel<K>& robot, const IVec& box, int samples, std::mt19937_64& rng,
                              bool requireAffine = true) {
  constexpr int n = K::kDof;
  const model::RobotDescription& d = robot.description();
  GeometryDerivatives out;
  ASSERT_TRUE(robot.geometryDerivatives(box, out));
  const int params = robot.geometryParameterCount();
  ASSERT_GT(params, 0);
  std::vector<int> value(static_cast<std::size_t>(params));
  for (int p = 0; p < params; ++p) value[static_cast<std::size_t>(p)] = d.geometryIndex(robot.geometryParameterName(p));
  std::vector<std::vector<int>> entry(static_cast<std::size_t>(params), std::vector<int>(n, -1));
  for (int e = 0; e < out.count; ++e) {
    const GeometryRowDerivative& r = out.entries[static_cast<std::size_t>(e)];
    ASSERT_GE(r.parameter, 0);
    ASSERT_LT(r.parameter, params);
    ASSERT_GE(r.row, 0);
    ASSERT_LT(r.row, n);
    EXPECT_EQ(entry[static_cast<std::size_t>(r.parameter)][r.row], -1) << "two entries for one parameter and row";
    entry[static_cast<std::size_t>(r.parameter)][r.row] = e;
  }
  const K k = robot.kinematics();
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int affineChecked = 0;
  for (int s = 0; s < samples; ++s) {
    const DVec q = randomPoint(box, rng);
    double tau[kMaxDof];  // the pose's symbols in the affine forms (AffineForm::variable)
    for (int m = 0; m < n; ++m) {
      const interval::AffineForm<kMaxDof> x = interval::AffineForm<kMaxDof>::variable(box[m], m);
      tau[m] = (q[m] - x.centre()) / x.coefficient(m);
    }
    std::vector<double> g;
    for (const model::GeometryValue& v : d.geometry) g.push_back(v.nominal + v.lo + unit(rng) * (v.hi - v.lo));
    double jinv[n * n];
    k.inverseJacobian(q.data(), g.data(), jinv);
    bool finite = true;
    for (int i = 0; i < n * n; ++i) finite = finite && std::isfinite(jinv[i]);
    if (!finite) continue;
    // The interval J^-1 over the box and every admissible geometry contains this one.
    const IMat mi = robot.inverseJacobian(box);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) EXPECT_TRUE(encloses(mi(i, j), jinv[i * n + j], 1e-12)) << i << "," << j;
    for (int p = 0; p < params; ++p) {
      const std::size_t v = static_cast<std::size_t>(value[static_cast<std::size_t>(p)]);
      const double h = 1e-7 * std::max(1.0, std::abs(g[v]));
      std::vector<double> gp = g, gm = g;
      gp[v] += h;
      gm[v] -= h;
      double jp[n * n], jm[n * n];
      k.inverseJacobian(q.data(), gp.data(), jp);
      k.inverseJacobian(q.data(), gm.data(), jm);
      for (int r = 0; r < n; ++r) {
        const int e = entry[static_cast<std::size_t>(p)][r];
        for (int l = 0; l < n; ++l) {
          const double fd = (jp[r * n + l] - jm[r * n + l]) / (2 * h);
          if (e < 0) {
            EXPECT_LT(std::abs(fd), 1e-6) << d.geometry[v].name << " moves row " << r << " but has no entry for it";
            continue;
          }
          const GeometryRowDerivative& entryE = out.entries[static_cast<std::size_t>(e)];
          EXPECT_TRUE(encloses(entryE.d[static_cast<std::size_t>(l)].toInterval(), fd, 1e-6 * (1.0 + std::abs(fd))))
              << d.geometry[v].name << " row " << r << " column " << l;
          if (!entryE.affine) continue;
          // The affine form in the pose, at this pose's symbols: centre + sum_m slope_m tau_m +- radius.
          double lin = entryE.centre[l];
          for (int m = 0; m < n; ++m) lin += entryE.slope[l][m] * tau[m];
          EXPECT_LE(std::abs(fd - lin), entryE.radius[l] + 1e-6 * (1.0 + std::abs(fd)))
              << d.geometry[v].name << " row " << r << " column " << l << " (affine form)";
          ++affineChecked;
        }
      }
    }
  }
  if (requireAffine) {
    EXPECT_GT(affineChecked, 0) << "no affine geometry derivative was checked";
  }
}

/// The first point on the segment from `from` (where J^-1 is finite) along `dir` where J^-1 is not finite (the pose
/// leaves the reachable set), to within 1e-12 of the parameter t in [0, tmax] (J^-1 must be non-finite at tmax).
inline double reachLimit(const model::RobotModel& robot, const DVec& from, const DVec& dir, double tmax) {
  auto finite = [&](double t) { return allFinite(robot.inverseJacobian(DVec(from + t * dir))); };
  EXPECT_TRUE(finite(0.0));
  EXPECT_FALSE(finite(tmax));
  double lo = 0.0, hi = tmax;
  while (hi - lo > 1e-12) {
    const double mid = 0.5 * (lo + hi);
    (finite(mid) ? lo : hi) = mid;
  }
  return lo;
}

/// Max-error mode to 1 % over `box` (2 threads) brackets the maxima sampled in double, its lower ends are attained,
/// and verify mode gives SAFE at 1.05 x and UNSAFE (with a real witness) at 0.95 x the sampled maxima.
inline void checkVerifier(const model::RobotModel& robot, const IVec& box, int samples) {
  const int n = robot.dof();
  const domain::PoseBox ws = poseBox(robot, box);
  const DVec maxima = sampledMaxima(robot, box, samples, 5);
  verify::VerifierOptions o;
  o.mode = verify::Mode::MaxError;
  o.alpha = 0.01;
  o.threads = 2;
  const verify::VerifierResult r = verify::Verifier::run(robot, ws, o);
  ASSERT_TRUE(r.converged) << r.message;
  EXPECT_FALSE(r.singular);
  for (int k = 0; k < n; ++k) {
    EXPECT_TRUE(std::isfinite(r.max_upper[k])) << k;
    EXPECT_LE(r.max_lower[k], r.max_upper[k]) << k;
    EXPECT_GE(r.max_upper[k], maxima[k]) << robot.componentName(k);
    EXPECT_LE(r.max_upper[k] - r.max_lower[k], o.alpha * r.max_lower[k] * (1 + 1e-9)) << k;
    // The sampler comes close to the certified maximum, and the lower bound is attained where reported.
    EXPECT_GE(maxima[k], r.max_lower[k] * (1 - 0.02)) << robot.componentName(k);
    ASSERT_EQ(r.max_argmax[static_cast<std::size_t>(k)].size(), n);
    for (int i = 0; i < n; ++i) EXPECT_TRUE(box[i].contains(r.max_argmax[static_cast<std::size_t>(k)][i]));
    EXPECT_GE(robot.worstErrorAt(r.max_argmax[static_cast<std::size_t>(k)])[k], r.max_lower[k] * (1 - 1e-9)) << k;
  }
  verify::VerifierOptions v;
  v.threads = 2;
  v.thresholds = maxima * 1.05;
  const verify::VerifierResult safe = verify::Verifier::run(robot, ws, v);
  EXPECT_EQ(safe.verdict, verify::Verdict::Safe) << safe.message;
  EXPECT_EQ(safe.undecided_box_count, 0u);
  v.thresholds = maxima * 0.95;
  const verify::VerifierResult unsafe = verify::Verifier::run(robot, ws, v);
  ASSERT_EQ(unsafe.verdict, verify::Verdict::Unsafe) << unsafe.message;
  const int k = unsafe.witness_component;
  ASSERT_GE(k, 0);
  for (int i = 0; i < n; ++i) EXPECT_TRUE(box[i].contains(unsafe.witness[i]));
  EXPECT_GT(robot.worstErrorAt(unsafe.witness)[k], v.thresholds[k]);
}

}  // namespace test
}  // namespace pkm_accuracy
