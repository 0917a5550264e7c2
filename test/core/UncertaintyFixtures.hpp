// Shared helpers of the geometric-uncertainty tests (docs/uncertainty.md): an uncertain robot as the tests see it
// (the model under test and, independently, the admissible box nominal +- h of every uncertain anchor or tool
// coordinate, with double evaluations of the error at concrete geometries), sampling of poses x geometries, and the
// pose boxes the tests share.
//
// The evidence is independent of the code under test: admissible geometries are built here as plain GoughGeometry
// values (nominal +- h per coordinate, in the documented parameter order), the worst error at a pose and a geometry
// is computed in MPFR (200 bits) or in double with a relative margin of 1e-12, and the worst geometries are found
// here by the signs of central finite differences of f_k with respect to the anchor coordinates (the "worst
// vertex", refined by single-coordinate flips where f_k is not smooth), plus random vertices and interior points of
// the uncertainty box.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "TestRobots.hpp"
#include "pkm_accuracy/core/domain/Workspace.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/core/model/RobotModel.hpp"

namespace pkm_accuracy {
namespace test {
namespace uncertainty {

// ---- admissible geometries, built here ------------------------------------------------------------------------------
using Geometry = std::vector<double>;  ///< one value per geometry parameter

/// The coordinates with a non-zero half-width, in the documented parameter order: base anchors leg-major x, y, z,
/// then platform anchors, then the tool point; each with its nominal value and half-width.
struct Coordinate {
  int kind;  // 0 base, 1 platform, 2 tool
  int leg, axis;
  double nominal, half;
};

inline std::vector<Coordinate> uncertainCoordinates(const model::GoughGeometry& g) {
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

inline model::GoughGeometry withUncertainty(double h) {
  model::GoughGeometry g = test::ref6File().geometry;
  g.setUniformAnchorUncertainty(h);
  return g;
}

/// A box of `fraction` of every width of `ws`, at a random place inside it (fraction 0: a single pose).
inline IVec randomSubBox(const IVec& ws, double fraction, std::mt19937_64& rng) {
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
inline void centresAndHalfWidths(const model::RobotModel& robot, std::vector<double>& gc, std::vector<double>& gh) {
  const int params = robot.geometryParameterCount();
  gc.assign(params, 0.0);
  gh.assign(params, 0.0);
  for (int p = 0; p < params; ++p) {
    gc[p] = robot.geometryParameterCentre(p);
    gh[p] = (robot.geometryParameterRange(p) - Interval(gc[p])).mag();
  }
}

inline DVec randomVertexOf(const IVec& box, std::mt19937_64& rng) {
  DVec q(box.size());
  for (int i = 0; i < box.size(); ++i) q[i] = (rng() & 1u) ? box[i].upper() : box[i].lower();
  return q;
}

inline IVec thinOf(const DVec& q) {
  IVec t(q.size());
  for (int i = 0; i < q.size(); ++i) t[i] = Interval(q[i]);
  return t;
}

inline std::string where(const DVec& q) {
  std::string s = "pose (";
  for (int i = 0; i < q.size(); ++i) s += (i ? ", " : "") + std::to_string(q[i]);
  return s + ")";
}

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
inline std::vector<Geometry> sampleGeometries(const Uncertain& u, const DVec& q, std::mt19937_64& rng, bool refine) {
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

inline Sampled sample(const Uncertain& u, const IVec& box, int randomPoses, std::uint64_t seed) {
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

/// The sub-box of `paper` with `fraction` of every width at its (+x, +y, +z, +angles) vertex. The error maxima of
/// `paper` are at its vertices (sampled: each component's maximum over the 1/16 corner box is 74-91% of its maximum
/// over `paper`, h = 0.5 and 1 mm), and the maxima over the corner box are at vertices of the box too, where the
/// search must close its bounds: a small problem with the structure of the whole one.
inline IVec cornerBox(double fraction) {
  const IVec paper = test::ref6File().workspaces.at("paper").initialBox();
  IVec box(6);
  for (int i = 0; i < 6; ++i) {
    const double w = (paper[i].upper() - paper[i].lower()) * fraction;
    box[i] = Interval(paper[i].upper() - w, paper[i].upper());
  }
  return box;
}

/// The box of the centred 1/16 paper sub-box at h = 1 mm where two of the problems that the UncertaintyRegression tests
/// reproduce showed, as the enclosures see it (ReproducerBox::in).
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

/// The ref6 `paper` pose box of the given half-widths (m, rad) at the vertex (+x, +y, -z, +roll, -pitch, -yaw),
/// where the pitch error is largest (sampled, h = 1 mm).
inline IVec pitchCorner(double position, double angle) {
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

}  // namespace uncertainty
}  // namespace test
}  // namespace pkm_accuracy
