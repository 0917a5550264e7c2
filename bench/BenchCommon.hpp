// Helpers shared by the benchmark programs (not installed, not part of the library).
#pragma once

#include <sys/resource.h>

#include <chrono>
#include <random>
#include <string>

#include "pkm_accuracy/core/model/RobotModel.hpp"

namespace pkm_accuracy {
namespace bench {

inline std::string sourceDir() {
  const char* env = std::getenv("PKM_SOURCE_DIR");
  return env ? env : ".";
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

}  // namespace bench
}  // namespace pkm_accuracy
