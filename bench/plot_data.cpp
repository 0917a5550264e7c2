// Data files for the plots of scripts/plots (gnuplot script bench/plots.gp); not a benchmark.
// Usage: plot_data <output_dir> [repo_root]   (repo root also from PKM_SOURCE_DIR; default ".")
//
// Writes into <output_dir>:
//   map_mid.dat    worst error at points of the (x, y) grid of ref6's `paper` workspace, z = mid, angles 0
//   map_tilt.dat   the same at z = max, roll = pitch = yaw = +15 deg
//                  columns: x [mm], y [mm], dx dy dz [um], rx ry rz [mrad]; gnuplot blocks of constant x
//   trajectory.dat worst error at 2000 times along config/trajectory_example.yaml (point evaluation, not certified)
//                  columns: t [s], dx dy dz [um], rx ry rz [mrad]
//   bounds.gp      gnuplot variables: certified max-error bounds over the whole trajectory (Verifier, max-error
//                  mode, alpha 0.01): lo1..lo6 / up1..up6 (um, mrad), the verdict, boxes and seconds; map titles.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <limits>
#include <string>

#include "BenchCommon.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"
#include "pkm_accuracy/io/RobotFile.hpp"
#include "pkm_accuracy/io/TrajectoryFile.hpp"

using namespace pkm_accuracy;

namespace {

constexpr int kGrid = 61;
constexpr int kTrajectorySamples = 2000;

/// Display scale of error component k: position m -> um, rotation rad -> mrad.
double scale(int k) { return k < 3 ? 1e6 : 1e3; }

/// Worst error at a pose in display units; NaN where the model cannot evaluate it (singular pose).
DVec displayError(const model::RobotModel& robot, const DVec& pose) {
  DVec f = DVec::Constant(6, std::numeric_limits<double>::quiet_NaN());
  try {
    const DVec e = robot.worstErrorAt(pose);
    for (int k = 0; k < 6; ++k) f[k] = e[k] * scale(k);
  } catch (const std::exception&) {
  }
  return f;
}

void writeMap(const model::RobotModel& robot, const IVec& box, double z, double angle, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << "# x[mm] y[mm] dx[um] dy[um] dz[um] rx[mrad] ry[mrad] rz[mrad]; z = " << z
      << " m, roll = pitch = yaw = " << angle << " rad\n";
  char line[256];
  for (int i = 0; i < kGrid; ++i) {
    const double x = box[0].lower() + (box[0].upper() - box[0].lower()) * i / (kGrid - 1);
    for (int j = 0; j < kGrid; ++j) {
      const double y = box[1].lower() + (box[1].upper() - box[1].lower()) * j / (kGrid - 1);
      DVec pose(6);
      pose << x, y, z, angle, angle, angle;
      const DVec f = displayError(robot, pose);
      std::snprintf(line, sizeof line, "%.3f %.3f %.6g %.6g %.6g %.6g %.6g %.6g\n", 1e3 * x, 1e3 * y, f[0], f[1], f[2],
                    f[3], f[4], f[5]);
      out << line;
    }
    out << "\n";
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: plot_data <output_dir> [repo_root]\n";
    return 2;
  }
  const std::string dir = argv[1];
  const std::string root = argc > 2 ? argv[2] : bench::sourceDir();
  try {
    const io::RobotFile ref = io::loadRobotFile(root + "/config/ref6.yaml");
    const model::GoughPlatform robot(ref.geometry);
    const IVec& box = ref.workspaces.at("paper").initialBox();

    const double zMid = 0.5 * (box[2].lower() + box[2].upper());
    const double zMax = box[2].upper();
    const double tilt = box[5].upper();  // +15 deg
    writeMap(robot, box, zMid, 0.0, dir + "/map_mid.dat");
    writeMap(robot, box, zMax, tilt, dir + "/map_tilt.dat");

    const io::TrajectoryFile file = io::loadTrajectoryFile(root + "/config/trajectory_example.yaml");
    if (!file.trajectory) throw std::runtime_error("trajectory_example.yaml is not a one-parameter trajectory");
    const domain::PiecewiseTrajectory& traj = *file.trajectory;
    {
      std::ofstream out(dir + "/trajectory.dat");
      if (!out) throw std::runtime_error("cannot write " + dir + "/trajectory.dat");
      out << "# t[s] dx[um] dy[um] dz[um] rx[mrad] ry[mrad] rz[mrad] (" << file.description << ")\n";
      char line[256];
      for (int i = 0; i < kTrajectorySamples; ++i) {
        const double t = traj.startTime() + (traj.endTime() - traj.startTime()) * i / (kTrajectorySamples - 1);
        const DVec f = displayError(robot, traj.pointAtTime(t).pose);
        std::snprintf(line, sizeof line, "%.6f %.6g %.6g %.6g %.6g %.6g %.6g\n", t, f[0], f[1], f[2], f[3], f[4], f[5]);
        out << line;
      }
    }

    verify::VerifierOptions o;
    o.mode = verify::Mode::MaxError;
    o.alpha = 0.01;
    o.time_limit_s = 120.0;
    const verify::VerifierResult r = verify::Verifier::run(robot, traj, o);
    std::ofstream out(dir + "/bounds.gp");
    if (!out) throw std::runtime_error("cannot write " + dir + "/bounds.gp");
    char line[256];
    for (int k = 0; k < 6; ++k) {
      const double lo = r.max_lower.size() == 6 ? r.max_lower[k] * scale(k) : NAN;
      const double up = r.max_upper.size() == 6 ? r.max_upper[k] * scale(k) : NAN;
      std::snprintf(line, sizeof line, "lo%d = %.9g; up%d = %.9g\n", k + 1, lo, k + 1, std::isfinite(up) ? up : NAN);
      out << line;
    }
    std::snprintf(line, sizeof line, "certified = \"to %.0f%%, %zu boxes, %.1f ms\"\n", 100.0 * o.alpha, r.stats.boxes,
                  1e3 * r.stats.seconds);
    out << line;
    std::snprintf(line, sizeof line, "slice_mid = \"z = %.3f m, roll = pitch = yaw = 0\"\n", zMid);
    out << line;
    std::snprintf(line, sizeof line, "slice_tilt = \"z = %.3f m, roll = pitch = yaw = %+.0f deg\"\n", zMax,
                  tilt * 180.0 / 3.14159265358979323846);
    out << line;
    // "\\_": a literal underscore in gnuplot's enhanced text.
    out << "trajectory_name = \"config/trajectory\\\\_example.yaml: " << file.description << "\"\n";
    out << "waypoint_times = \"";
    for (double t : traj.times()) out << t << " ";
    out << "\"\n";
    std::printf("plot_data: wrote %s/{map_mid,map_tilt,trajectory}.dat and bounds.gp (max-error run: %zu boxes)\n",
                dir.c_str(), r.stats.boxes);
    for (int k = 0; k < 6; ++k)
      std::printf("  %-12s certified max in [%.6g, %.6g] %s\n", robot.componentName(k).c_str(),
                  r.max_lower[k] * scale(k), r.max_upper[k] * scale(k), k < 3 ? "um" : "mrad");
  } catch (const std::exception& e) {
    std::cerr << "plot_data: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
