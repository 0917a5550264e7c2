// Shared by the trajectory tests (core, io, CLI): the reference robot's worst error along a trajectory, densely
// sampled in double precision (the oracle of the verifier's answers), and the rotation matrix of a pose.
#pragma once

#include <limits>
#include <vector>

#include <Eigen/Geometry>

#include "TestRobots.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/PiecewiseTrajectory.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"

namespace pkm_accuracy {
namespace test {

/// The reference robot (config/ref6.yaml).
inline const model::GoughPlatform& ref6() {
  static const model::GoughPlatform robot(ref6File().geometry);
  return robot;
}

/// The reference robot's worst error at a pose (double precision; +inf at a singular pose).
inline DVec worstError(const DVec& pose) {
  try {
    return ref6().worstErrorAt(pose);
  } catch (const SingularMatrix&) {
    return DVec::Constant(6, std::numeric_limits<double>::infinity());
  }
}

/// Dense sampling of the worst error along a trajectory (n equally spaced times, double precision).
struct Sampled {
  DVec max = DVec::Zero(6);
  std::vector<double> at = std::vector<double>(6, 0.0);  ///< the time of each maximum
};

inline Sampled sample(const domain::PiecewiseTrajectory& traj, int n) {
  Sampled s;
  for (int i = 0; i < n; ++i) {
    const double t = traj.startTime() + (traj.endTime() - traj.startTime()) * i / (n - 1);
    const DVec f = worstError(traj.pointAtTime(t).pose);
    for (int k = 0; k < 6; ++k) {
      if (f[k] > s.max[k]) {
        s.max[k] = f[k];
        s.at[k] = t;
      }
    }
  }
  return s;
}

/// Rz(yaw) Ry(pitch) Rx(roll) of a pose (x, y, z, roll, pitch, yaw).
inline Eigen::Matrix3d rotation(const DVec& pose) {
  return (Eigen::AngleAxisd(pose[5], Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pose[4], Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(pose[3], Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace test
}  // namespace pkm_accuracy
