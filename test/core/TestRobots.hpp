// Shared fixtures for the core tests: the reference robots loaded from the project's own config/ copies.
#pragma once

#include <random>
#include <string>

#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/io/RobotFile.hpp"

namespace pkm_accuracy {
namespace test {

inline std::string configPath(const std::string& file) { return std::string(PKM_SOURCE_DIR) + "/config/" + file; }

inline io::RobotFile ref6File() { return io::loadRobotFile(configPath("ref6.yaml")); }
inline io::RobotFile tinyFile() { return io::loadRobotFile(configPath("tiny_fixed_orientation.yaml")); }

/// A uniformly random point of a box (degenerate intervals give their value).
inline DVec randomPoint(const IVec& box, std::mt19937_64& rng) {
  DVec p(box.size());
  for (int i = 0; i < box.size(); ++i) {
    std::uniform_real_distribution<double> u(box[i].lower(), box[i].upper());
    p[i] = box[i].isPoint() ? box[i].lower() : u(rng);
  }
  return p;
}

/// The sub-box of `box` with the same centre and `fraction` of every width.
inline IVec centredSubBox(const IVec& box, double fraction) {
  IVec s(box.size());
  for (int i = 0; i < box.size(); ++i) {
    const double c = box[i].mid(), h = 0.5 * fraction * (box[i].upper() - box[i].lower());
    s[i] = Interval(c - h, c + h);
  }
  return s;
}

/// Whether g lies in [nominal - h, nominal + h] as real numbers: exact, from the rounding error of the difference
/// (TwoSum, round-to-nearest), so that a value an ulp outside is caught.
inline bool withinHalfWidth(double g, double nominal, double h) {
  const auto atMost = [h](double a, double b) {  // a - b <= h exactly
    const double s = a - b, c = -b;
    const double bb = s - a;
    const double err = (a - (s - bb)) + (c - bb);  // a - b = s + err exactly
    return s < h || (s == h && err <= 0.0);
  };
  return atMost(g, nominal) && atMost(nominal, g);
}

inline std::array<Interval, 6> toRanges(const IVec& box) {
  std::array<Interval, 6> r;
  for (int i = 0; i < 6; ++i) r[i] = box[i];
  return r;
}

}  // namespace test
}  // namespace pkm_accuracy
