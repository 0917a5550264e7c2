// Reading trajectory / motion-variety files with yaml-cpp (ROS-free; used by pkm_verify --trajectory, the tests and
// the benchmarks). Format and semantics: docs/trajectories.md. The poses are in the pose coordinates of the robot's
// type (domain::PoseCoordinates, given by the caller: n coordinates q_1 .. q_n named as in its description, e.g.
// x, y, z, roll, pitch, yaw for gough and rus6, x, y, z for delta3, z, tilt_x, tilt_y for prs3). Exactly one of the
// keys waypoints, polynomial_segments, variety:
//
//   interpolation: slerp | linear_rpy | linear  # waypoints only; slerp and linear_rpy (= linear) for the rigid-body
//                                          # pose (default slerp), linear for any type (default for the others)
//   waypoints:                             # >= 2 rows [t, q_1, .., q_n] (s, the coordinates' units), t increasing
//     - [0.0, 0.0, 0.0, 0.47, 0.0, 0.0, 0.0]
//     - [2.0, 0.1, 0.0, 0.47, 0.0, 0.1, 0.0]
//
//   polynomial_segments:                   # tiling [t_0, t_N]; coefficients of tau^0, tau^1, ... (tau = t - start)
//     - t: [0.0, 1.0]                      # and one key per pose coordinate, e.g. for gough:
//       x: [0.0, 0.1]  y: [0.0]  z: [0.47]  roll: [0.0]  pitch: [0.0]  yaw: [0.0, 0.0, 0.3]
//
//   variety:                               # pose as polynomials of m parameters in [0, 1]^m
//     parameters: 2
//     x: [[coefficient, exponent_u, exponent_v], ...]   # one row per monomial; any pose coordinate alike (missing: 0)
//
//   region:                                # optional (pose coordinates with x, y, z): only the part of the motion
//     type: box | cylinder | sphere | polyhedron         # inside is verified
//     x: [min, max]  y: [min, max]  z: [min, max]        # box (and the bounds of a polyhedron)
//     centre: [x, y(, z)]  radius: r  z: [min, max]       # cylinder (z range) / sphere (3-D centre)
//     normals: [[nx, ny, nz], ...]  offsets: [d, ...]     # polyhedron: n . p <= d
//
//   frame:                                 # optional (rigid-body pose only): the poses (and region) are in a frame F
//     translation: [x, y, z]               # placed in the robot's base frame at this translation (m) and rotation
//     rpy: [roll, pitch, yaw]              # Rz(yaw) Ry(pitch) Rx(roll) (rad); both optional (0); verified exactly in
//                                          # the base frame
//
// Unknown keys are errors (a typo must not silently change the problem). Every error is a ParseError whose message
// names the file, the key and the row, e.g. "traj.yaml: waypoints[3][0]: time 1 s is not greater than ...",
// "traj.yaml: waypoints[1]: expected 4 numbers [t, x, y, z] (a time and the 3 pose coordinates of delta3), got 7".
#pragma once

#include <memory>
#include <string>

#include "pkm_accuracy/core/domain/Domain.hpp"
#include "pkm_accuracy/core/domain/ParametricVariety.hpp"
#include "pkm_accuracy/core/domain/PiecewiseTrajectory.hpp"
#include "pkm_accuracy/core/domain/PoseCoordinates.hpp"

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

/// @param pose the pose coordinates of the robot the file is for (default: the rigid-body pose of gough); the
///        domain's poses have pose.size() coordinates.
/// @throws ParseError naming the file, key and row (missing file, YAML syntax, wrong structure, bad values, an
///         interpolation, region or frame the pose coordinates do not allow).
TrajectoryFile loadTrajectoryFile(const std::string& path,
                                  const domain::PoseCoordinates& pose = domain::PoseCoordinates());

/// The same from YAML text; `name` stands for the file name in messages.
TrajectoryFile parseTrajectory(const std::string& yamlText, const std::string& name,
                               const domain::PoseCoordinates& pose = domain::PoseCoordinates());

}  // namespace io
}  // namespace pkm_accuracy
