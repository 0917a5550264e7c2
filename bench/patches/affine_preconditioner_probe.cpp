// Session 35 (bench/RESULTS.md *Session 35*): on the boxes a `PKM_DUMP` run enclosed at depths [d0, d1] (every
// `every`-th; session35_oracles.patch), the largest row-sum norm over 300 sampled poses (64 corners) of
// S(t) = C0 J^-1(t) - I (the expansion's constant preconditioner C0 = J^-1(t0)^-1) and of E'(t) = C(t) J^-1(t) - I with
// the affine preconditioner C(t) = C0 - sum_i (t_i - t0_i) C0 G_i C0 (G_i = dJ^-1/dt_i at t0, central differences).
// Double precision, a measurement only. Build as increase_probe.cpp. Usage: affine_preconditioner_probe DUMP d0 d1
// every
#include <Eigen/Dense>
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include "BenchCommon.hpp"
#include "DumpedBoxes.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/io/RobotFile.hpp"
using namespace pkm_accuracy;
int main(int argc, char** argv) {
  const int d0 = std::atoi(argv[2]), d1 = std::atoi(argv[3]), every = std::atoi(argv[4]);
  const io::RobotFile rf = io::loadRobotFile("config/ref6.yaml");
  const model::GoughPlatform robot(rf.geometry);
  std::vector<double> nS, nE;
  std::mt19937_64 rng(5);
  for (const bench::DumpedBox& dumped : bench::readDumpedBoxes(argv[1], d0, d1, every)) {
    const IVec& box = dumped.box;
    DVec t0(6);
    for (int i = 0; i < 6; ++i) t0[i] = box[i].mid();
    const DMat A0 = robot.inverseJacobian(t0);
    const DMat C0 = A0.inverse();
    DMat G[6];
    for (int i = 0; i < 6; ++i) {
      const double st = 1e-6;
      DVec a = t0, b = t0;
      a[i] += st;
      b[i] -= st;
      G[i] = (robot.inverseJacobian(a) - robot.inverseJacobian(b)) / (2 * st);
    }
    double mS = 0, mE = 0;
    for (int k = 0; k < 300; ++k) {
      DVec t = bench::randomPoint(box, rng);
      if (k < 64)
        for (int i = 0; i < 6; ++i) t[i] = (k >> i) & 1 ? box[i].upper() : box[i].lower();
      const DMat Ji = robot.inverseJacobian(t);
      DMat Ct = C0;
      for (int i = 0; i < 6; ++i) Ct -= (t[i] - t0[i]) * C0 * G[i] * C0;
      const DMat S = C0 * Ji - DMat::Identity(6, 6);
      const DMat E = Ct * Ji - DMat::Identity(6, 6);
      mS = std::max(mS, S.cwiseAbs().rowwise().sum().maxCoeff());
      mE = std::max(mE, E.cwiseAbs().rowwise().sum().maxCoeff());
    }
    nS.push_back(mS);
    nE.push_back(mE);
  }
  auto med = [](std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v[size_t(q * (v.size() - 1))];
  };
  std::printf("boxes %zu  max_t ||S(t)||inf med %.3f q90 %.3f | max_t ||E'(t)||inf med %.3f q90 %.3f\n", nS.size(),
              med(nS, .5), med(nS, .9), med(nE, .5), med(nE, .9));
}
