// Random verification problems for the soundness suite and the checks run on each (docs/soundness.md, "The randomized
// soundness suite").
//
// makeCase(seed, index, ref6) draws one problem from its own generator (seeded by seed and index, so any case can be
// re-run alone): a robot (ref6 perturbed, or a random semi-regular hexagon at a scale of 0.01-10 m; per-leg sensor
// errors, a tool point), optional anchor / tool-point uncertainty (0-2% of the robot's size), a domain (box
// workspace with thin variables and angle ranges up to 40 degrees, near-singular boxes, position regions, a
// transformed frame, waypoint and polynomial trajectories, polynomial motion varieties) and verifier options. The same
// numbers are given to the core (GoughGeometry, domain classes; every fourth case through the generic model path,
// KinematicModel<GoughKinematics>) and to the plain oracle (PlainOracle.hpp), which never uses the core's models or
// domains.
//
// runCase() runs the verifier on it (max-error mode, then verify mode with thresholds below and just above the
// maxima) and checks every answer against the oracle; it returns the failures as sentences (empty: the case passed).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/SVD>

#include "PlainOracle.hpp"
#include "pkm_accuracy/core/domain/ParametricVariety.hpp"
#include "pkm_accuracy/core/domain/PolynomialTrajectory.hpp"
#include "pkm_accuracy/core/domain/PositionRegion.hpp"
#include "pkm_accuracy/core/domain/TransformedDomain.hpp"
#include "pkm_accuracy/core/domain/WaypointTrajectory.hpp"
#include "pkm_accuracy/core/domain/Workspace.hpp"
#include "pkm_accuracy/core/model/GoughGeometry.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/core/model/robots/GoughKinematics.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"

namespace pkm_accuracy {
namespace test {
namespace soundness {

inline std::string num(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

/// Which problems: every kind (General), or only box workspaces of small and mid size with anchor uncertainty of
/// 0.2-2% of the robot's size and the default options (Uncertain: the decomposed geometry form's territory).
enum class Profile { General, Uncertain };

inline std::string profileName(Profile p) { return p == Profile::General ? "general" : "uncertain"; }

/// One random problem.
struct Case {
  std::uint64_t seed = 0;
  int index = 0;
  Profile profile = Profile::General;
  std::string robotKind, domainKind, sizeClass;
  /// The robot through the generic model path (KinematicModel<GoughKinematics>, model::makeGenericGough) instead of
  /// the hand-written GoughPlatform: every fourth case (index % 4 == 3; the random draws are the same either way).
  bool generic = false;
  double size = 0.0;                ///< the robot's base radius (m)
  model::GoughGeometry geometry;    ///< what the core gets (with its half-widths)
  oracle::Uncertainty uncertainty;  ///< what the oracle gets (nominal robot and uncertain coordinates)
  std::shared_ptr<const domain::Domain> domain;
  std::shared_ptr<const oracle::PoseMap> map;
  std::string robotText, domainText, optionsText;
  verify::VerifierOptions options;  ///< method and search options (mode, thresholds and budgets set per run)
  double alpha = 0.01;              ///< max-error tolerance (relative)

  std::string description() const {
    std::ostringstream os;
    os << "seed " << seed << " case " << index << " (" << profileName(profile) << "): " << robotKind
       << (generic ? " (generic model path)" : "") << ", " << domainKind << " (" << sizeClass
       << ")\n  robot: " << robotText << "\n  domain: " << domainText << "\n  options: " << optionsText << ", alpha "
       << alpha;
    return os.str();
  }
};

namespace detail {

using Rng = std::mt19937_64;

inline double uniform(Rng& rng, double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
inline double logUniform(Rng& rng, double a, double b) {
  return std::pow(10.0, uniform(rng, std::log10(a), std::log10(b)));
}
inline bool chance(Rng& rng, double p) { return uniform(rng, 0.0, 1.0) < p; }
inline int pick(Rng& rng, int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng); }

constexpr double kDeg = 3.14159265358979323846 / 180.0;

/// J^-1 conditioning at a pose with the rotation columns scaled by the robot's size (oracle; long double).
inline double conditionAt(const oracle::PlainRobot& r, const std::array<double, 6>& q, double size) {
  Eigen::Matrix<long double, 6, 6> m =
      oracle::inverseJacobian<long double>(r, oracle::Placement::fromPose({q[0], q[1], q[2], q[3], q[4], q[5]}));
  for (int i = 0; i < 6; ++i)
    for (int j = 3; j < 6; ++j) m(i, j) /= size;
  const Eigen::JacobiSVD<Eigen::Matrix<long double, 6, 6>> svd(m);
  const auto s = svd.singularValues();
  return s[5] > 0 ? static_cast<double>(s[0] / s[5]) : std::numeric_limits<double>::infinity();
}

struct Robot {
  oracle::PlainRobot plain;
  double size = 0.0, height = 0.0, platformRadius = 0.0;
  std::string kind;
};

inline Robot makeRobot(Rng& rng, const model::GoughGeometry& ref6, double ref6Share) {
  for (int attempt = 0;; ++attempt) {
    Robot r;
    if (chance(rng, ref6Share)) {
      r.kind = "ref6 perturbed";
      r.size = 0.1316;
      r.platformRadius = 0.0790;
      r.height = 0.475 * uniform(rng, 0.9, 1.1);
      const double jitter = uniform(rng, 0.0, 0.03) * r.size;
      for (int i = 0; i < 6; ++i) {
        for (int a = 0; a < 3; ++a) {
          r.plain.base[i][a] = ref6.base_anchors[i][a] + uniform(rng, -1.0, 1.0) * jitter * (a == 2 ? 0.3 : 1.0);
          r.plain.platform[i][a] =
              ref6.platform_anchors[i][a] + uniform(rng, -1.0, 1.0) * jitter * (a == 2 ? 0.3 : 1.0);
        }
      }
    } else {
      r.kind = "random hexagon";
      r.size = logUniform(rng, 0.01, 10.0);
      r.platformRadius = r.size * uniform(rng, 0.35, 0.9);
      r.height = r.size * uniform(rng, 1.5, 4.0);
      const double db = uniform(rng, 30.0, 55.0) * kDeg, dp = uniform(rng, 5.0, 35.0) * kDeg;
      const double jitter = uniform(rng, 0.0, 0.02) * r.size;
      for (int k = 0; k < 3; ++k) {
        const double c = (90.0 - 120.0 * k) * kDeg;
        for (int s = 0; s < 2; ++s) {
          const int leg = 2 * k + s;
          const double sign = s == 0 ? 1.0 : -1.0;
          r.plain.base[leg] = Eigen::Vector3d(r.size * std::cos(c + sign * db), r.size * std::sin(c + sign * db), 0.0);
          r.plain.platform[leg] = Eigen::Vector3d(r.platformRadius * std::cos(c + sign * dp),
                                                  r.platformRadius * std::sin(c + sign * dp), 0.0);
          for (int a = 0; a < 3; ++a) {
            r.plain.base[leg][a] += uniform(rng, -1.0, 1.0) * jitter;
            r.plain.platform[leg][a] += uniform(rng, -1.0, 1.0) * jitter;
          }
        }
      }
    }
    const double e = r.size * logUniform(rng, 1e-5, 1e-3);
    const bool perLeg = chance(rng, 0.6);
    for (int i = 0; i < 6; ++i) r.plain.sensor[i] = perLeg ? e * uniform(rng, 0.5, 2.0) : e;
    if (chance(rng, 0.4)) {
      r.plain.tool = Eigen::Vector3d(uniform(rng, -0.5, 0.5) * r.platformRadius,
                                     uniform(rng, -0.5, 0.5) * r.platformRadius, uniform(rng, -0.5, 0.5) * r.size);
    }
    // A robot that is far from singular at its home pose (a well-posed problem to start from).
    if (conditionAt(r.plain, {0, 0, r.height, 0, 0, 0}, r.size) < 1e3 || attempt > 20) return r;
  }
}

/// Half-widths of position (relative to the robot's size) and angle (rad) per size class.
struct SizeClass {
  std::string name;
  double position = 0.0, angle = 0.0;
};

inline SizeClass drawSizeClass(Rng& rng) {
  const double u = uniform(rng, 0.0, 1.0);
  if (u < 0.15) return {"tiny", logUniform(rng, 1e-6, 1e-4), logUniform(rng, 1e-6, 3e-4)};
  if (u < 0.45) return {"small", logUniform(rng, 1e-3, 1e-2), logUniform(rng, 1e-3, 2e-2)};
  if (u < 0.8) return {"mid", uniform(rng, 0.02, 0.1), uniform(rng, 0.02, 0.15)};
  return {"full", uniform(rng, 0.1, 0.4), uniform(rng, 0.15, 40.0 * kDeg)};
}

inline std::string rangesText(const std::array<double, 6>& lo, const std::array<double, 6>& hi) {
  static const char* kNames[6] = {"x", "y", "z", "roll", "pitch", "yaw"};
  std::string s;
  for (int i = 0; i < 6; ++i) s += std::string(i ? ", " : "") + kNames[i] + " [" + num(lo[i]) + ", " + num(hi[i]) + "]";
  return s;
}

/// A singular pose of the nominal robot (bisection between two poses with opposite signs of det J^-1), if found.
inline bool findSingularPose(Rng& rng, const Robot& r, std::array<double, 6>& q) {
  auto det = [&](const std::array<double, 6>& x) {
    return oracle::determinant(r.plain, oracle::Placement::fromPose({x[0], x[1], x[2], x[3], x[4], x[5]})).value;
  };
  for (int attempt = 0; attempt < 300; ++attempt) {
    std::array<double, 6> a, b;
    for (int i = 0; i < 6; ++i) {
      const double lo = i < 2 ? -0.5 * r.platformRadius : i == 2 ? 0.6 * r.height : -1.2;
      const double hi = i < 2 ? 0.5 * r.platformRadius : i == 2 ? 1.5 * r.height : 1.2;
      a[i] = uniform(rng, lo, hi);
      b[i] = uniform(rng, lo, hi);
    }
    long double da = det(a);
    const long double db = det(b);
    if (!(da * db < 0)) continue;
    for (int it = 0; it < 80; ++it) {
      std::array<double, 6> m;
      for (int i = 0; i < 6; ++i) m[i] = 0.5 * (a[i] + b[i]);
      const long double dm = det(m);
      if ((dm < 0) == (da < 0)) {
        a = m;
        da = dm;
      } else {
        b = m;
      }
    }
    q = a;
    return true;
  }
  return false;
}

/// A workspace box (and its oracle map) around `centre` with half-widths from the size class; thin variables with
/// probability `thin`.
inline void drawRanges(Rng& rng, const Robot& r, const SizeClass& sc, const std::array<double, 6>& centre, double thin,
                       std::array<double, 6>& lo, std::array<double, 6>& hi) {
  for (int i = 0; i < 6; ++i) {
    const double half = chance(rng, thin) ? 0.0 : (i < 3 ? sc.position * r.size : sc.angle) * uniform(rng, 0.3, 1.0);
    lo[i] = centre[i] - half;
    hi[i] = centre[i] + half;
  }
}

inline std::array<double, 6> homeCentre(Rng& rng, const Robot& r) {
  std::array<double, 6> c{};
  c[0] = uniform(rng, -0.3, 0.3) * r.platformRadius;
  c[1] = uniform(rng, -0.3, 0.3) * r.platformRadius;
  c[2] = r.height * uniform(rng, 0.85, 1.25);
  if (chance(rng, 0.5))
    for (int i = 3; i < 6; ++i) c[i] = uniform(rng, -0.2, 0.2);
  return c;
}

inline std::array<Interval, 6> toIntervals(const std::array<double, 6>& lo, const std::array<double, 6>& hi) {
  std::array<Interval, 6> r;
  for (int i = 0; i < 6; ++i) r[i] = Interval(lo[i], hi[i]);
  return r;
}

/// A position region inside the ranges' position box, as the core's PositionRegion and the oracle's Region.
inline domain::PositionRegion drawRegion(Rng& rng, std::array<double, 6>& lo, std::array<double, 6>& hi,
                                         oracle::Region& region, std::string& text) {
  Eigen::Vector3d c, h;
  for (int i = 0; i < 3; ++i) {
    c[i] = 0.5 * (lo[i] + hi[i]);
    h[i] = std::max(0.5 * (hi[i] - lo[i]), 1e-9 * (std::abs(c[i]) + 1e-3));
  }
  region.size = h.maxCoeff();
  const int kind = pick(rng, 3);
  if (kind == 0) {
    region.kind = oracle::Region::Cylinder;
    region.centre = Eigen::Vector3d(c[0], c[1], 0.0);
    region.radius = std::min(h[0], h[1]);
    region.zmin = c[2] - h[2];
    region.zmax = c[2] + h[2];
    lo[0] = c[0] - region.radius;
    hi[0] = c[0] + region.radius;
    lo[1] = c[1] - region.radius;
    hi[1] = c[1] + region.radius;
    lo[2] = region.zmin;
    hi[2] = region.zmax;
    text = "cylinder centre (" + num(c[0]) + ", " + num(c[1]) + ") radius " + num(region.radius) + " z [" +
           num(region.zmin) + ", " + num(region.zmax) + "]";
    return domain::PositionRegion::cylinder(c[0], c[1], region.radius, region.zmin, region.zmax);
  }
  if (kind == 1) {
    region.kind = oracle::Region::Sphere;
    region.centre = c;
    region.radius = h.minCoeff();
    for (int i = 0; i < 3; ++i) {
      lo[i] = c[i] - region.radius;
      hi[i] = c[i] + region.radius;
    }
    text = "sphere centre (" + num(c[0]) + ", " + num(c[1]) + ", " + num(c[2]) + ") radius " + num(region.radius);
    return domain::PositionRegion::sphere(c, region.radius);
  }
  // The box cut by 1-4 random half-spaces that keep the centre inside.
  region.kind = oracle::Region::Polyhedron;
  text = "polyhedron";
  for (int i = 0; i < 3; ++i) {
    for (const double s : {1.0, -1.0}) {
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      n[i] = s;
      region.normals.push_back(n);
      region.offsets.push_back(s > 0 ? hi[i] : -lo[i]);
    }
  }
  const int cuts = 1 + pick(rng, 4);
  for (int j = 0; j < cuts; ++j) {
    Eigen::Vector3d n(uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0));
    n.normalize();
    const double reach = std::abs(n[0]) * h[0] + std::abs(n[1]) * h[1] + std::abs(n[2]) * h[2];
    region.normals.push_back(n);
    region.offsets.push_back(n.dot(c) + uniform(rng, 0.1, 0.9) * reach);
  }
  for (std::size_t j = 0; j < region.normals.size(); ++j) {
    const Eigen::Vector3d& n = region.normals[j];
    text += " [" + num(n[0]) + ", " + num(n[1]) + ", " + num(n[2]) + "].p <= " + num(region.offsets[j]) + ";";
  }
  return domain::PositionRegion::polyhedron(region.normals, region.offsets, Eigen::Vector3d(lo[0], lo[1], lo[2]),
                                            Eigen::Vector3d(hi[0], hi[1], hi[2]));
}

/// Position and angle reach of a trajectory / variety around the home pose.
inline std::array<double, 6> reachOf(const Robot& r, const SizeClass& sc) {
  std::array<double, 6> reach{};
  for (int i = 0; i < 6; ++i) reach[i] = i < 3 ? sc.position * r.size : sc.angle;
  return reach;
}

inline void drawOptions(Rng& rng, Case& c, bool defaults) {
  verify::VerifierOptions& o = c.options;
  std::ostringstream os;
  static const double kAlpha[] = {0.002, 0.01, 0.01, 0.02, 0.05, 0.1};
  c.alpha = kAlpha[pick(rng, 6)];
  if (defaults) {
    c.optionsText = "defaults";
    return;
  }
  if (chance(rng, 0.25)) {
    static const char* kOthers[] = {"combined", "mean_value", "symbolic_precond", "precond", "paper_baseline"};
    o.method = kOthers[pick(rng, 5)];
  }
  const double b = uniform(rng, 0.0, 1.0);
  o.tuning.bisection = b < 0.7    ? verify::Bisection::Smear
                       : b < 0.85 ? verify::Bisection::LargestScaledWidth
                                  : verify::Bisection::RoundRobin;
  const double g = uniform(rng, 0.0, 1.0);
  o.geometry_splitting = g < 0.7    ? verify::GeometrySplitting::Auto
                         : g < 0.85 ? verify::GeometrySplitting::Never
                                    : verify::GeometrySplitting::Always;
  o.tuning.decompose_geometry = chance(rng, 0.8);
  o.monotonicity = chance(rng, 0.2);
  o.tuning.faces = chance(rng, 0.85);
  o.tuning.skip_hopeless = chance(rng, 0.85);
  static const int kPresample[] = {3, 3, 3, 3, 0, 2, 5};
  o.presample_points = kPresample[pick(rng, 7)];
  static const int kCentre[] = {2, 2, 2, 1, 3};
  o.tuning.centre_check_period = kCentre[pick(rng, 5)];
  o.stop_at_first_witness = chance(rng, 0.8);
  static const char* kBisection[] = {"smear", "largest_scaled_width", "round_robin"};
  static const char* kSplitting[] = {"auto", "never", "always"};
  os << "method " << o.method << ", bisection " << kBisection[static_cast<int>(o.tuning.bisection)]
     << ", geometry_splitting " << kSplitting[static_cast<int>(o.geometry_splitting)] << ", decompose_geometry "
     << o.tuning.decompose_geometry << ", monotonicity " << o.monotonicity << ", faces " << o.tuning.faces
     << ", skip_hopeless " << o.tuning.skip_hopeless << ", presample_points " << o.presample_points
     << ", centre_check_period " << o.tuning.centre_check_period << ", stop_at_first_witness "
     << o.stop_at_first_witness;
  c.optionsText = os.str();
}

}  // namespace detail

/// The case `index` of the campaign `seed` (its own generator: the same case whatever else is run).
inline Case makeCase(std::uint64_t seed, int index, const model::GoughGeometry& ref6,
                     Profile profile = Profile::General) {
  using namespace detail;
  const bool focus = profile == Profile::Uncertain;
  std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                    static_cast<std::uint32_t>(index), focus ? 0x55u : 0x50u};
  Rng rng(seq);
  Case c;
  c.seed = seed;
  c.index = index;
  c.profile = profile;
  const Robot r = makeRobot(rng, ref6, focus ? 0.6 : 0.35);
  c.robotKind = r.kind;
  c.size = r.size;
  c.generic = index % 4 == 3;

  // ---- uncertainty: none, every anchor coordinate, base or platform anchors only, or a few coordinates ----
  std::array<Eigen::Vector3d, 6> baseHalf, platformHalf;
  for (int i = 0; i < 6; ++i) baseHalf[i] = platformHalf[i] = Eigen::Vector3d::Zero();
  Eigen::Vector3d toolHalf = Eigen::Vector3d::Zero();
  std::string uncertaintyText = "exact geometry";
  if (focus || chance(rng, 0.55)) {
    const double h = r.size * logUniform(rng, focus ? 0.002 : 1e-4, 0.02);
    const double u = uniform(rng, 0.0, focus ? 0.8 : 1.0);
    if (u < 0.5) {
      for (int i = 0; i < 6; ++i) baseHalf[i] = platformHalf[i] = Eigen::Vector3d::Constant(h);
      uncertaintyText = "every anchor coordinate +- " + num(h);
    } else if (u < 0.65) {
      for (int i = 0; i < 6; ++i) baseHalf[i] = Eigen::Vector3d::Constant(h);
      uncertaintyText = "every base anchor coordinate +- " + num(h);
    } else if (u < 0.8) {
      for (int i = 0; i < 6; ++i) platformHalf[i] = Eigen::Vector3d::Constant(h);
      uncertaintyText = "every platform anchor coordinate +- " + num(h);
    } else {
      uncertaintyText = "";
      const int n = 1 + pick(rng, 12);
      for (int j = 0; j < n; ++j) {
        const int kind = pick(rng, 2), leg = pick(rng, 6), axis = pick(rng, 3);
        const double hj = h * uniform(rng, 0.2, 1.0);
        (kind == 0 ? baseHalf : platformHalf)[leg][axis] = hj;
      }
      if (chance(rng, 0.3)) {
        for (int a = 0; a < 3; ++a) toolHalf[a] = chance(rng, 0.7) ? h * uniform(rng, 0.2, 1.0) : 0.0;
      }
      for (int kind = 0; kind < 2; ++kind)
        for (int i = 0; i < 6; ++i)
          for (int a = 0; a < 3; ++a) {
            const double hj = (kind == 0 ? baseHalf : platformHalf)[i][a];
            if (hj > 0.0)
              uncertaintyText += std::string(kind == 0 ? "base" : "platform") + "[" + std::to_string(i) + "]." +
                                 "xyz"[a] + " +- " + num(hj) + "; ";
          }
      for (int a = 0; a < 3; ++a)
        if (toolHalf[a] > 0.0) uncertaintyText += std::string("tool.") + "xyz"[a] + " +- " + num(toolHalf[a]) + "; ";
      if (uncertaintyText.empty()) uncertaintyText = "exact geometry";
    }
  }
  c.uncertainty = oracle::Uncertainty::of(r.plain, baseHalf, platformHalf, toolHalf);
  model::GoughGeometry& g = c.geometry;
  for (int i = 0; i < 6; ++i) {
    g.base_anchors.push_back(r.plain.base[i]);
    g.platform_anchors.push_back(r.plain.platform[i]);
    g.sensor_error.push_back(r.plain.sensor[i]);
  }
  g.tool_point = r.plain.tool;
  if (c.uncertainty.count() > 0) {
    for (int i = 0; i < 6; ++i) {
      g.base_anchor_halfwidth.push_back(baseHalf[i]);
      g.platform_anchor_halfwidth.push_back(platformHalf[i]);
    }
    g.tool_point_halfwidth = toolHalf;
  }
  {
    std::ostringstream os;
    os << "base_anchors";
    for (int i = 0; i < 6; ++i)
      os << " [" << num(r.plain.base[i][0]) << ", " << num(r.plain.base[i][1]) << ", " << num(r.plain.base[i][2])
         << "]";
    os << "; platform_anchors";
    for (int i = 0; i < 6; ++i)
      os << " [" << num(r.plain.platform[i][0]) << ", " << num(r.plain.platform[i][1]) << ", "
         << num(r.plain.platform[i][2]) << "]";
    os << "; sensor_error [";
    for (int i = 0; i < 6; ++i) os << (i ? ", " : "") << num(r.plain.sensor[i]);
    os << "]; tool_point [" << num(r.plain.tool[0]) << ", " << num(r.plain.tool[1]) << ", " << num(r.plain.tool[2])
       << "]; uncertainty: " << uncertaintyText;
    c.robotText = os.str();
  }

  // ---- domain ----
  SizeClass sc = drawSizeClass(rng);
  if (focus) {
    sc = chance(rng, 0.7) ? SizeClass{"mid", uniform(rng, 0.02, 0.1), uniform(rng, 0.02, 0.15)}
                          : SizeClass{"small", logUniform(rng, 1e-3, 1e-2), logUniform(rng, 1e-3, 2e-2)};
  }
  c.sizeClass = sc.name;
  const double kind = focus ? 0.0 : uniform(rng, 0.0, 1.0);
  if (kind < 0.5) {
    // Box workspace (a tenth of them around a singular pose of the nominal robot), or a position region.
    auto ws = std::make_shared<oracle::WorkspaceMap>();
    std::array<double, 6> centre = homeCentre(rng, r);
    SizeClass box = sc;
    bool nearSingular = false;
    std::array<double, 6> singular{};
    if (!focus && chance(rng, 0.2) && findSingularPose(rng, r, singular)) {
      nearSingular = true;
      box = chance(rng, 0.5) ? SizeClass{"small", logUniform(rng, 1e-4, 1e-2), logUniform(rng, 1e-4, 2e-2)}
                             : SizeClass{"tiny", logUniform(rng, 1e-6, 1e-4), logUniform(rng, 1e-6, 1e-4)};
      centre = singular;
    }
    drawRanges(rng, r, box, centre, focus ? 0.0 : 0.15, ws->lo, ws->hi);
    if (nearSingular && chance(rng, 0.5)) {
      // Shifted off the singular pose along one variable (by 1.2-3 half-widths: near it, not containing it).
      const int i = pick(rng, 6);
      const double half = 0.5 * (ws->hi[i] - ws->lo[i]), shift = (chance(rng, 0.5) ? 1 : -1) * uniform(rng, 1.2, 3.0);
      ws->lo[i] += shift * half;
      ws->hi[i] += shift * half;
      c.domainKind = "box workspace near a singular pose";
    } else {
      c.domainKind = nearSingular ? "box workspace around a singular pose" : "box workspace";
    }
    c.sizeClass = box.name;
    if (!nearSingular && !focus && chance(rng, 0.3)) {
      for (int i = 0; i < 3; ++i) {  // a region needs a solid position box
        if (ws->hi[i] == ws->lo[i]) {
          ws->lo[i] -= sc.position * r.size * 0.5;
          ws->hi[i] += sc.position * r.size * 0.5;
        }
      }
      std::string regionText;
      const domain::PositionRegion region = drawRegion(rng, ws->lo, ws->hi, ws->region, regionText);
      c.domain = std::make_shared<domain::Workspace>(
          region, std::array<Interval, 3>{Interval(ws->lo[3], ws->hi[3]), Interval(ws->lo[4], ws->hi[4]),
                                          Interval(ws->lo[5], ws->hi[5])});
      c.domainKind = "region workspace";
      c.domainText = regionText + "; " + detail::rangesText(ws->lo, ws->hi);
    } else {
      c.domain = std::make_shared<domain::Workspace>(domain::Workspace::fromRanges(toIntervals(ws->lo, ws->hi)));
      c.domainText = detail::rangesText(ws->lo, ws->hi);
    }
    c.map = ws;
  } else if (kind < 0.6) {
    // A box workspace given in a frame F (the pose of F in the base frame: a rotation about z or a general one).
    auto ws = std::make_shared<oracle::WorkspaceMap>();
    ws->transformed = true;
    ws->frameRpy = {0.0, 0.0, uniform(rng, -3.0, 3.0)};
    if (chance(rng, 0.5)) {
      ws->frameRpy[0] = uniform(rng, -0.5, 0.5);
      ws->frameRpy[1] = uniform(rng, -0.5, 0.5);
    }
    ws->frameTranslation =
        Eigen::Vector3d(uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0)) * r.size;
    // The centre of the workspace in F: the base-frame home centre seen from F.
    const std::array<double, 6> home = homeCentre(rng, r);
    const oracle::Mat3L33 rt = oracle::rotation(ws->frameRpy[0], ws->frameRpy[1], ws->frameRpy[2]);
    const oracle::Vec3L pf =
        rt.transpose() * (oracle::Vec3L(home[0], home[1], home[2]) - ws->frameTranslation.cast<long double>());
    const auto angles = oracle::rpyOf(rt.transpose() * oracle::rotation(home[3], home[4], home[5]));
    const std::array<double, 6> centre = {static_cast<double>(pf[0]),     static_cast<double>(pf[1]),
                                          static_cast<double>(pf[2]),     static_cast<double>(angles[0]),
                                          static_cast<double>(angles[1]), static_cast<double>(angles[2])};
    drawRanges(rng, r, sc, centre, 0.15, ws->lo, ws->hi);
    auto inner = std::make_shared<domain::Workspace>(domain::Workspace::fromRanges(toIntervals(ws->lo, ws->hi)));
    c.domain = std::make_shared<domain::TransformedDomain>(
        inner, domain::RigidTransform::fromTranslationRpy(ws->frameTranslation, ws->frameRpy[0], ws->frameRpy[1],
                                                          ws->frameRpy[2]));
    c.domainKind = "transformed box workspace";
    c.domainText = "frame rpy [" + num(ws->frameRpy[0]) + ", " + num(ws->frameRpy[1]) + ", " + num(ws->frameRpy[2]) +
                   "] translation [" + num(ws->frameTranslation[0]) + ", " + num(ws->frameTranslation[1]) + ", " +
                   num(ws->frameTranslation[2]) + "]; ranges in F: " + detail::rangesText(ws->lo, ws->hi);
    c.map = ws;
  } else if (kind < 0.75) {
    // Waypoints, linear in roll-pitch-yaw or slerp.
    auto wp = std::make_shared<oracle::WaypointMap>();
    wp->slerp = chance(rng, 0.5);
    const std::array<double, 6> centre = homeCentre(rng, r), reach = reachOf(r, sc);
    const int n = 2 + pick(rng, 5);
    double t = uniform(rng, -1.0, 1.0);
    std::vector<domain::WaypointTrajectory::Waypoint> points;
    std::ostringstream os;
    os << (wp->slerp ? "slerp" : "linear_rpy") << " waypoints";
    for (int i = 0; i < n; ++i) {
      domain::WaypointTrajectory::Waypoint w;
      w.t = t;
      for (int a = 0; a < 6; ++a) w.pose[a] = centre[a] + uniform(rng, -1.0, 1.0) * reach[a];
      points.push_back(w);
      wp->times.push_back(t);
      wp->poses6.push_back(w.pose);
      os << " [" << num(t);
      for (int a = 0; a < 6; ++a) os << ", " << num(w.pose[a]);
      os << "]";
      t += uniform(rng, 0.1, 2.0);
    }
    c.domain = std::make_shared<domain::WaypointTrajectory>(
        points, wp->slerp ? domain::WaypointTrajectory::Interpolation::Slerp
                          : domain::WaypointTrajectory::Interpolation::LinearRpy);
    c.domainKind = "waypoint trajectory";
    c.domainText = os.str();
    c.map = wp;
  } else if (kind < 0.87) {
    // Continuous polynomial segments of degree 1-5.
    auto pm = std::make_shared<oracle::PolynomialMap>();
    const std::array<double, 6> centre = homeCentre(rng, r), reach = reachOf(r, sc);
    const int segments = 1 + pick(rng, 3);
    double t = uniform(rng, -1.0, 1.0);
    std::array<double, 6> start;
    for (int a = 0; a < 6; ++a) start[a] = centre[a] + uniform(rng, -0.5, 0.5) * reach[a];
    std::vector<domain::PolynomialTrajectory::Segment> segs;
    std::ostringstream os;
    os << "polynomial segments";
    for (int s = 0; s < segments; ++s) {
      domain::PolynomialTrajectory::Segment seg;
      const double duration = uniform(rng, 0.2, 2.0);
      seg.start = t;
      seg.end = t + duration;
      const int degree = 1 + pick(rng, 5);
      os << " {t [" << num(seg.start) << ", " << num(seg.end) << "]";
      for (int a = 0; a < 6; ++a) {
        seg.coefficients[a].push_back(start[a]);
        for (int j = 1; j <= degree; ++j)
          seg.coefficients[a].push_back(uniform(rng, -1.0, 1.0) * reach[a] / std::pow(duration, j) / j);
        // The next segment starts where this one ends (Horner in double: continuous up to rounding).
        double v = 0.0;
        for (std::size_t j = seg.coefficients[a].size(); j-- > 0;) v = v * duration + seg.coefficients[a][j];
        start[a] = v;
        os << " c" << a << " [";
        for (std::size_t j = 0; j < seg.coefficients[a].size(); ++j)
          os << (j ? ", " : "") << num(seg.coefficients[a][j]);
        os << "]";
      }
      os << "}";
      segs.push_back(seg);
      oracle::PolynomialMap::Segment o;
      o.start = seg.start;
      o.end = seg.end;
      o.coefficients = seg.coefficients;
      pm->segments.push_back(o);
      t = seg.end;
    }
    c.domain = std::make_shared<domain::PolynomialTrajectory>(segs);
    c.domainKind = "polynomial trajectory";
    c.domainText = os.str();
    c.map = pm;
  } else {
    // A motion variety of 1-3 parameters.
    auto vm = std::make_shared<oracle::VarietyMap>();
    vm->m = 1 + pick(rng, 3);
    const std::array<double, 6> centre = homeCentre(rng, r), reach = reachOf(r, sc);
    std::array<std::vector<domain::ParametricVariety::Monomial>, 6> coords;
    std::ostringstream os;
    os << vm->m << "-parameter variety";
    for (int a = 0; a < 6; ++a) {
      std::vector<oracle::VarietyMap::Monomial> list;
      list.push_back({centre[a] + uniform(rng, -0.5, 0.5) * reach[a], {}});
      const int terms = chance(rng, 0.15) ? 0 : 1 + pick(rng, 3);
      for (int j = 0; j < terms; ++j) {
        oracle::VarietyMap::Monomial mono;
        mono.coefficient = uniform(rng, -1.0, 1.0) * reach[a];
        int total = 0;
        for (int p = 0; p < vm->m; ++p) total += mono.exponents[p] = pick(rng, 3);
        if (total == 0) mono.exponents[pick(rng, vm->m)] = 1;
        list.push_back(mono);
      }
      os << " c" << a << ":";
      for (const auto& mono : list) {
        domain::ParametricVariety::Monomial d;
        d.coefficient = mono.coefficient;
        for (int p = 0; p < 6; ++p) d.exponents[p] = mono.exponents[p];
        coords[a].push_back(d);
        os << " " << num(mono.coefficient);
        for (int p = 0; p < vm->m; ++p) os << (p ? "," : "*t^") << mono.exponents[p];
      }
      vm->coordinates[a] = list;
    }
    c.domain = std::make_shared<domain::ParametricVariety>(vm->m, coords);
    c.domainKind = "motion variety";
    c.domainText = os.str();
    c.map = vm;
  }
  drawOptions(rng, c, focus);
  return c;
}

// ---- running and checking a case ------------------------------------------------------------------------------------

struct RunSettings {
  oracle::SearchSettings search;
  std::size_t maxBoxes = 2000;  ///< per verifier run
  double timeLimit = 3.0;       ///< per verifier run (a safety net; the box budget is what normally stops a run)
  int threads = 1;
  /// Recorded boxes (safe boxes of verify runs, undecided boxes) whose own upper bounds are checked per run, and the
  /// oracle's effort in each (random points, pattern-search evaluations per component).
  int boxChecks = 8;
  int boxSamples = 24;
  int boxEvaluations = 150;
};

/// The budgets of the CI slice (test/core/SoundnessSuiteTest.cpp; soundness_campaign --slice).
inline RunSettings sliceSettings() {
  RunSettings s;
  s.search.samples = 1200;
  s.search.starts = 2;
  s.search.maxEvaluations = 900;
  s.maxBoxes = 1500;
  s.timeLimit = 1.0;
  s.boxChecks = 6;
  return s;
}

/// The default budgets of soundness_campaign.
inline RunSettings campaignSettings() {
  RunSettings s;
  s.search.samples = 3000;
  s.search.starts = 3;
  s.search.maxEvaluations = 1500;
  s.maxBoxes = 4000;
  s.timeLimit = 5.0;
  s.boxChecks = 16;
  s.boxSamples = 40;
  s.boxEvaluations = 300;
  return s;
}

struct Counts {
  long cases = 0;
  long maxConverged = 0, maxUnconverged = 0, maxSingular = 0;
  long safe = 0, unsafe = 0, undecided = 0, sensitive = 0, singular = 0;
  long assertions = 0, skipped = 0, failedCases = 0;
  long evaluations = 0;
  /// The oracle's reach: components of converged max-error runs, and those where the oracle's maximum is more than 1%
  /// below the certified lower bound (the search missed the worst pose or geometry there).
  long oracleCompared = 0, oracleShort = 0;
  double oracleWorst = 1.0;  ///< the smallest ratio oracle maximum / certified lower bound among them

  void add(const Counts& o) {
    cases += o.cases;
    maxConverged += o.maxConverged;
    maxUnconverged += o.maxUnconverged;
    maxSingular += o.maxSingular;
    safe += o.safe;
    unsafe += o.unsafe;
    undecided += o.undecided;
    sensitive += o.sensitive;
    singular += o.singular;
    assertions += o.assertions;
    skipped += o.skipped;
    failedCases += o.failedCases;
    evaluations += o.evaluations;
    oracleCompared += o.oracleCompared;
    oracleShort += o.oracleShort;
    oracleWorst = std::min(oracleWorst, o.oracleWorst);
  }
  std::string summary() const {
    std::ostringstream os;
    os << cases << " cases (" << failedCases << " failed); max-error runs: " << maxConverged << " converged, "
       << maxUnconverged << " not converged, " << maxSingular << " singular; verify runs: " << safe << " SAFE, "
       << unsafe << " UNSAFE, " << undecided << " UNDECIDED (" << sensitive
       << " uncertainty_sensitive), singular verdicts " << singular << "; " << assertions << " assertions checked, "
       << skipped << " skipped (pose singular to working precision); " << evaluations << " oracle evaluations; "
       << "oracle maximum > 1% below the certified lower bound in " << oracleShort << " of " << oracleCompared
       << " converged components (smallest ratio " << oracleWorst << ")";
    return os.str();
  }
};

namespace detail {

/// f_k at (t, g) in long double over every pose at t: the largest (lowest = false) or the smallest (lowest = true),
/// with the loosest tolerance among them.
inline oracle::Precise preciseAt(const Case& c, const oracle::Point& t, const oracle::Geometry& g, int k, bool lowest) {
  std::vector<oracle::Placement> poses;
  c.map->poses(t, poses);
  const oracle::PlainRobot robot = c.uncertainty.count() > 0 ? c.uncertainty.at(g) : c.uncertainty.nominal;
  oracle::Precise out;
  bool first = true;
  for (const oracle::Placement& x : poses) {
    const oracle::Precise p = oracle::precise(robot, x, k);
    if (first || (lowest ? p.value < out.value : p.value > out.value)) {
      out.value = p.value;
    }
    out.tolerance = first ? p.tolerance : std::max(out.tolerance, p.tolerance);
    out.reliable = first ? p.reliable : out.reliable && p.reliable;
    first = false;
  }
  return out;
}

inline oracle::Point toPoint(const DVec& v) {
  oracle::Point t(v.size());
  for (int i = 0; i < v.size(); ++i) t[i] = v[i];
  return t;
}

inline std::string pointText(const oracle::Point& t) {
  std::string s = "(";
  for (int i = 0; i < t.size(); ++i) s += (i ? ", " : "") + num(t[i]);
  return s + ")";
}

inline std::string geometryText(const oracle::Geometry& g) {
  if (g.empty()) return "nominal";
  std::string s = "[";
  for (std::size_t i = 0; i < g.size(); ++i) s += (i ? ", " : "") + num(g[i]);
  return s + "]";
}

/// Collects the failures of one case.
struct Checker {
  const Case& c;
  Counts& counts;
  std::vector<std::string>& failures;
  std::mt19937_64 rng;

  void fail(const std::string& what) { failures.push_back(what); }
  bool check(bool ok, const std::string& what) {
    ++counts.assertions;
    if (!ok) fail(what);
    return ok;
  }

  /// f_k >= bound (1 - tol) for every geometry tried at t (the smallest over a search), or at `g` alone when given.
  void attained(const oracle::Point& t, const std::vector<double>* g, int k, double bound, const std::string& what) {
    oracle::Geometry geometry;
    if (g && !g->empty()) {
      if (!check(c.uncertainty.admissible(*g), what + ": geometry not admissible: " + geometryText(*g))) return;
      geometry = *g;
    } else if (c.uncertainty.count() > 0) {
      geometry = oracle::minimumOverGeometries(*c.map, c.uncertainty, t, k, rng).g;
    }
    const oracle::Precise p = preciseAt(c, t, geometry, k, true);
    if (!p.reliable) {
      ++counts.skipped;
      return;
    }
    check(p.value >= bound * (1.0 - p.tolerance), what + ": component " + std::to_string(k) + " oracle " +
                                                      num(p.value) + " < certified " + num(bound) + " at " +
                                                      pointText(t) + " geometry " + geometryText(geometry));
  }

  bool inside(const DVec& v, const std::string& what) {
    const oracle::Point t = toPoint(v);
    return check(t.size() == c.map->variables() && c.map->inside(t, 1e-9),
                 what + ": point " + pointText(t) + " outside the domain");
  }

  /// det J^-1 of opposite signs at both ends, at the geometry given or at the nominal one and random vertices.
  void singular(const verify::VerifierResult& r, const std::string& what) {
    if (!inside(r.singular_from, what + " singular_from") || !inside(r.singular_to, what + " singular_to")) return;
    std::vector<oracle::Geometry> geometries;
    if (!r.singular_geometry.empty()) {
      if (!check(c.uncertainty.admissible(r.singular_geometry), what + ": singular_geometry not admissible")) return;
      geometries.push_back(r.singular_geometry);
    } else {
      geometries.push_back(c.uncertainty.centre());
      for (int i = 0; i < 4 && c.uncertainty.count() > 0; ++i) geometries.push_back(c.uncertainty.randomVertex(rng));
    }
    std::vector<oracle::Placement> a, b;
    c.map->poses(toPoint(r.singular_from), a);
    c.map->poses(toPoint(r.singular_to), b);
    for (const oracle::Geometry& g : geometries) {
      const oracle::PlainRobot robot = c.uncertainty.count() > 0 ? c.uncertainty.at(g) : c.uncertainty.nominal;
      for (const oracle::Placement& x : a)
        for (const oracle::Placement& y : b) {
          const oracle::Determinant da = oracle::determinant(robot, x), db = oracle::determinant(robot, y);
          if (!(da.relative > 1e-12 && db.relative > 1e-12)) {
            ++counts.skipped;
            continue;
          }
          check((da.value < 0) != (db.value < 0),
                what + ": det J^-1 has the same sign at singular_from " + pointText(toPoint(r.singular_from)) +
                    " and singular_to " + pointText(toPoint(r.singular_to)) + " for geometry " + geometryText(g));
        }
    }
  }

  /// An UNSAFE answer: a witness above its threshold for every geometry tried, or a certified singularity.
  void unsafe(const verify::VerifierResult& r, const DVec& thresholds, const std::string& what) {
    if (r.singular) singular(r, what);
    if (r.witness.size() == 0) {
      check(r.singular, what + ": UNSAFE without a witness or a singularity");
      return;
    }
    const int k = r.witness_component;
    if (!check(k >= 0 && k < 6, what + ": witness component " + std::to_string(k))) return;
    if (!inside(r.witness, what + " witness")) return;
    check(r.witness_lower_bound > thresholds[k],
          what + ": witness_lower_bound " + num(r.witness_lower_bound) + " <= threshold " + num(thresholds[k]));
    const oracle::Point t = toPoint(r.witness);
    attained(t, nullptr, k, r.witness_lower_bound, what + " witness (every geometry)");
    if (r.witness_error_lower.size() == 6) {
      for (int j = 0; j < 6; ++j) {
        if (j != k && std::isfinite(r.witness_error_lower[j]) && r.witness_error_lower[j] > 0.0)
          attained(t, nullptr, j, r.witness_error_lower[j], what + " witness_error_lower");
      }
    }
  }

  /// The upper bounds recorded with boxes of the search (safe or undecided) hold at the oracle's largest values in
  /// the box (its points in the domain) and the geometries it was searched with (every admissible one, or the
  /// recorded sub-ranges).
  void boxBounds(const std::vector<verify::BoxRecord>& records, const RunSettings& s, const std::string& what) {
    std::vector<std::size_t> order(records.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::shuffle(order.begin(), order.end(), rng);
    for (std::size_t n = 0; n < order.size() && static_cast<int>(n) < s.boxChecks; ++n) {
      const verify::BoxRecord& b = records[order[n]];
      const int m = c.map->variables();
      if (!check(b.box.size() == m && b.upper.size() == 6, what + ": recorded box of the wrong size")) return;
      std::vector<double> lo(m), hi(m);
      for (int i = 0; i < m; ++i) {
        lo[i] = b.box[i].lower();
        hi[i] = b.box[i].upper();
      }
      const oracle::BoxMap box(*c.map, lo, hi);
      oracle::Uncertainty u = c.uncertainty;
      std::string geometry = "every admissible geometry";
      if (!b.geometry.empty()) {
        if (!check(static_cast<int>(b.geometry.size()) == u.count(), what + ": recorded geometry of the wrong size"))
          return;
        std::vector<double> glo(u.count()), ghi(u.count());
        for (int p = 0; p < u.count(); ++p) {
          glo[p] = b.geometry[p].lower();
          ghi[p] = b.geometry[p].upper();
        }
        if (!check(c.uncertainty.admissible(glo) && c.uncertainty.admissible(ghi),
                   what + ": recorded geometry ranges not admissible"))
          continue;
        u = oracle::restricted(c.uncertainty, glo, ghi);
        geometry = "geometry ranges " + geometryText(glo) + " .. " + geometryText(ghi);
      }
      const std::array<oracle::Candidate, 6> best = oracle::boxMaxima(box, u, s.boxSamples, s.boxEvaluations, rng);
      for (int k = 0; k < 6; ++k) {
        if (!(b.upper[k] < std::numeric_limits<double>::infinity()) || best[k].t.size() == 0) continue;
        std::vector<oracle::Placement> poses;
        c.map->poses(best[k].t, poses);
        const oracle::PlainRobot robot = u.count() > 0 ? u.at(best[k].g) : u.nominal;
        for (const oracle::Placement& x : poses) {
          const oracle::Precise p = oracle::precise(robot, x, k);
          if (!p.reliable) {
            ++counts.skipped;
            continue;
          }
          std::string boxText;
          for (int i = 0; i < m; ++i) boxText += (i ? ", [" : "[") + num(lo[i]) + ", " + num(hi[i]) + "]";
          check(p.value <= b.upper[k] * (1.0 + p.tolerance),
                what + ": box bound of component " + std::to_string(k) + " " + num(b.upper[k]) + " < oracle " +
                    num(p.value) + " at " + pointText(best[k].t) + " geometry " + geometryText(best[k].g) +
                    " in the box " + boxText + " (" + geometry + ")");
        }
      }
    }
  }

  void sensitive(const verify::VerifierResult& r, const DVec& thresholds, const std::string& what) {
    check(!r.sensitive.empty() && c.uncertainty.count() > 0, what + ": uncertainty_sensitive without a recorded pose");
    for (std::size_t i = 0; i < r.sensitive.size() && i < 3; ++i) {
      const verify::SensitivePose& s = r.sensitive[i];
      const int k = s.component;
      if (!check(k >= 0 && k < 6, what + ": sensitive component " + std::to_string(k))) continue;
      if (!inside(s.point, what + " sensitive pose")) continue;
      check(s.failing_lower > thresholds[k],
            what + ": failing_lower " + num(s.failing_lower) + " <= threshold " + num(thresholds[k]));
      const oracle::Point t = toPoint(s.point);
      attained(t, &s.failing_geometry, k, s.failing_lower, what + " sensitive failing geometry");
      if (!s.passing_geometry.empty()) {
        if (!check(c.uncertainty.admissible(s.passing_geometry), what + ": passing geometry not admissible")) continue;
        for (int j = 0; j < 6; ++j) {
          if (j != k && !s.passes_all) continue;
          const oracle::Precise p = preciseAt(c, t, s.passing_geometry, j, false);
          if (!p.reliable) {
            ++counts.skipped;
            continue;
          }
          const double bound = j == k ? std::min(s.passing_upper, thresholds[k]) : thresholds[j];
          check(p.value <= bound * (1.0 + p.tolerance), what + ": passing geometry: component " + std::to_string(j) +
                                                            " oracle " + num(p.value) + " > " + num(bound) + " at " +
                                                            pointText(t));
        }
      }
    }
  }
};

}  // namespace detail

/// Runs the verifier on a case and checks its answers against the oracle. Returns the failures (empty: passed).
inline std::vector<std::string> runCase(const Case& c, const RunSettings& s, Counts& counts) {
  using namespace detail;
  std::vector<std::string> failures;
  Checker chk{c, counts, failures, std::mt19937_64(c.seed * 7919u + static_cast<std::uint64_t>(c.index))};
  ++counts.cases;
  const std::unique_ptr<const model::RobotModel> robotModel =
      c.generic ? std::unique_ptr<const model::RobotModel>(model::makeGenericGough(c.geometry))
                : std::make_unique<const model::GoughPlatform>(c.geometry);
  const model::RobotModel& robot = *robotModel;
  const oracle::Uncertainty& u = c.uncertainty;

  // The parameters the verifier reports geometries in are the oracle's coordinates, in the same order.
  bool sameParameters = chk.check(robot.geometryParameterCount() == u.count(),
                                  "geometry parameters: core " + std::to_string(robot.geometryParameterCount()) +
                                      ", oracle " + std::to_string(u.count()));
  for (int p = 0; sameParameters && p < u.count(); ++p) {
    sameParameters = chk.check(robot.geometryParameterName(p) == u.name(p),
                               "geometry parameter " + std::to_string(p) + ": core " + robot.geometryParameterName(p) +
                                   ", oracle " + u.name(p));
  }
  if (!sameParameters) {
    ++counts.failedCases;
    return failures;
  }

  // ---- the oracle's maxima over poses and geometries ----
  std::mt19937_64 searchRng(c.seed * 104729u + static_cast<std::uint64_t>(c.index));
  const oracle::Maxima sampled = oracle::searchMaxima(*c.map, u, s.search, searchRng);
  counts.evaluations += sampled.evaluations;
  std::array<oracle::Precise, 6> sampledPrecise;
  DVec sampledMax = DVec::Constant(6, std::numeric_limits<double>::quiet_NaN());
  for (int k = 0; k < 6; ++k) {
    const oracle::Candidate& b = sampled.best[k];
    if (b.t.size() == 0 || !std::isfinite(b.value)) continue;
    sampledPrecise[k] = preciseAt(c, b.t, b.g, k, false);
    if (sampledPrecise[k].reliable) sampledMax[k] = sampledPrecise[k].value;
  }

  auto baseOptions = [&]() {
    verify::VerifierOptions o = c.options;
    o.max_boxes = s.maxBoxes;
    o.time_limit_s = s.timeLimit;
    o.threads = s.threads;
    o.max_recorded_boxes = 16;
    return o;
  };

  // ---- max-error mode: upper >= the sampled maxima, lower attained at (argmax, argmax geometry) ----
  verify::VerifierOptions mo = baseOptions();
  mo.mode = verify::Mode::MaxError;
  mo.alpha = c.alpha;
  const verify::VerifierResult mr = verify::Verifier::run(robot, *c.domain, mo);
  (mr.singular ? counts.maxSingular : mr.converged ? counts.maxConverged : counts.maxUnconverged)++;
  if (mr.singular) chk.singular(mr, "max-error singular");
  chk.boxBounds(mr.undecided_boxes, s, "max-error undecided box");
  const bool haveBracket = mr.max_lower.size() == 6 && mr.max_upper.size() == 6;
  chk.check(haveBracket, "max-error: no bracket");
  DVec reference = DVec::Constant(6, std::numeric_limits<double>::quiet_NaN());
  for (int k = 0; haveBracket && k < 6; ++k) {
    const std::string comp = "component " + std::to_string(k);
    chk.check(mr.max_lower[k] <= mr.max_upper[k],
              "max-error " + comp + ": lower " + num(mr.max_lower[k]) + " > upper " + num(mr.max_upper[k]));
    if (std::isfinite(sampledMax[k])) {
      chk.check(mr.max_upper[k] >= sampledMax[k] * (1.0 - sampledPrecise[k].tolerance),
                "max-error " + comp + ": certified upper " + num(mr.max_upper[k]) + " < oracle " + num(sampledMax[k]) +
                    " at " + pointText(sampled.best[k].t) + " geometry " + geometryText(sampled.best[k].g));
    } else {
      ++counts.skipped;
    }
    if (mr.max_lower[k] > 0.0) {
      const bool hasArgmax = mr.max_argmax.size() == 6u && mr.max_argmax[k].size() == c.map->variables();
      if (chk.check(hasArgmax, "max-error " + comp + ": lower bound " + num(mr.max_lower[k]) + " without argmax") &&
          chk.inside(mr.max_argmax[k], "max-error " + comp + " argmax")) {
        const std::vector<double>* g = mr.max_argmax_geometry.size() == 6u && !mr.max_argmax_geometry[k].empty()
                                           ? &mr.max_argmax_geometry[k]
                                           : nullptr;
        chk.attained(toPoint(mr.max_argmax[k]), g, k, mr.max_lower[k], "max-error lower bound");
      }
    }
    if (mr.converged && !mr.singular && std::isfinite(sampledMax[k]) && mr.max_lower[k] > 0.0) {
      ++counts.oracleCompared;
      if (sampledMax[k] < 0.99 * mr.max_lower[k]) ++counts.oracleShort;
      counts.oracleWorst = std::min(counts.oracleWorst, sampledMax[k] / mr.max_lower[k]);
    }
    const double ref = std::max(std::isfinite(sampledMax[k]) ? sampledMax[k] : 0.0, mr.max_lower[k]);
    if (std::isfinite(ref) && ref > 0.0) reference[k] = ref;
  }

  // ---- verify mode ----
  auto verifyRun = [&](const DVec& thresholds, bool mayBeSafe, const std::string& what) {
    verify::VerifierOptions vo = baseOptions();
    vo.mode = verify::Mode::Verify;
    vo.thresholds = thresholds;
    vo.max_recorded_safe_boxes = 4096;
    const verify::VerifierResult vr = verify::Verifier::run(robot, *c.domain, vo);
    std::string t = what + " (thresholds";
    for (int k = 0; k < 6; ++k) t += " " + num(thresholds[k]);
    t += ")";
    // (A safe box's bound of a component decided on a containing box may be above the threshold: the enclosures may
    // return looser bounds for the components not asked for, ErrorEnclosure.hpp BoxInput::rows. Every recorded bound
    // must hold all the same.)
    chk.boxBounds(vr.safe_boxes, s, t + " safe box");
    chk.boxBounds(vr.undecided_boxes, s, t + " undecided box");
    if (vr.verdict == verify::Verdict::Safe) {
      ++counts.safe;
      chk.check(mayBeSafe, t + ": SAFE below the maxima: " + vr.message + "; fractions safe " +
                               num(vr.stats.safe_fraction) + ", unsafe " + num(vr.stats.unsafe_fraction) +
                               ", undecided " + num(vr.stats.undecided_fraction) + ", outside " +
                               num(vr.stats.outside_fraction));
      // SAFE must agree with every certified lower bound of the max-error run and every oracle value.
      std::string above;
      for (int k = 0; k < 6; ++k) {
        if (haveBracket && !(mr.max_lower[k] <= thresholds[k]))
          above += " component " + std::to_string(k) + " certified lower bound " + num(mr.max_lower[k]) + ";";
        if (std::isfinite(sampledMax[k]) && !(sampledMax[k] * (1.0 - sampledPrecise[k].tolerance) <= thresholds[k]))
          above += " component " + std::to_string(k) + " oracle " + num(sampledMax[k]) + ";";
      }
      chk.check(above.empty(), t + ": SAFE but above the thresholds:" + above);
      chk.check(!vr.singular && vr.sensitive_count == 0, t + ": SAFE with a singularity or a sensitive pose");
    } else if (vr.verdict == verify::Verdict::Unsafe) {
      ++counts.unsafe;
      if (vr.singular) ++counts.singular;
      chk.unsafe(vr, thresholds, t);
    } else {
      ++counts.undecided;
      if (vr.reason == verify::UndecidedReason::UncertaintySensitive) {
        ++counts.sensitive;
        chk.sensitive(vr, thresholds, t);
      }
    }
  };
  bool anyReference = false;
  for (int k = 0; k < 6; ++k) anyReference = anyReference || std::isfinite(reference[k]);
  if (anyReference) {
    auto below = [&](double factor) {
      DVec th(6);
      for (int k = 0; k < 6; ++k) th[k] = std::isfinite(reference[k]) ? factor * reference[k] : 1e300;
      return th;
    };
    verifyRun(below(0.999), false, "verify 0.999 x max");
    // Clearly below in some components (at least one), far above in the others.
    DVec mixed(6);
    const bool all = chk.rng() & 1u;
    int tight = -1;
    for (int k = 0; k < 6; ++k) {
      const bool low = all || (chk.rng() % 3u == 0u);
      const double f = low ? std::uniform_real_distribution<double>(0.5, 0.99)(chk.rng)
                           : std::uniform_real_distribution<double>(1.5, 100.0)(chk.rng);
      mixed[k] = std::isfinite(reference[k]) ? f * reference[k] : 1e300;
      if (low && std::isfinite(reference[k])) tight = k;
    }
    if (tight < 0) {
      for (int k = 0; k < 6; ++k)
        if (std::isfinite(reference[k])) mixed[k] = 0.8 * reference[k];
    }
    verifyRun(mixed, false, "verify below the maxima");
  } else {
    ++counts.skipped;
  }
  // Just above the oracle's maxima: SAFE is possible, and must then agree with the certified lower bounds.
  bool allSampled = true;
  for (int k = 0; k < 6; ++k) allSampled = allSampled && std::isfinite(sampledMax[k]);
  if (allSampled) {
    const double f = std::uniform_real_distribution<double>(1.0005, 1.05)(chk.rng);
    verifyRun(sampledMax * f, true, "verify " + num(f) + " x oracle max");
  }
  if (!failures.empty()) ++counts.failedCases;
  return failures;
}

}  // namespace soundness
}  // namespace test
}  // namespace pkm_accuracy
