// Session 35 (bench/RESULTS.md *Session 35*): the bounds ssy >= |S S y| and sy >= |S y| of AffineInverseAction
// (exact geometry, the columns y = J C e_j) against their maxima sampled at the 64 corners and 236 random poses of the
// boxes a `PKM_DUMP` run enclosed at depths [d0, d1] (every `every`-th). Build as increase_probe.cpp.
// Usage: ssy_probe DUMP d0 d1 every
#include <Eigen/Dense>
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include "BenchCommon.hpp"
#include "DumpedBoxes.hpp"
#include "pkm_accuracy/core/enclosure/AffineInverseAction.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/io/RobotFile.hpp"
using namespace pkm_accuracy;
int main(int argc, char** argv) {
  const int d0 = std::atoi(argv[2]), d1 = std::atoi(argv[3]), every = std::atoi(argv[4]);
  const io::RobotFile rf = io::loadRobotFile("config/ref6.yaml");
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const model::GoughPlatform robot(rf.geometry);
  std::vector<double> rR1, rR2, rB, rC, rSSY, rSY, rW, sNorm, rS, rS2, radShare;
  std::mt19937_64 rng(5);
  for (const bench::DumpedBox& dumped : bench::readDumpedBoxes(argv[1], d0, d1, every)) {
    const IVec& box = dumped.box;
    enclosure::AffineInverseAction act;
    enclosure::AffineInverseAction::AffineMatrix nv;
    if (!bench::formsOfJacobianColumns(robot, ws, box, act, nv)) continue;
    const DMat& C = act.preconditioner();
    DMat mxS = DMat::Zero(6, 6), mxS2 = DMat::Zero(6, 6);
    DMat mxSSY = DMat::Zero(6, 6), mxSY = DMat::Zero(6, 6);
    for (int sIdx = 0; sIdx < 300; ++sIdx) {
      DVec t = bench::randomPoint(box, rng);
      if (sIdx < 64)
        for (int i = 0; i < 6; ++i) t[i] = (sIdx >> i) & 1 ? box[i].upper() : box[i].lower();
      const DMat Ji = robot.inverseJacobian(t);
      const DMat S = C * Ji - DMat::Identity(6, 6);
      const DMat y = (C * Ji).inverse() * C;
      mxSSY = mxSSY.cwiseMax((S * S * y).cwiseAbs());
      mxSY = mxSY.cwiseMax((S * y).cwiseAbs());
      mxS = mxS.cwiseMax(S.cwiseAbs());
      mxS2 = mxS2.cwiseMax((S * S).cwiseAbs());
      sNorm.push_back(S.cwiseAbs().rowwise().sum().maxCoeff());
    }
    {
      const DMat& mS = act.poseMagnitude();
      const DMat& mS2 = act.poseSquareMagnitude();
      DMat midPart = DMat::Zero(6, 6), radPart = DMat::Zero(6, 6);
      for (int i = 0; i < 6; ++i) {
        midPart += act.poseSlopeMid(i).cwiseAbs() * act.deviation(i);
        radPart += act.poseSlopeRad(i) * act.deviation(i);
      }
      rS.push_back(mS.rowwise().sum().maxCoeff() / mxS.rowwise().sum().maxCoeff());
      rS2.push_back(mS2.rowwise().sum().maxCoeff() / mxS2.rowwise().sum().maxCoeff());
      radShare.push_back(radPart.sum() / (midPart.sum() + radPart.sum()));
    }
    {
      DVec t0(6);
      for (int i = 0; i < 6; ++i) t0[i] = box[i].mid();
      const DMat y0 = (C * robot.inverseJacobian(t0)).inverse() * C;
      DMat qb = DMat::Zero(6, 6), qc = DMat::Zero(6, 6);
      DMat P[6][6];
      for (int i = 0; i < 6; ++i)
        for (int m = 0; m < 6; ++m) {
          P[i][m] = act.poseSlopeMid(i) * (act.poseSlopeMid(m) * y0) * (act.deviation(i) * act.deviation(m));
          qb += P[i][m].cwiseAbs();
        }
      DMat r1 = DMat::Zero(6, 6);
      const DMat ay0 = y0.cwiseAbs();
      DMat magP = DMat::Zero(6, 6);
      for (int i = 0; i < 6; ++i) magP += (act.poseSlopeMid(i).cwiseAbs() + act.poseSlopeRad(i)) * act.deviation(i);
      for (int i = 0; i < 6; ++i)
        for (int m = 0; m < 6; ++m) {
          const DMat& dmi = act.poseSlopeMid(i);
          const DMat& dmm = act.poseSlopeMid(m);
          const DMat& dri = act.poseSlopeRad(i);
          const DMat& drm = act.poseSlopeRad(m);
          r1 += (dri * (dmm * y0).cwiseAbs() + dmi.cwiseAbs() * (drm * ay0) + dri * (drm * ay0)) *
                (act.deviation(i) * act.deviation(m));
        }
      // |y - y0| sampled
      DMat dy = DMat::Zero(6, 6);
      for (int sIdx = 0; sIdx < 100; ++sIdx) {
        DVec t = bench::randomPoint(box, rng);
        if (sIdx < 64)
          for (int i = 0; i < 6; ++i) t[i] = (sIdx >> i) & 1 ? box[i].upper() : box[i].lower();
        dy = dy.cwiseMax(((C * robot.inverseJacobian(t)).inverse() * C - y0).cwiseAbs());
      }
      const DMat r2 = magP * (magP * dy);
      for (int l = 0; l < 6; ++l)
        for (int j = 0; j < 6; ++j)
          if (mxSSY(l, j) > 0) {
            rR1.push_back(r1(l, j) / mxSSY(l, j));
            rR2.push_back(r2(l, j) / mxSSY(l, j));
          }
      for (int vtx = 0; vtx < 64; ++vtx) {
        DMat q = DMat::Zero(6, 6);
        for (int i = 0; i < 6; ++i)
          for (int m = 0; m < 6; ++m)
            q += P[i][m] * ((((vtx >> i) & 1) ? 1.0 : -1.0) * (((vtx >> m) & 1) ? 1.0 : -1.0));
        qc = qc.cwiseMax(q.cwiseAbs());
      }
      for (int l = 0; l < 6; ++l)
        for (int j = 0; j < 6; ++j)
          if (mxSSY(l, j) > 0) {
            rB.push_back(qb(l, j) / mxSSY(l, j));
            rC.push_back(qc(l, j) / mxSSY(l, j));
          }
    }
    for (int l = 0; l < 6; ++l)
      for (int j = 0; j < 6; ++j) {
        if (mxSSY(l, j) > 0) rSSY.push_back(nv.ssy(l, j) / mxSSY(l, j));
        if (mxSY(l, j) > 0) rSY.push_back(nv.sy(l, j) / mxSY(l, j));
        rW.push_back(nv.radius(l, j) / std::max(1e-300, nv.ssy(l, j)));
      }
  }
  auto med = [](std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[size_t(q * (v.size() - 1))];
  };
  std::printf("R1 (slope radii)/sampled med %.2f  R2 (|P||P||y-y0|)/sampled med %.2f\n", med(rR1, .5), med(rR2, .5));
  std::printf("quad magnitude/sampled med %.2f  quad vertex-max/sampled med %.2f q25 %.2f\n", med(rB, .5), med(rC, .5),
              med(rC, .25));
  std::printf("|S|bound/sampled(rowsum) med %.2f  |SS| med %.2f  slope-radius share med %.2f\n", med(rS, .5),
              med(rS2, .5), med(radShare, .5));
  std::printf("|S(t)|inf med %.2f q90 %.2f  ", med(sNorm, .5), med(sNorm, .9));
  std::printf(
      "n %zu  ssy/sampled q25 %.2f med %.2f q75 %.2f | sy/sampled q25 %.2f med %.2f q75 %.2f | radius/ssy med %.2f\n",
      rSSY.size(), med(rSSY, .25), med(rSSY, .5), med(rSSY, .75), med(rSY, .25), med(rSY, .5), med(rSY, .75),
      med(rW, .5));
}
