// A plain oracle of the worst positioning error of a Gough platform, written independently of the core (no core
// model, domain or interval class is used here): J^-1 from the conventions (docs/conventions.md) in double or long
// double, J by Eigen's inverse, f_k = sum_j |J_kj| e_j; the poses of workspaces (box or position region, optionally
// in a rigidly transformed frame), waypoint and polynomial trajectories and polynomial motion varieties evaluated
// from their definitions; admissible geometries built from the nominal anchors and their half-widths; and a search
// for the maxima over poses and geometries (dense random sampling plus a coordinate pattern search) and for the
// minimum over the geometries at one pose (vertex flips plus a pattern search).
//
// Used by the randomized soundness suite (test/core/SoundnessSuiteTest.cpp, bench/soundness_campaign.cpp). Header
// only; Eigen and the long-double rotation oracle (test/core/RotationOracle.hpp) are its only dependencies.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include "../core/RotationOracle.hpp"

namespace pkm_accuracy {
namespace test {
namespace oracle {

using Real = long double;
using Vec3L = Eigen::Matrix<Real, 3, 1>;
using Mat3L33 = Eigen::Matrix<Real, 3, 3>;
using Vec6d = Eigen::Matrix<double, 6, 1>;
using Point = Eigen::VectorXd;         ///< a point of a domain's variables
using Geometry = std::vector<double>;  ///< one value per uncertain coordinate (in the documented order)

/// R = Rz(yaw) Ry(pitch) Rx(roll), in long double (RotationOracle).
inline Mat3L33 rotation(Real roll, Real pitch, Real yaw) {
  const Mat3L r = rpy(roll, pitch, yaw);
  Mat3L33 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = r[i][j];
  return m;
}

/// Roll, pitch, yaw of a rotation matrix (principal values).
inline std::array<Real, 3> rpyOf(const Mat3L33& m) {
  return {std::atan2(m(2, 1), m(2, 2)), std::atan2(-m(2, 0), std::hypot(m(0, 0), m(1, 0))),
          std::atan2(m(1, 0), m(0, 0))};
}

/// A pose as a position and a rotation (long double).
struct Placement {
  Vec3L p = Vec3L::Zero();
  Mat3L33 r = Mat3L33::Identity();
  static Placement fromPose(const std::array<Real, 6>& q) {
    Placement x;
    x.p << q[0], q[1], q[2];
    x.r = rotation(q[3], q[4], q[5]);
    return x;
  }
};

/// One concrete geometry (no uncertainty): A_i, b_i, c, e_i.
struct PlainRobot {
  std::array<Eigen::Vector3d, 6> base, platform;
  Eigen::Vector3d tool = Eigen::Vector3d::Zero();
  std::array<double, 6> sensor{};
};

/// Row i of J^-1 = [n_i^T, ((R (b_i - c)) x n_i)^T], B_i = p + R b_i, n_i = (B_i - A_i) / |B_i - A_i|.
template <typename T>
Eigen::Matrix<T, 6, 6> inverseJacobian(const PlainRobot& robot, const Placement& x) {
  using V3 = Eigen::Matrix<T, 3, 1>;
  const Eigen::Matrix<T, 3, 3> r = x.r.template cast<T>();
  const V3 p = x.p.template cast<T>(), c = robot.tool.template cast<T>();
  Eigen::Matrix<T, 6, 6> m;
  for (int i = 0; i < 6; ++i) {
    const V3 b = robot.platform[i].template cast<T>(), a = robot.base[i].template cast<T>();
    const V3 leg = p + r * b - a;
    const V3 n = leg / leg.norm();
    const V3 moment = (r * (b - c)).cross(n);
    m.template block<1, 3>(i, 0) = n.transpose();
    m.template block<1, 3>(i, 3) = moment.transpose();
  }
  return m;
}

/// f_k = sum_j |J_kj| e_j for every component (T: double or long double); NaN/inf where J^-1 is singular.
template <typename T>
Vec6d worstError(const PlainRobot& robot, const Placement& x) {
  const Eigen::Matrix<T, 6, 6> j = inverseJacobian<T>(robot, x).inverse();
  Vec6d f;
  for (int k = 0; k < 6; ++k) {
    T s = 0;
    for (int l = 0; l < 6; ++l) s += std::abs(j(k, l)) * static_cast<T>(robot.sensor[l]);
    f[k] = static_cast<double>(s);
  }
  return f;
}

/// det J^-1 in long double and its size relative to the product of the rows' norms (Hadamard's bound).
struct Determinant {
  Real value = 0;
  Real relative = 0;
};
inline Determinant determinant(const PlainRobot& robot, const Placement& x) {
  const Eigen::Matrix<Real, 6, 6> m = inverseJacobian<Real>(robot, x);
  Determinant d;
  d.value = m.determinant();
  Real h = 1;
  for (int i = 0; i < 6; ++i) h *= m.row(i).norm();
  d.relative = h > 0 ? std::abs(d.value) / h : 0;
  return d;
}

/// A value of f_k re-evaluated in long double, with a relative tolerance for comparisons against certified bounds:
/// 1e-9 plus a multiple of the long double result's own error estimate (the double/long double discrepancy divided
/// by the 2^11 ratio of their epsilons). `reliable` is false where even long double has too few digits left (J^-1
/// singular to working precision): such points prove nothing either way.
struct Precise {
  double value = 0.0;
  double tolerance = 1e-9;
  bool reliable = false;
};
inline Precise precise(const PlainRobot& robot, const Placement& x, int k) {
  Precise out;
  const double ld = worstError<Real>(robot, x)[k], d = worstError<double>(robot, x)[k];
  out.value = ld;
  if (!std::isfinite(ld) || !(ld > 0.0)) return out;
  const double rel = std::isfinite(d) ? std::abs(d - ld) / ld : 1.0;
  out.tolerance = 1e-9 + rel * (32.0 / 2048.0);
  out.reliable = rel < 1e-2;
  return out;
}

// ---- uncertain geometry ---------------------------------------------------------------------------------------------

/// An uncertain coordinate: kind 0 = base anchor, 1 = platform anchor, 2 = tool point.
struct Coordinate {
  int kind = 0, leg = 0, axis = 0;
  double nominal = 0.0, half = 0.0;
};

/// The admissible geometries: the nominal robot with every uncertain coordinate in nominal +- half. The coordinates are
/// kept in the documented parameter order (base anchors leg by leg x, y, z; platform anchors; tool point), so a
/// geometry reported by the verifier (one value per parameter) reads directly as a Geometry here.
struct Uncertainty {
  PlainRobot nominal;
  std::vector<Coordinate> coords;

  /// From per-coordinate half-widths (0: known exactly).
  static Uncertainty of(const PlainRobot& robot, const std::array<Eigen::Vector3d, 6>& baseHalf,
                        const std::array<Eigen::Vector3d, 6>& platformHalf, const Eigen::Vector3d& toolHalf) {
    Uncertainty u;
    u.nominal = robot;
    for (int kind = 0; kind < 2; ++kind)
      for (int i = 0; i < 6; ++i)
        for (int a = 0; a < 3; ++a) {
          const double h = kind == 0 ? baseHalf[i][a] : platformHalf[i][a];
          const double v = kind == 0 ? robot.base[i][a] : robot.platform[i][a];
          if (h > 0.0) u.coords.push_back({kind, i, a, v, h});
        }
    for (int a = 0; a < 3; ++a)
      if (toolHalf[a] > 0.0) u.coords.push_back({2, 0, a, robot.tool[a], toolHalf[a]});
    return u;
  }

  int count() const { return static_cast<int>(coords.size()); }
  double lo(int p) const { return coords[p].nominal - coords[p].half; }
  double hi(int p) const { return coords[p].nominal + coords[p].half; }
  Geometry centre() const {
    Geometry g(coords.size());
    for (std::size_t p = 0; p < coords.size(); ++p) g[p] = coords[p].nominal;
    return g;
  }
  std::string name(int p) const {
    static const char* kAxis[3] = {"x", "y", "z"};
    const Coordinate& c = coords[p];
    if (c.kind == 2) return std::string("tool_point.") + kAxis[c.axis];
    return std::string(c.kind == 0 ? "base_anchors[" : "platform_anchors[") + std::to_string(c.leg) + "]." +
           kAxis[c.axis];
  }
  /// Within nominal +- half, allowing `ulps` units in the last place of the coordinate's magnitude (the verifier's
  /// ranges are rounded outward).
  bool admissible(const Geometry& g, double ulps = 4.0) const {
    if (g.size() != coords.size()) return false;
    for (std::size_t p = 0; p < coords.size(); ++p) {
      const double slack = ulps * std::numeric_limits<double>::epsilon() *
                           (std::abs(coords[p].nominal) + coords[p].half + std::numeric_limits<double>::min());
      if (!(g[p] >= lo(static_cast<int>(p)) - slack && g[p] <= hi(static_cast<int>(p)) + slack)) return false;
    }
    return true;
  }
  PlainRobot at(const Geometry& g) const {
    PlainRobot r = nominal;
    for (std::size_t p = 0; p < coords.size(); ++p) {
      const Coordinate& c = coords[p];
      if (c.kind == 0) r.base[c.leg][c.axis] = g[p];
      if (c.kind == 1) r.platform[c.leg][c.axis] = g[p];
      if (c.kind == 2) r.tool[c.axis] = g[p];
    }
    return r;
  }
  template <typename Rng>
  Geometry randomVertex(Rng& rng) const {
    Geometry g(coords.size());
    for (std::size_t p = 0; p < coords.size(); ++p)
      g[p] = (rng() & 1u) ? hi(static_cast<int>(p)) : lo(static_cast<int>(p));
    return g;
  }
  template <typename Rng>
  Geometry randomInterior(Rng& rng) const {
    Geometry g(coords.size());
    for (std::size_t p = 0; p < coords.size(); ++p)
      g[p] = std::uniform_real_distribution<double>(lo(static_cast<int>(p)), hi(static_cast<int>(p)))(rng);
    return g;
  }
};

// ---- domains as the oracle sees them --------------------------------------------------------------------------------

/// The oracle's view of a domain: a box of variables, a membership test and the poses at a point of the variables.
class PoseMap {
 public:
  virtual ~PoseMap() = default;
  virtual int variables() const = 0;
  virtual double lower(int i) const = 0;
  virtual double upper(int i) const = 0;
  /// Whether t belongs to the domain; `slack` (>= 0) widens the test relative to the domain's size (0: exact test
  /// in double for sampling, a small slack for points reported by the verifier).
  virtual bool inside(const Point& t, double slack) const = 0;
  /// The poses at t (more than one where several pieces of a trajectory meet at t; all belong to the domain).
  virtual void poses(const Point& t, std::vector<Placement>& out) const = 0;
  /// Points worth evaluating besides random ones (box corners, waypoints, segment boundaries).
  virtual std::vector<Point> specialPoints() const { return {}; }

  bool inBox(const Point& t, double slack) const {
    if (t.size() != variables()) return false;
    for (int i = 0; i < variables(); ++i) {
      const double s = slack * (upper(i) - lower(i) + std::abs(lower(i)) + std::abs(upper(i)));
      if (!(t[i] >= lower(i) - s && t[i] <= upper(i) + s)) return false;
    }
    return true;
  }
};

/// The position part of a workspace: a box, a vertical cylinder, a ball or a convex polyhedron (half-spaces).
struct Region {
  enum Kind { Box, Cylinder, Sphere, Polyhedron } kind = Box;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< cylinder: (cx, cy, -); sphere: centre
  double radius = 0.0;
  double zmin = 0.0, zmax = 0.0;  ///< cylinder
  std::vector<Eigen::Vector3d> normals;
  std::vector<double> offsets;
  double size = 1.0;  ///< a length scale for the slack

  bool contains(const Eigen::Vector3d& p, double slack) const {
    const double s = slack * size;
    switch (kind) {
      case Box:
        return true;
      case Cylinder: {
        const double dx = p[0] - centre[0], dy = p[1] - centre[1];
        return std::sqrt(dx * dx + dy * dy) <= radius + s && p[2] >= zmin - s && p[2] <= zmax + s;
      }
      case Sphere:
        return (p - centre).norm() <= radius + s;
      case Polyhedron:
        for (std::size_t i = 0; i < normals.size(); ++i)
          if (normals[i].dot(p) > offsets[i] + s * normals[i].norm()) return false;
        return true;
    }
    return false;
  }
};

/// A workspace: ranges of (x, y, z, roll, pitch, yaw) in a frame F, optionally a position region in F, and the pose of
/// F in the base frame (rotation Rz(c) Ry(b) Rx(a), translation t): p_base = t + R_T p_F, R_base = R_T R_F.
class WorkspaceMap final : public PoseMap {
 public:
  std::array<double, 6> lo{}, hi{};
  Region region;
  bool transformed = false;
  std::array<double, 3> frameRpy{};
  Eigen::Vector3d frameTranslation = Eigen::Vector3d::Zero();

  int variables() const override { return 6; }
  double lower(int i) const override { return lo[i]; }
  double upper(int i) const override { return hi[i]; }
  bool inside(const Point& t, double slack) const override {
    return inBox(t, slack) && region.contains(Eigen::Vector3d(t[0], t[1], t[2]), slack);
  }
  void poses(const Point& t, std::vector<Placement>& out) const override {
    Placement x = Placement::fromPose({t[0], t[1], t[2], t[3], t[4], t[5]});
    if (transformed) {
      const Mat3L33 rt = rotation(frameRpy[0], frameRpy[1], frameRpy[2]);
      x.p = frameTranslation.cast<Real>() + rt * x.p;
      x.r = rt * x.r;
    }
    out.assign(1, x);
  }
  std::vector<Point> specialPoints() const override {
    std::vector<Point> out;
    for (int corner = 0; corner < 64; ++corner) {
      Point t(6);
      for (int i = 0; i < 6; ++i) t[i] = (corner >> i) & 1 ? hi[i] : lo[i];
      if (inside(t, 0.0)) out.push_back(t);
    }
    return out;
  }
};

/// Timed waypoints (s; x, y, z, roll, pitch, yaw), one variable u in [0, 1], t = t_0 + u (t_N - t_0); positions
/// linear per segment, orientations linear in roll-pitch-yaw or along the geodesic R_a Rot(axis, s phi).
class WaypointMap final : public PoseMap {
 public:
  std::vector<double> times;
  std::vector<std::array<double, 6>> poses6;
  bool slerp = false;

  int variables() const override { return 1; }
  double lower(int) const override { return 0.0; }
  double upper(int) const override { return 1.0; }
  bool inside(const Point& t, double slack) const override { return inBox(t, slack); }
  void poses(const Point& u, std::vector<Placement>& out) const override {
    out.clear();
    const Real t0 = times.front(), tn = times.back();
    const Real t = t0 + static_cast<Real>(u[0]) * (tn - t0);
    const Real eps = 1e-13L * (tn - t0);
    for (std::size_t k = 0; k + 1 < times.size(); ++k) {
      if (t < times[k] - eps || t > times[k + 1] + eps) continue;
      const Real s = std::min<Real>(1, std::max<Real>(0, (t - times[k]) / (Real(times[k + 1]) - times[k])));
      const auto& a = poses6[k];
      const auto& b = poses6[k + 1];
      Placement x;
      for (int i = 0; i < 3; ++i) x.p[i] = a[i] + s * (Real(b[i]) - a[i]);
      if (!slerp) {
        x.r = rotation(a[3] + s * (Real(b[3]) - a[3]), a[4] + s * (Real(b[4]) - a[4]), a[5] + s * (Real(b[5]) - a[5]));
      } else {
        const Mat3L33 ra = rotation(a[3], a[4], a[5]), rb = rotation(b[3], b[4], b[5]);
        const Eigen::AngleAxis<Real> rel(Mat3L33(ra.transpose() * rb));
        x.r = ra * Eigen::AngleAxis<Real>(s * rel.angle(), rel.axis()).toRotationMatrix();
      }
      out.push_back(x);
    }
  }
  std::vector<Point> specialPoints() const override {
    std::vector<Point> out;
    for (double t : times) out.push_back(Point::Constant(1, (t - times.front()) / (times.back() - times.front())));
    return out;
  }
};

/// Polynomial segments [start_k, end_k] (tiling the span), coordinate i = sum_j c_kij tau^j with tau = t - start_k.
class PolynomialMap final : public PoseMap {
 public:
  struct Segment {
    double start = 0.0, end = 0.0;
    std::array<std::vector<double>, 6> coefficients;
  };
  std::vector<Segment> segments;

  int variables() const override { return 1; }
  double lower(int) const override { return 0.0; }
  double upper(int) const override { return 1.0; }
  bool inside(const Point& t, double slack) const override { return inBox(t, slack); }
  void poses(const Point& u, std::vector<Placement>& out) const override {
    out.clear();
    const Real t0 = segments.front().start, tn = segments.back().end;
    const Real t = t0 + static_cast<Real>(u[0]) * (tn - t0);
    const Real eps = 1e-13L * (tn - t0);
    for (const Segment& s : segments) {
      if (t < s.start - eps || t > s.end + eps) continue;
      const Real tau = std::min<Real>(Real(s.end) - s.start, std::max<Real>(0, t - s.start));
      std::array<Real, 6> q{};
      for (int i = 0; i < 6; ++i) {
        Real v = 0;
        for (std::size_t j = s.coefficients[i].size(); j-- > 0;) v = v * tau + s.coefficients[i][j];
        q[i] = v;
      }
      out.push_back(Placement::fromPose(q));
    }
  }
  std::vector<Point> specialPoints() const override {
    std::vector<Point> out;
    const double t0 = segments.front().start, tn = segments.back().end;
    for (const Segment& s : segments) out.push_back(Point::Constant(1, (s.start - t0) / (tn - t0)));
    out.push_back(Point::Constant(1, 1.0));
    return out;
  }
};

/// A motion variety: every pose coordinate a sum of monomials coefficient * prod_i t_i^e_i over [0, 1]^m.
class VarietyMap final : public PoseMap {
 public:
  struct Monomial {
    double coefficient = 0.0;
    std::array<int, 6> exponents{};
  };
  int m = 1;
  std::array<std::vector<Monomial>, 6> coordinates;

  int variables() const override { return m; }
  double lower(int) const override { return 0.0; }
  double upper(int) const override { return 1.0; }
  bool inside(const Point& t, double slack) const override { return inBox(t, slack); }
  void poses(const Point& t, std::vector<Placement>& out) const override {
    std::array<Real, 6> q{};
    for (int i = 0; i < 6; ++i) {
      Real v = 0;
      for (const Monomial& mono : coordinates[i]) {
        Real term = mono.coefficient;
        for (int j = 0; j < m; ++j)
          for (int e = 0; e < mono.exponents[j]; ++e) term *= static_cast<Real>(t[j]);
        v += term;
      }
      q[i] = v;
    }
    out.assign(1, Placement::fromPose(q));
  }
  std::vector<Point> specialPoints() const override {
    std::vector<Point> out;
    for (int corner = 0; corner < (1 << m); ++corner) {
      Point t(m);
      for (int i = 0; i < m; ++i) t[i] = (corner >> i) & 1 ? 1.0 : 0.0;
      out.push_back(t);
    }
    return out;
  }
};

// ---- searches -------------------------------------------------------------------------------------------------------

/// f_k at a point of the variables and a geometry: the largest over the poses at t (double; -inf if none is finite).
inline double valueAt(const PoseMap& map, const Uncertainty& u, const Point& t, const Geometry& g, int k,
                      std::vector<Placement>& scratch) {
  map.poses(t, scratch);
  const PlainRobot robot = u.count() > 0 ? u.at(g) : u.nominal;
  double best = -std::numeric_limits<double>::infinity();
  for (const Placement& x : scratch) {
    const double f = worstError<double>(robot, x)[k];
    if (std::isfinite(f)) best = std::max(best, f);
  }
  return best;
}

/// All components at once (the largest over the poses at t).
inline Vec6d valuesAt(const PoseMap& map, const Uncertainty& u, const Point& t, const Geometry& g,
                      std::vector<Placement>& scratch) {
  map.poses(t, scratch);
  const PlainRobot robot = u.count() > 0 ? u.at(g) : u.nominal;
  Vec6d best = Vec6d::Constant(-std::numeric_limits<double>::infinity());
  for (const Placement& x : scratch) {
    const Vec6d f = worstError<double>(robot, x);
    for (int k = 0; k < 6; ++k)
      if (std::isfinite(f[k])) best[k] = std::max(best[k], f[k]);
  }
  return best;
}

/// A point of the variables and a geometry, with the value of f_k there.
struct Candidate {
  Point t;
  Geometry g;
  double value = -std::numeric_limits<double>::infinity();
};

struct SearchSettings {
  int samples = 2000;         ///< random points (each with a random geometry vertex, interior point or the nominal one)
  int starts = 3;             ///< pattern searches per component (from the best distinct samples)
  int maxEvaluations = 1500;  ///< per pattern search
  int kicks = 6;              ///< iterated vertex searches per start (uncertain geometry)
};

/// Coordinate pattern search maximising (sign +1) or minimising (-1) f_k over the variables (if `moveT`) and the
/// geometry (if `moveG`), from `start`, inside the domain and the geometry box. Steps start at a quarter of every
/// variable's width and at the full width of every geometry coordinate, and halve when no move improves.
inline Candidate patternSearch(const PoseMap& map, const Uncertainty& u, int k, double sign, Candidate start,
                               bool moveT, bool moveG, int maxEvaluations) {
  std::vector<Placement> scratch;
  const int m = map.variables(), params = u.count();
  std::vector<double> stepT(m, 0.0), stepG(params, 0.0), minT(m, 0.0), minG(params, 0.0);
  for (int i = 0; i < m && moveT; ++i) {
    stepT[i] = 0.25 * (map.upper(i) - map.lower(i));
    minT[i] = 1e-9 * stepT[i];
  }
  for (int p = 0; p < params && moveG; ++p) {
    stepG[p] = 2.0 * u.coords[p].half;  // (the first steps flip a coordinate between its bounds)
    minG[p] = 1e-6 * stepG[p];
  }
  double best = sign * start.value;
  int evaluations = 0;
  while (evaluations < maxEvaluations) {
    bool improved = false, anyStep = false;
    for (int c = 0; c < m + params && evaluations < maxEvaluations; ++c) {
      const double step = c < m ? stepT[c] : stepG[c - m];
      const double floor = c < m ? minT[c] : minG[c - m];
      if (!(step > floor)) continue;
      anyStep = true;
      for (const double dir : {1.0, -1.0}) {
        Candidate next = start;
        if (c < m) {
          next.t[c] = std::min(map.upper(c), std::max(map.lower(c), start.t[c] + dir * step));
          if (next.t[c] == start.t[c] || !map.inside(next.t, 0.0)) continue;
        } else {
          const int p = c - m;
          next.g[p] = std::min(u.hi(p), std::max(u.lo(p), start.g[p] + dir * step));
          if (next.g[p] == start.g[p]) continue;
        }
        next.value = valueAt(map, u, next.t, next.g, k, scratch);
        ++evaluations;
        if (sign * next.value > best) {
          best = sign * next.value;
          start = next;
          improved = true;
          break;
        }
      }
    }
    if (!anyStep) break;
    if (!improved) {
      for (double& s : stepT) s *= 0.5;
      for (double& s : stepG) s *= 0.5;
    }
  }
  return start;
}

template <typename Rng>
Point randomInside(const PoseMap& map, Rng& rng, bool& ok) {
  Point t(map.variables());
  for (int attempt = 0; attempt < 200; ++attempt) {
    for (int i = 0; i < map.variables(); ++i) {
      t[i] = map.lower(i) == map.upper(i) ? map.lower(i)
                                          : std::uniform_real_distribution<double>(map.lower(i), map.upper(i))(rng);
    }
    if (map.inside(t, 0.0)) {
      ok = true;
      return t;
    }
  }
  ok = false;
  return t;
}

/// A box of a domain's variables (a box of the verifier's search): its points that belong to the domain.
class BoxMap final : public PoseMap {
 public:
  BoxMap(const PoseMap& inner, std::vector<double> lo, std::vector<double> hi)
      : inner_(inner), lo_(std::move(lo)), hi_(std::move(hi)) {}
  int variables() const override { return inner_.variables(); }
  double lower(int i) const override { return lo_[i]; }
  double upper(int i) const override { return hi_[i]; }
  bool inside(const Point& t, double slack) const override { return inBox(t, slack) && inner_.inside(t, slack); }
  void poses(const Point& t, std::vector<Placement>& out) const override { inner_.poses(t, out); }
  std::vector<Point> specialPoints() const override {
    std::vector<Point> out;
    const int m = variables();
    for (int corner = 0; corner < (1 << m); ++corner) {
      Point t(m);
      for (int i = 0; i < m; ++i) t[i] = (corner >> i) & 1 ? hi_[i] : lo_[i];
      if (inside(t, 0.0)) out.push_back(t);
    }
    return out;
  }

 private:
  const PoseMap& inner_;
  std::vector<double> lo_, hi_;
};

/// The admissible geometries restricted to sub-ranges [lo_p, hi_p] of every coordinate (a box of the verifier's
/// geometry bisection).
inline Uncertainty restricted(const Uncertainty& u, const std::vector<double>& lo, const std::vector<double>& hi) {
  Uncertainty r = u;
  for (int p = 0; p < r.count(); ++p) {
    r.coords[p].nominal = 0.5 * (lo[p] + hi[p]);
    r.coords[p].half = 0.5 * (hi[p] - lo[p]);
  }
  return r;
}

/// The largest f_k found in a box (and geometry set) per component: its corners and random points, each with a random
/// geometry, then a pattern search over pose and geometry from the best of each component.
template <typename Rng>
std::array<Candidate, 6> boxMaxima(const PoseMap& box, const Uncertainty& u, int samples, int evaluations, Rng& rng) {
  std::array<Candidate, 6> best;
  std::vector<Placement> scratch;
  auto someGeometry = [&]() {
    if (u.count() == 0) return Geometry();
    const double r = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
    return r < 0.7 ? u.randomVertex(rng) : r < 0.9 ? u.randomInterior(rng) : u.centre();
  };
  auto account = [&](const Point& t) {
    const Geometry g = someGeometry();
    const Vec6d f = valuesAt(box, u, t, g, scratch);
    for (int k = 0; k < 6; ++k)
      if (std::isfinite(f[k]) && f[k] > best[k].value) best[k] = {t, g, f[k]};
  };
  std::vector<Point> corners = box.specialPoints();
  std::shuffle(corners.begin(), corners.end(), rng);
  for (std::size_t i = 0; i < corners.size() && i < 8; ++i) account(corners[i]);
  for (int i = 0; i < samples; ++i) {
    bool ok = false;
    const Point t = randomInside(box, rng, ok);
    if (ok) account(t);
  }
  for (int k = 0; k < 6; ++k) {
    if (best[k].t.size() == 0) continue;
    best[k] = patternSearch(box, u, k, 1.0, best[k], true, u.count() > 0, evaluations);
  }
  return best;
}

/// Maxima over the domain and the geometries, per component, with where they were found.
struct Maxima {
  std::array<Candidate, 6> best;
  long evaluations = 0;
};

/// Local search over the vertices of the geometry box at a point t, from the vertex g: moves that flip one coordinate
/// between its bounds, two coordinates of the same leg (one of its base anchor, one of its platform anchor: together
/// they turn the leg) or a whole anchor, taken while they raise (sign +1) or lower (-1) f_k. f_k is not smooth where
/// some J_kj changes sign, and there single flips can miss the extreme by a few percent.
inline Candidate vertexSearch(const PoseMap& map, const Uncertainty& u, const Point& t, int k, double sign, Geometry g,
                              std::vector<Placement>& scratch, int passes = 6) {
  std::vector<std::vector<int>> moves;
  for (int p = 0; p < u.count(); ++p) moves.push_back({p});
  for (int p = 0; p < u.count(); ++p)
    for (int q = p + 1; q < u.count(); ++q) {
      const Coordinate &a = u.coords[p], &b = u.coords[q];
      if (a.kind == 0 && b.kind == 1 && a.leg == b.leg) moves.push_back({p, q});
    }
  for (int kind = 0; kind < 2; ++kind)
    for (int leg = 0; leg < 6; ++leg) {
      std::vector<int> anchor;
      for (int p = 0; p < u.count(); ++p)
        if (u.coords[p].kind == kind && u.coords[p].leg == leg) anchor.push_back(p);
      if (anchor.size() > 1) moves.push_back(anchor);
    }
  Candidate best{t, g, valueAt(map, u, t, g, k, scratch)};
  for (int pass = 0; pass < passes; ++pass) {
    bool improved = false;
    for (const std::vector<int>& move : moves) {
      Geometry f = best.g;
      for (const int p : move) f[p] = f[p] == u.hi(p) ? u.lo(p) : u.hi(p);
      const double w = valueAt(map, u, t, f, k, scratch);
      if (sign * w > sign * best.value) {
        best.g = f;
        best.value = w;
        improved = true;
      }
    }
    if (!improved) break;
  }
  return best;
}

/// The best vertex for every f_k at t by the linearisation of J in the geometry: with J_kj(g) ~ J_kj(g0) + sum_p
/// D_pj (g_p - g0_p), f_k = sum_j |J_kj| e_j is the largest of the linear functions sum_j s_j e_j J_kj(g) over the sign
/// patterns s, each maximised at the vertex of the signs of sum_j s_j e_j D_pj: those 64 vertices are evaluated
/// exactly and the best is kept (the gradient's vertex is the one of s = sign J_k(g0); where some J_kj is small against
/// its change over the geometry box, another pattern wins).
inline std::array<Candidate, 6> linearizedMaxima(const PoseMap& map, const Uncertainty& u, const Point& t,
                                                 std::vector<Placement>& scratch) {
  std::array<Candidate, 6> best;
  for (Candidate& b : best) b.t = t;
  map.poses(t, scratch);
  if (scratch.empty() || u.count() == 0) return best;
  const Placement x = scratch.front();
  auto jacobian = [&](const Geometry& g) -> Eigen::Matrix<double, 6, 6> {
    return inverseJacobian<double>(u.at(g), x).inverse();
  };
  const Geometry g0 = u.centre();
  std::vector<Eigen::Matrix<double, 6, 6>> d(u.count());
  for (int p = 0; p < u.count(); ++p) {
    Geometry plus = g0, minus = g0;
    const double step = 1e-3 * u.coords[p].half;
    plus[p] += step;
    minus[p] -= step;
    d[p] = (jacobian(plus) - jacobian(minus)) * (u.coords[p].half / (2.0 * step));
  }
  for (int k = 0; k < 6; ++k) {
    for (int pattern = 0; pattern < 64; ++pattern) {
      Geometry g(u.count());
      for (int p = 0; p < u.count(); ++p) {
        double slope = 0.0;
        for (int j = 0; j < 6; ++j) slope += ((pattern >> j) & 1 ? 1.0 : -1.0) * u.nominal.sensor[j] * d[p](k, j);
        g[p] = slope >= 0.0 ? u.hi(p) : u.lo(p);
      }
      const double v = valueAt(map, u, t, g, k, scratch);
      if (v > best[k].value) {
        best[k].g = g;
        best[k].value = v;
      }
    }
  }
  return best;
}

/// Iterated vertex search from a local extreme `start` at its point: `kicks` times, flip a random subset of the
/// coordinates whose single flips change f_k least (they interact most: several of them flipped together can raise
/// f_k by percents where none alone does), search again from there and keep the better vertex.
template <typename Rng>
Candidate kickSearch(const PoseMap& map, const Uncertainty& u, int k, double sign, Candidate start, int kicks, Rng& rng,
                     std::vector<Placement>& scratch) {
  if (u.count() < 2) return start;
  for (int kick = 0; kick < kicks; ++kick) {
    std::vector<std::pair<double, int>> change;
    for (int p = 0; p < u.count(); ++p) {
      Geometry f = start.g;
      f[p] = f[p] == u.hi(p) ? u.lo(p) : u.hi(p);
      change.push_back({std::abs(valueAt(map, u, start.t, f, k, scratch) - start.value), p});
    }
    std::sort(change.begin(), change.end());
    const int pool = std::min<int>(u.count(), 12);
    Geometry g = start.g;
    int flipped = 0;
    for (int i = 0; i < pool; ++i) {
      if (rng() % 3u != 0u) continue;
      const int p = change[i].second;
      g[p] = g[p] == u.hi(p) ? u.lo(p) : u.hi(p);
      ++flipped;
    }
    if (flipped < 2) continue;
    const Candidate c = vertexSearch(map, u, start.t, k, sign, g, scratch, 3);
    if (sign * c.value > sign * start.value) start = c;
  }
  return start;
}

/// The vertex of the geometry box that the signs of d f_k / d g at (t, g) point to (central differences; sign +1:
/// raising f_k, -1: lowering it).
inline Geometry signVertex(const PoseMap& map, const Uncertainty& u, const Point& t, const Geometry& g, int k,
                           double sign, std::vector<Placement>& scratch) {
  Geometry out(g.size());
  for (int p = 0; p < u.count(); ++p) {
    Geometry plus = g, minus = g;
    const double step = 1e-3 * u.coords[p].half;
    plus[p] += step;
    minus[p] -= step;
    const double d = valueAt(map, u, t, plus, k, scratch) - valueAt(map, u, t, minus, k, scratch);
    out[p] = sign * d >= 0.0 ? u.hi(p) : u.lo(p);
  }
  return out;
}

template <typename Rng>
Maxima searchMaxima(const PoseMap& map, const Uncertainty& u, const SearchSettings& s, Rng& rng) {
  Maxima out;
  std::vector<Placement> scratch;
  // Keep the best few samples of every component as the starts of the pattern searches.
  std::array<std::vector<Candidate>, 6> top;
  auto offer = [&](int k, const Candidate& c) {
    if (!std::isfinite(c.value)) return;
    std::vector<Candidate>& list = top[k];
    if (static_cast<int>(list.size()) >= s.starts && c.value <= list.back().value) return;
    // (One start per point: the same point with another geometry replaces it if better.)
    auto same = std::find_if(list.begin(), list.end(), [&](const Candidate& o) { return o.t == c.t; });
    if (same != list.end()) {
      if (c.value > same->value) *same = c;
    } else {
      list.push_back(c);
    }
    std::sort(list.begin(), list.end(), [](const Candidate& a, const Candidate& b) { return a.value > b.value; });
    if (static_cast<int>(list.size()) > s.starts) list.pop_back();
  };
  auto account = [&](const Point& t, const Geometry& g) {
    const Vec6d f = valuesAt(map, u, t, g, scratch);
    ++out.evaluations;
    for (int k = 0; k < 6; ++k) offer(k, {t, g, f[k]});
  };
  auto someGeometry = [&]() {
    if (u.count() == 0) return Geometry();
    const double r = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
    return r < 0.35 ? u.randomVertex(rng) : r < 0.5 ? u.randomInterior(rng) : u.centre();
  };
  for (const Point& t : map.specialPoints()) {
    account(t, u.centre());
    if (u.count() == 0) continue;
    // (Corners are where the maxima usually are; which corner wins can depend on the geometry.)
    const std::array<Candidate, 6> lin = linearizedMaxima(map, u, t, scratch);
    out.evaluations += 2 * u.count() + 6 * 64;
    for (int k = 0; k < 6; ++k) offer(k, lin[k]);
  }
  for (int i = 0; i < s.samples; ++i) {
    bool ok = false;
    const Point t = randomInside(map, rng, ok);
    if (ok) account(t, someGeometry());
  }
  for (int k = 0; k < 6; ++k) {
    Candidate best;
    for (Candidate c : top[k]) {
      // First the geometry at the start pose (the vertex the gradient's signs point to, flips and the continuous
      // search), then both.
      if (u.count() > 0) {
        const Candidate v = linearizedMaxima(map, u, c.t, scratch)[k];
        out.evaluations += 2 * u.count() + 6 * 64;
        if (v.value > c.value) c = v;
        Candidate w = vertexSearch(map, u, c.t, k, 1.0, c.g, scratch, 3);
        w = kickSearch(map, u, k, 1.0, w, s.kicks, rng, scratch);
        if (w.value > c.value) c = w;
        c = patternSearch(map, u, k, 1.0, c, false, true, s.maxEvaluations / 3);
      }
      c = patternSearch(map, u, k, 1.0, c, true, u.count() > 0, s.maxEvaluations);
      out.evaluations += s.maxEvaluations;
      if (c.value > best.value) best = c;
    }
    out.best[k] = best;
  }
  return out;
}

/// The geometries tried at one pose to find the smallest f_k: the nominal one, random vertices and interior points,
/// and local minima of vertex searches and of the pattern search from several of them. Returns the smallest found (f_k
/// in double).
template <typename Rng>
Candidate minimumOverGeometries(const PoseMap& map, const Uncertainty& u, const Point& t, int k, Rng& rng,
                                int randomVertices = 24, int randomInterior = 8, int searches = 3) {
  std::vector<Placement> scratch;
  Candidate best;
  best.t = t;
  best.value = std::numeric_limits<double>::infinity();
  auto account = [&](const Geometry& g) {
    const double v = valueAt(map, u, t, g, k, scratch);
    if (v < best.value) {
      best.g = g;
      best.value = v;
    }
  };
  account(u.centre());
  if (u.count() == 0) return best;
  std::vector<Geometry> starts = {signVertex(map, u, t, u.centre(), k, -1.0, scratch)};
  account(starts.back());
  for (int i = 0; i < randomVertices; ++i) {
    starts.push_back(u.randomVertex(rng));
    account(starts.back());
  }
  for (int i = 0; i < randomInterior; ++i) account(u.randomInterior(rng));
  // Vertex searches from a few vertices (the gradient's first), then the continuous search from the best.
  for (int sIdx = 0; sIdx < searches && sIdx < static_cast<int>(starts.size()); ++sIdx) {
    account(vertexSearch(map, u, t, k, -1.0, starts[sIdx], scratch).g);
  }
  Candidate c = best;
  c = patternSearch(map, u, k, -1.0, c, false, true, 600);
  if (c.value < best.value) best = c;
  return best;
}

}  // namespace oracle
}  // namespace test
}  // namespace pkm_accuracy
