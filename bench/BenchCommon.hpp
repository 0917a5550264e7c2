// Helpers shared by the benchmark programs (not installed, not part of the library).
#pragma once

#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <random>
#include <string>
#include <vector>

#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/core/model/RobotModel.hpp"

namespace pkm_accuracy {
namespace bench {

inline std::string sourceDir() {
  const char* env = std::getenv("PKM_SOURCE_DIR");
  return env ? env : ".";
}

/// The 1, 5 and 15 minute load averages (Linux /proc/loadavg; "?" elsewhere): timings are only comparable when the
/// machine was otherwise idle.
inline std::string loadAverage() {
  std::FILE* f = std::fopen("/proc/loadavg", "r");
  if (!f) return "?";
  double a = 0, b = 0, c = 0;
  const int got = std::fscanf(f, "%lf %lf %lf", &a, &b, &c);
  std::fclose(f);
  if (got != 3) return "?";
  char text[64];
  std::snprintf(text, sizeof text, "%.2f %.2f %.2f", a, b, c);
  return text;
}

/// Peak resident set size of this process so far (MiB).
inline double peakRssMiB() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;
}

inline DVec randomPoint(const IVec& box, std::mt19937_64& rng) {
  DVec p(box.size());
  for (int i = 0; i < box.size(); ++i) {
    std::uniform_real_distribution<double> u(box[i].lower(), box[i].upper());
    p[i] = box[i].isPoint() ? box[i].lower() : u(rng);
  }
  return p;
}

inline IVec subBox(const IVec& box, const DVec& centre, double fraction) {
  IVec s(box.size());
  for (int i = 0; i < box.size(); ++i) {
    const double h = 0.5 * fraction * (box[i].upper() - box[i].lower());
    s[i] = Interval(std::max(box[i].lower(), centre[i] - h), std::min(box[i].upper(), centre[i] + h));
  }
  return s;
}

/// Sampled range [min, max] of every component over a box (random points + corners).
inline void sampledRange(const model::RobotModel& robot, const IVec& box, int samples, DVec& lo, DVec& hi) {
  std::mt19937_64 rng(42);
  lo = DVec::Constant(robot.dof(), 1e300);
  hi = DVec::Zero(robot.dof());
  auto account = [&](const DVec& q) {
    const DVec f = robot.worstErrorAt(q);
    lo = lo.cwiseMin(f);
    hi = hi.cwiseMax(f);
  };
  for (int s = 0; s < samples; ++s) account(randomPoint(box, rng));
  for (int c = 0; c < (1 << box.size()); ++c) {
    DVec q(box.size());
    for (int i = 0; i < box.size(); ++i) q[i] = (c >> i) & 1 ? box[i].upper() : box[i].lower();
    account(q);
  }
}

/// Maxima over poses AND admissible geometries of a Gough platform whose 36 anchor coordinates are each known to
/// +-h (sampled in double: lower estimates of the true maxima, not certified). See sampledMaximaOverGeometry().
struct GeometryMaxima {
  static constexpr int kParams = 36;  ///< base_anchors[0..5].xyz, then platform_anchors[0..5].xyz
  using Offsets = std::array<double, kParams>;
  DVec hi;                       ///< per component: the largest f_k found
  std::vector<DVec> pose;        ///< per component: the pose where it was found
  std::vector<Offsets> offsets;  ///< per component: the anchor offsets (each +-h, or 0 when h = 0) used there
  long evaluations = 0;          ///< f evaluations (one double J^-1 inversion each)
  int poses = 0;                 ///< poses sampled
};

/// The nominal geometry with anchor offsets applied (and no uncertainty).
inline model::GoughGeometry offsetGeometry(const model::GoughGeometry& nominal, const GeometryMaxima::Offsets& d) {
  model::GoughGeometry g = nominal;
  g.setUniformAnchorUncertainty(0.0);
  for (int p = 0; p < GeometryMaxima::kParams; ++p) {
    const int q = p % 18;
    (p < 18 ? g.base_anchors : g.platform_anchors)[q / 3][q % 3] += d[p];
  }
  return g;
}

/// sum_j |J_kj| e_j at a pose for the geometry nominal + d (double; +inf components if singular there).
inline DVec worstErrorWithOffsets(const model::GoughGeometry& nominal, const GeometryMaxima::Offsets& d,
                                  const DVec& pose) {
  try {
    return model::GoughPlatform(offsetGeometry(nominal, d)).worstErrorAt(pose);
  } catch (const std::exception&) {
    return DVec::Constant(6, 1e300);
  }
}

/// Maxima over the pose box and over every geometry with each anchor coordinate in nominal +- h, sampled in
/// double. Poses: the 2^6 corners of the box and `randomPoses` random poses. Per pose and component k: f_k at the
/// geometry vertex given by the signs of the central differences (step h, i.e. the secant across each range) of
/// f_k with respect to the 36 anchor coordinates, and at `randomVertices` random vertices. Then, per component,
/// the best `refine` (pose, vertex) pairs are improved by flipping one coordinate at a time while f_k increases.
/// (f_k is smooth in the geometry where no J_kj changes sign and nearly affine over +-1 mm, so its maximum over
/// the geometry box is at or next to a vertex.) h = 0: the plain sampled maxima.
inline GeometryMaxima sampledMaximaOverGeometry(const model::GoughGeometry& nominal, double h, const IVec& box,
                                                int randomPoses, int randomVertices = 8, int refine = 8) {
  using Offsets = GeometryMaxima::Offsets;
  constexpr int kP = GeometryMaxima::kParams;
  const int n = 6;
  GeometryMaxima out;
  out.hi = DVec::Zero(n);
  out.pose.assign(n, DVec::Zero(box.size()));
  out.offsets.assign(n, Offsets{});
  std::mt19937_64 rng(7);
  std::vector<DVec> poses;
  for (int c = 0; c < (1 << box.size()); ++c) {
    DVec q(box.size());
    for (int i = 0; i < box.size(); ++i) q[i] = (c >> i) & 1 ? box[i].upper() : box[i].lower();
    poses.push_back(q);
  }
  for (int s = 0; s < randomPoses; ++s) poses.push_back(randomPoint(box, rng));
  out.poses = static_cast<int>(poses.size());

  struct Candidate {
    double value;
    int pose;
    Offsets d;
  };
  std::vector<std::vector<Candidate>> best(n);
  auto eval = [&](const Offsets& d, const DVec& q) {
    ++out.evaluations;
    return worstErrorWithOffsets(nominal, d, q);
  };
  auto account = [&](int pi, const Offsets& d, const DVec& f) {
    for (int k = 0; k < n; ++k) {
      if (!(f[k] < 1e299)) continue;
      if (f[k] > out.hi[k]) {
        out.hi[k] = f[k];
        out.pose[k] = poses[pi];
        out.offsets[k] = d;
      }
      std::vector<Candidate>& b = best[k];
      if (static_cast<int>(b.size()) < refine || f[k] > b.back().value) {
        b.push_back({f[k], pi, d});
        std::sort(b.begin(), b.end(), [](const Candidate& x, const Candidate& y) { return x.value > y.value; });
        if (static_cast<int>(b.size()) > refine) b.pop_back();
      }
    }
  };
  std::bernoulli_distribution coin(0.5);
  for (int pi = 0; pi < out.poses; ++pi) {
    const DVec& q = poses[pi];
    const Offsets zero{};
    if (!(h > 0.0)) {
      account(pi, zero, eval(zero, q));
      continue;
    }
    std::array<DVec, kP> slope;
    for (int p = 0; p < kP; ++p) {
      Offsets plus{}, minus{};
      plus[p] = h;
      minus[p] = -h;
      slope[p] = eval(plus, q) - eval(minus, q);
    }
    for (int k = 0; k < n; ++k) {
      Offsets v{};
      for (int p = 0; p < kP; ++p) v[p] = slope[p][k] >= 0.0 ? h : -h;
      account(pi, v, eval(v, q));
    }
    for (int r = 0; r < randomVertices; ++r) {
      Offsets v{};
      for (int p = 0; p < kP; ++p) v[p] = coin(rng) ? h : -h;
      account(pi, v, eval(v, q));
    }
  }
  if (h > 0.0) {
    for (int k = 0; k < n; ++k) {
      const std::vector<Candidate> start = best[k];
      for (const Candidate& c : start) {
        Offsets v = c.d;
        double value = c.value;
        for (bool improved = true; improved;) {
          improved = false;
          for (int p = 0; p < kP; ++p) {
            Offsets w = v;
            w[p] = -w[p];
            const DVec f = eval(w, poses[c.pose]);
            account(c.pose, w, f);
            if (f[k] < 1e299 && f[k] > value) {
              value = f[k];
              v = w;
              improved = true;
            }
          }
        }
      }
    }
  }
  return out;
}

}  // namespace bench
}  // namespace pkm_accuracy
