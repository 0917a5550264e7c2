// Reading trajectory / motion-variety files with yaml-cpp (ROS-free; used by pkm_verify --trajectory, the tests and
// the benchmarks). Format and semantics: docs/trajectories.md. Exactly one of the keys waypoints,
// polynomial_segments, variety:
//
//   interpolation: slerp | linear_rpy      # waypoints only (default slerp)
//   waypoints:                             # >= 2 rows [t, x, y, z, roll, pitch, yaw] (s, m, rad), t increasing
//     - [0.0, 0.0, 0.0, 0.47, 0.0, 0.0, 0.0]
//     - [2.0, 0.1, 0.0, 0.47, 0.0, 0.1, 0.0]
//
//   polynomial_segments:                   # tiling [t_0, t_N]; coefficients of tau^0, tau^1, ... (tau = t - start)
//     - t: [0.0, 1.0]
//       x: [0.0, 0.1]  y: [0.0]  z: [0.47]  roll: [0.0]  pitch: [0.0]  yaw: [0.0, 0.0, 0.3]
//
//   variety:                               # pose as polynomials of m parameters in [0, 1]^m
//     parameters: 2
//     x: [[coefficient, exponent_u, exponent_v], ...]   # one row per monomial; y, z, roll, pitch, yaw alike
//
//   region:                                # optional: only the part of the motion inside is verified
//     type: box | cylinder | sphere | polyhedron
//     x: [min, max]  y: [min, max]  z: [min, max]        # box (and the bounds of a polyhedron)
//     centre: [x, y(, z)]  radius: r  z: [min, max]       # cylinder (z range) / sphere (3-D centre)
//     normals: [[nx, ny, nz], ...]  offsets: [d, ...]     # polyhedron: n . p <= d
//
//   frame:                                 # optional: the poses (and region) are in a frame F placed in the robot's
//     translation: [x, y, z]               # base frame at this translation (m) and rotation Rz(yaw) Ry(pitch) Rx(roll)
//     rpy: [roll, pitch, yaw]              # (rad); both optional (0); verified exactly in the base frame
//
// Unknown keys are errors (a typo must not silently change the problem). Every error is a ParseError whose message
// names the file, the key and the row, e.g. "traj.yaml: waypoints[3][0]: time 1 s is not greater than ...".
#pragma once

#include <memory>
#include <string>

#include "pkm_accuracy/core/domain/Domain.hpp"
#include "pkm_accuracy/core/domain/ParametricVariety.hpp"
#include "pkm_accuracy/core/domain/PiecewiseTrajectory.hpp"

namespace pkm_accuracy {
namespace io {

struct TrajectoryFile {
  enum class Kind { Waypoints, Polynomial, Variety };
  Kind kind = Kind::Waypoints;
  /// The domain to verify (never null): the trajectory / variety below, or, with a `frame`, the core's
  /// TransformedDomain of it (its poses in the base frame; the variables are the same).
  std::shared_ptr<const domain::Domain> domain;
  /// The trajectory itself (in the file's frame) as a one-parameter trajectory (Waypoints, Polynomial), else null.
  std::shared_ptr<const domain::PiecewiseTrajectory> trajectory;
  /// The variety itself (in the file's frame) (Variety), else null.
  std::shared_ptr<const domain::ParametricVariety> variety;
  std::string description;  ///< e.g. "waypoints (slerp), 12 waypoints"
  std::string region;       ///< position region type, or "none"
};

/// @throws ParseError naming the file, key and row (missing file, YAML syntax, wrong structure, bad values).
TrajectoryFile loadTrajectoryFile(const std::string& path);

/// The same from YAML text; `name` stands for the file name in messages.
TrajectoryFile parseTrajectory(const std::string& yamlText, const std::string& name);

}  // namespace io
}  // namespace pkm_accuracy
