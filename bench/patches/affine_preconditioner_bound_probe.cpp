// Session 35 (bench/RESULTS.md *Session 35*): a plain rigorous-style bound of the affine-preconditioned expansion
// y = J e_j = N' C(t) e_j, N' = (C(t) J^-1(t))^-1, C(t) = C0 - sum_i (t_i - t0_i) C0 G_i C0, on the dumped boxes:
// J^-1(t) by its second-order Taylor form with the model's interval Hessian over the box, E' = C(t) J^-1(t) - I bounded
// in magnitude term by term (pairs of pose variables summed), the form's radius |E' v(t)| + |E'| |E'| z against the
// radius of AffineInverseAction's form of the same columns and against the sampled nonlinearity of J's columns.
// Double precision (a measurement, not a bound). Build as increase_probe.cpp.
// Usage: affine_preconditioner_bound_probe DUMP d0 d1 every
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
static DMat midOf(const IMat& a) {
  DMat m(a.rows(), a.cols());
  for (int r = 0; r < a.rows(); ++r)
    for (int c = 0; c < a.cols(); ++c) m(r, c) = a(r, c).mid();
  return m;
}
static DMat radOf(const IMat& a) {
  DMat m(a.rows(), a.cols());
  for (int r = 0; r < a.rows(); ++r)
    for (int c = 0; c < a.cols(); ++c) m(r, c) = a(r, c).rad();
  return m;
}
int main(int argc, char** argv) {
  const int d0 = std::atoi(argv[2]), d1 = std::atoi(argv[3]), every = std::atoi(argv[4]);
  const io::RobotFile rf = io::loadRobotFile("config/ref6.yaml");
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const model::GoughPlatform robot(rf.geometry);
  std::vector<double> rNewOld, rNewTrue, rOldTrue, rowK;
  std::mt19937_64 rng(5);
  for (const bench::DumpedBox& dumped : bench::readDumpedBoxes(argv[1], d0, d1, every)) {
    const IVec& box = dumped.box;
    enclosure::AffineInverseAction act;
    enclosure::AffineInverseAction::AffineMatrix nv;
    if (!bench::formsOfJacobianColumns(robot, ws, box, act, nv)) continue;
    const DMat C0 = act.preconditioner();
    DVec t0(6), dev(6);
    IVec thin(6);
    for (int i = 0; i < 6; ++i) {
      t0[i] = box[i].mid();
      dev[i] = 0.5 * (box[i].upper() - box[i].lower());
      thin[i] = Interval(t0[i]);
    }
    MatrixHessian hc, hb;
    if (!robot.inverseJacobianHessianAtGeometryCentre(thin, hc, false)) {
      std::printf("no hessian\n");
      return 1;
    }
    if (!robot.inverseJacobianHessianAtGeometryCentre(box, hb, true)) {
      std::printf("no hessian\n");
      return 1;
    }
    const DMat A0 = robot.inverseJacobian(t0);
    DMat G[6], K[6];
    for (int i = 0; i < 6; ++i) {
      G[i] = midOf(hc.first[i]);
      K[i] = C0 * G[i] * C0;
    }
    const DMat E0 = C0 * A0 - DMat::Identity(6, 6);
    DMat L[6];
    for (int m = 0; m < 6; ++m) L[m] = C0 * G[m] - K[m] * A0;
    // Q_im (ordered pairs): -K_i G_m + 1/2 C0 H_im; H = mid +- rad
    DMat Qm[6][6], Qr[6][6];
    for (int i = 0; i < 6; ++i)
      for (int m = 0; m < 6; ++m) {
        const IMat& H = hb.d[MatrixHessian::index(i, m)];
        Qm[i][m] = -K[i] * G[m] + 0.5 * C0 * midOf(H);
        Qr[i][m] = 0.5 * C0.cwiseAbs() * radOf(H);
      }
    DMat magH = DMat::Zero(6, 6);  // sum_{m,l} 1/2 |H_ml| dev_m dev_l
    for (int m = 0; m < 6; ++m)
      for (int l = 0; l < 6; ++l) {
        const IMat& H = hb.d[MatrixHessian::index(m, l)];
        magH += 0.5 * (midOf(H).cwiseAbs() + radOf(H)) * dev[m] * dev[l];
      }
    DMat magE = E0.cwiseAbs();
    for (int m = 0; m < 6; ++m) magE += L[m].cwiseAbs() * dev[m];
    std::array<DMat, MatrixHessian::kPairs> chm, chl, chq;
    const bool haveCH = robot.preconditionedHessianMagnitude(box, C0, chm, &chl, &chq);
    DMat magE2 = magE;
    for (int i = 0; i < 6; ++i)
      for (int m = 0; m < 6; ++m) magE += (Qm[i][m].cwiseAbs() + Qr[i][m]) * dev[i] * dev[m];
    for (int i = 0; i < 6; ++i)
      for (int m = 0; m < 6; ++m) {
        const int p = MatrixHessian::index(i, m);
        magE2 += ((K[i] * G[m]).cwiseAbs() + 0.5 * (chm[p] + chl[p] / 3.0 + chq[p] / 6.0)) * dev[i] * dev[m];
      }
    for (int i = 0; i < 6; ++i) magE2 += K[i].cwiseAbs() * magH * dev[i];
    static std::vector<double> e2;
    e2.push_back(magE2.rowwise().sum().maxCoeff());
    if (!haveCH) std::printf("no CH\n");
    static std::vector<double> kg;
    {
      DMat t = DMat::Zero(6, 6);
      for (int i = 0; i < 6; ++i)
        for (int m = 0; m < 6; ++m) t += (K[i] * G[m]).cwiseAbs() * dev[i] * dev[m];
      kg.push_back(t.rowwise().sum().maxCoeff());
    }
    if (e2.size() % 50 == 0) {
      auto v = e2;
      std::sort(v.begin(), v.end());
      auto w = kg;
      std::sort(w.begin(), w.end());
      std::printf("  |E'| with affine |C H|: rowsum med %.3f; |K G| part med %.3f\n", v[v.size() / 2], w[w.size() / 2]);
    }
    for (int i = 0; i < 6; ++i) magE += K[i].cwiseAbs() * magH * dev[i];
    // sampled J columns and linearisation error
    DMat trueNL = DMat::Zero(6, 6), maxAbsJ = DMat::Zero(6, 6);
    const DMat J0 = A0.inverse();
    DMat dJ[6];
    for (int i = 0; i < 6; ++i) dJ[i] = -J0 * G[i] * J0;
    for (int k = 0; k < 200; ++k) {
      DVec t = bench::randomPoint(box, rng);
      if (k < 64)
        for (int i = 0; i < 6; ++i) t[i] = (k >> i) & 1 ? box[i].upper() : box[i].lower();
      const DMat J = robot.inverseJacobian(t).inverse();
      DMat lin = J0;
      for (int i = 0; i < 6; ++i) lin += dJ[i] * (t[i] - t0[i]);
      trueNL = trueNL.cwiseMax((J - lin).cwiseAbs());
      maxAbsJ = maxAbsJ.cwiseMax(J.cwiseAbs());
    }
    // new radius per column j: y = J e_j, v(d) = C(d) e_j
    for (int j = 0; j < 6; ++j) {
      const DVec v0 = C0.col(j);
      DVec vmax = v0.cwiseAbs();
      for (int l = 0; l < 6; ++l) vmax += (K[l].col(j)).cwiseAbs() * dev[l];
      DVec ev = E0.cwiseAbs() * vmax;
      for (int m = 0; m < 6; ++m) ev += (L[m].cwiseAbs() * vmax) * dev[m];
      for (int i = 0; i < 6; ++i)
        for (int m = i; m < 6; ++m) {
          const DMat q = i == m ? Qm[i][i] : DMat(Qm[i][m] + Qm[m][i]);
          const DMat qr = i == m ? Qr[i][i] : DMat(Qr[i][m] + Qr[m][i]);
          ev += ((q * v0).cwiseAbs() + qr * v0.cwiseAbs()) * dev[i] * dev[m];
          DVec kv = DVec::Zero(6);
          for (int l = 0; l < 6; ++l) kv += K[l].col(j).cwiseAbs() * dev[l];
          ev += ((q.cwiseAbs() + qr) * kv) * dev[i] * dev[m];
        }
      DVec cub = DVec::Zero(6);
      for (int i = 0; i < 6; ++i) cub += K[i].cwiseAbs() * (magH * vmax) * dev[i];
      ev += cub;
      // z >= |y|: fixed point of z = vmax + |E'| z (iterate)
      DVec z = vmax;
      for (int it = 0; it < 200; ++it) z = vmax + magE * z;
      const DVec R = ev + magE * (magE * z);
      for (int l = 0; l < 6; ++l) {
        rNewOld.push_back(R[l] / nv.radius(l, j));
        if (trueNL(l, j) > 0) {
          rNewTrue.push_back(R[l] / trueNL(l, j));
          rOldTrue.push_back(nv.radius(l, j) / trueNL(l, j));
        }
      }
    }
    rowK.push_back(magE.rowwise().sum().maxCoeff());
  }
  auto med = [](std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[size_t(q * (v.size() - 1))];
  };
  std::printf(
      "boxes %zu |E'|bound rowsum med %.3f | new radius / current radius: q25 %.2f med %.2f q75 %.2f | current/sampled "
      "NL med %.2f | new/sampled NL med %.2f\n",
      rowK.size(), med(rowK, .5), med(rNewOld, .25), med(rNewOld, .5), med(rNewOld, .75), med(rOldTrue, .5),
      med(rNewTrue, .5));
}
