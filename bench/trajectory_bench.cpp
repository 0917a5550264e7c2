// Certified accuracy along a 100-waypoint trajectory inside the reference robot's `paper` workspace (x, y in
// [-0.15, 0.15] m, z in [0.45, 0.50] m, angles in [-15, 15] deg): thresholds 5% above the maxima sampled at 10^5
// times (plus every waypoint); prints the verdict, boxes and seconds (median of `repeats` runs) per interpolation,
// enclosure method and thread count. Target: <= 100 ms. Then a tilted-frame trajectory and two
// motion varieties (a surface and a volume of poses; no target, recorded in bench/RESULTS.md).
// Usage: trajectory_bench [repeats] (default 5).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "BenchCommon.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/ParametricVariety.hpp"
#include "pkm_accuracy/core/domain/PolynomialTrajectory.hpp"
#include "pkm_accuracy/core/domain/TransformedDomain.hpp"
#include "pkm_accuracy/core/domain/WaypointTrajectory.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"
#include "pkm_accuracy/io/RobotFile.hpp"

using namespace pkm_accuracy;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// 100 waypoints, 0.1 s apart, on a smooth Lissajous-like path that fills the paper workspace, with a small random
/// jitter (fixed seed); every coordinate stays inside its range.
std::vector<domain::WaypointTrajectory::Waypoint> paperWaypoints(int n) {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  const double a = 0.2617993877991494;  // 15 deg
  std::vector<domain::WaypointTrajectory::Waypoint> w;
  for (int i = 0; i < n; ++i) {
    const double s = static_cast<double>(i) / (n - 1);
    domain::WaypointTrajectory::Waypoint p;
    p.t = 0.1 * i;
    const double raw[6] = {0.13 * std::sin(2 * kPi * 3 * s) + 0.01 * jitter(rng),
                           0.13 * std::sin(2 * kPi * 2 * s + 0.5) + 0.01 * jitter(rng),
                           0.475 + 0.02 * std::sin(2 * kPi * 5 * s) + 0.002 * jitter(rng),
                           0.85 * a * std::sin(2 * kPi * 4 * s) + 0.1 * a * jitter(rng),
                           0.85 * a * std::cos(2 * kPi * 3 * s) + 0.1 * a * jitter(rng),
                           0.85 * a * std::sin(2 * kPi * 1 * s + 1.0) + 0.1 * a * jitter(rng)};
    const double lo[6] = {-0.15, -0.15, 0.45, -a, -a, -a}, hi[6] = {0.15, 0.15, 0.50, a, a, a};
    for (int k = 0; k < 6; ++k) p.pose[k] = std::min(std::max(raw[k], lo[k]), hi[k]);
    w.push_back(p);
  }
  return w;
}

/// The waypoints w (base frame) expressed in the frame whose pose in the base frame is t, in double:
/// p_F = R^T (p - t.translation), R_F = R^T R.
std::vector<domain::WaypointTrajectory::Waypoint> inFrame(std::vector<domain::WaypointTrajectory::Waypoint> w,
                                                          const domain::RigidTransform& t) {
  for (auto& p : w) {
    const Eigen::Vector3d x =
        t.rotation.transpose() * (Eigen::Vector3d(p.pose[0], p.pose[1], p.pose[2]) - t.translation);
    const Eigen::Matrix3d r = t.rotation.transpose() * (Eigen::AngleAxisd(p.pose[5], Eigen::Vector3d::UnitZ()) *
                                                        Eigen::AngleAxisd(p.pose[4], Eigen::Vector3d::UnitY()) *
                                                        Eigen::AngleAxisd(p.pose[3], Eigen::Vector3d::UnitX()))
                                                           .toRotationMatrix();
    p.pose = {x.x(),
              x.y(),
              x.z(),
              std::atan2(r(2, 1), r(2, 2)),
              std::atan2(-r(2, 0), std::hypot(r(0, 0), r(1, 0))),
              std::atan2(r(1, 0), r(0, 0))};
  }
  return w;
}

DVec sampledMax(const model::RobotModel& robot, const domain::PiecewiseTrajectory& traj, int samples) {
  DVec best = DVec::Zero(6);
  auto account = [&](double t) {
    const DVec f = robot.worstErrorAt(traj.pointAtTime(t).pose);
    best = best.cwiseMax(f);
  };
  for (int i = 0; i < samples; ++i) account(traj.startTime() + (traj.endTime() - traj.startTime()) * i / (samples - 1));
  for (double t : traj.times()) account(t);
  return best;
}

/// Maxima of the worst error over a grid of n points per parameter of a variety.
DVec sampledMax(const model::RobotModel& robot, const domain::ParametricVariety& v, int n) {
  const int m = v.variables();
  DVec best = DVec::Zero(6), t(m), pose;
  DMat jac;
  std::vector<int> idx(static_cast<std::size_t>(m), 0);
  while (true) {
    for (int i = 0; i < m; ++i) t[i] = static_cast<double>(idx[static_cast<std::size_t>(i)]) / (n - 1);
    v.pointAt(t, pose, jac);
    best = best.cwiseMax(robot.worstErrorAt(pose));
    int i = 0;
    while (i < m && ++idx[static_cast<std::size_t>(i)] == n) idx[static_cast<std::size_t>(i++)] = 0;
    if (i == m) break;
  }
  return best;
}

/// A monomial c u^a v^b w^c.
domain::ParametricVariety::Monomial mono(double c, int a, int b, int d = 0) {
  domain::ParametricVariety::Monomial x;
  x.coefficient = c;
  x.exponents[0] = a;
  x.exponents[1] = b;
  x.exponents[2] = d;
  return x;
}

void scenario(const char* name, const model::RobotModel& robot, const domain::Domain& traj, const DVec& thresholds,
              const std::string& method, int threads, int repeats) {
  verify::VerifierOptions o;
  o.thresholds = thresholds;
  o.method = method;
  o.threads = threads;
  o.time_limit_s = 60.0;
  std::vector<double> seconds;
  verify::VerifierResult r;
  for (int i = 0; i < repeats; ++i) {
    r = verify::Verifier::run(robot, traj, o);
    seconds.push_back(r.stats.seconds);
  }
  std::sort(seconds.begin(), seconds.end());
  std::printf("%-34s %-13s %3d %-10s %8zu %12.4f %12.4f %8.1f\n", name, method.c_str(), r.stats.threads,
              verify::toString(r.verdict).c_str(), r.stats.boxes, seconds[seconds.size() / 2], seconds.front(),
              1e6 * seconds[seconds.size() / 2] / std::max<std::size_t>(1, r.stats.boxes));
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  const io::RobotFile ref = io::loadRobotFile(bench::sourceDir() + "/config/ref6.yaml");
  const model::GoughPlatform robot(ref.geometry);
  const auto w = paperWaypoints(100);
  const domain::WaypointTrajectory slerp(w, domain::WaypointTrajectory::Interpolation::Slerp);
  const domain::WaypointTrajectory linear(w, domain::WaypointTrajectory::Interpolation::LinearRpy);

  std::printf(
      "100 waypoints over %.1f s inside `paper`; thresholds = 1.05 x maxima sampled at 1e5 times + waypoints; "
      "median of %d runs\n",
      slerp.endTime(), repeats);
  std::printf("%-34s %-13s %3s %-10s %8s %12s %12s %8s\n", "trajectory", "method", "thr", "verdict", "boxes",
              "median s", "best s", "us/box");
  for (const auto* t : {&slerp, &linear}) {
    const char* name = t == &slerp ? "100 waypoints, slerp, +5%" : "100 waypoints, linear_rpy, +5%";
    const DVec max = sampledMax(robot, *t, 100000);
    for (const std::string& method : {std::string("second_order"), std::string("mean_value")}) {
      for (int threads : {1, 2}) scenario(name, robot, *t, max * 1.05, method, threads, repeats);
    }
  }
  // The slerp trajectory with its waypoints given in a tilted frame (translated, roll -0.05, pitch 0.1, yaw 0.3): the
  // same base-frame trajectory (slerp and linear positions do not depend on the frame), through
  // domain::TransformedDomain, at the same thresholds.
  const domain::RigidTransform tilted =
      domain::RigidTransform::fromTranslationRpy(Eigen::Vector3d(0.02, -0.01, 0.1), -0.05, 0.1, 0.3);
  const domain::TransformedDomain framed(std::make_unique<domain::WaypointTrajectory>(
                                             inFrame(w, tilted), domain::WaypointTrajectory::Interpolation::Slerp),
                                         tilted);
  const DVec max = sampledMax(robot, slerp, 100000);
  for (int threads : {1, 2}) {
    scenario("100 waypoints, slerp, tilted frame", robot, framed, max * 1.05, "second_order", threads, repeats);
  }
  // Motion varieties inside `paper`: a curved 0.24 m x 0.24 m surface with the orientation varying over +-0.2 rad,
  // and a 3-parameter volume of poses (a 0.2 m x 0.2 m x 0.04 m block with the yaw turning along w and roll, pitch
  // varying with u v), thresholds 5% above the maxima sampled on 201^2 / 41^3 grids.
  const domain::ParametricVariety surface(2, {{{mono(-0.12, 0, 0), mono(0.24, 1, 0)},
                                               {mono(-0.12, 0, 0), mono(0.24, 0, 1), mono(0.02, 1, 1)},
                                               {mono(0.455, 0, 0), mono(0.04, 2, 0)},
                                               {mono(-0.1, 0, 0), mono(0.2, 0, 1)},
                                               {mono(0.15, 1, 1), mono(-0.05, 0, 0)},
                                               {mono(0.2, 1, 0), mono(-0.2, 0, 2)}}});
  const DVec surfaceMax = sampledMax(robot, surface, 201);
  for (int threads : {1, 2}) {
    scenario("variety: surface (m = 2), +5%", robot, surface, surfaceMax * 1.05, "second_order", threads, repeats);
  }
  const domain::ParametricVariety volume(3, {{{mono(-0.1, 0, 0), mono(0.2, 1, 0)},
                                              {mono(-0.1, 0, 0), mono(0.2, 0, 1)},
                                              {mono(0.455, 0, 0), mono(0.04, 0, 0, 1)},
                                              {mono(0.1, 1, 1), mono(-0.05, 0, 0)},
                                              {mono(-0.1, 1, 1), mono(0.05, 0, 0)},
                                              {mono(-0.2, 0, 0), mono(0.4, 0, 0, 1)}}});
  const DVec volumeMax = sampledMax(robot, volume, 41);
  for (int threads : {1, 2}) {
    scenario("variety: volume (m = 3), +5%", robot, volume, volumeMax * 1.05, "second_order", threads, repeats);
  }
  return 0;
}
