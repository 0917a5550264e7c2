// Second-order geometry term at single poses (session 24 scratch probe, not built; bench/RESULTS.md, *Session 24*).
//
// Standalone, Eigen only, double precision (not certified): the reference robot of config/ref6.yaml with every anchor
// coordinate uncertain by H = 1 mm (36 parameters gamma in [-1, 1]), at the pose of the workspace `paper` where
// component k of the nominal error is largest (corners and random poses). With u the sign pattern of row k of J at
// the nominal geometry, F(gamma) = e_k^T J(t, g0 + H gamma) u; it prints
//   - sum |L| (first-order terms L = dF/dgamma), the true increase max F - F0 (greedy vertex search from s = sign(L)
//     plus random restarts) and its second-order part, s^T Q s (Q = the Hessian / 2 in gamma), sum |Q|,
//   - the bound GeometryIncrement uses, sum_i |J_ki| (A B)_i (A_ii' = sum over leg i's parameters of |dbar . J_{.,i'}|,
//     B the fixed point of B = Bw + A B), and without the fixed point (A Bw),
//   - the "one-sided" and "two-sided" signed bounds through the first-order signs (where |L_p| dominates p's row of Q),
//   - the cancellation ratios |J^T d| / |J|^T |d| and |d^T T_i| / |d|^T |T_i| (d the row derivatives, T_i = J D_i
//   dt_i).
// Build and run: g++ -O2 -I/usr/include/eigen3 second_order_point_probe.cpp -o probe && ./probe K [seed], K = 0..5.
#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <random>
using namespace Eigen;
typedef Matrix<double, 6, 6> M6;
typedef Matrix<double, 6, 1> V6;
double Ab[6][3] = {{-0.097, 0.091, 0}, {0.097, 0.091, 0},   {0.1276, 0.039, 0},
                   {0.031, -0.129, 0}, {-0.031, -0.129, 0}, {-0.1276, 0.039, 0}};
double Bb[6][3] = {{-0.030, 0.073, 0},     {0.030, 0.073, 0},       {0.07822, -0.01052, 0},
                   {0.04822, -0.06248, 0}, {-0.04822, -0.06248, 0}, {-0.07822, -0.01052, 0}};
double H = 0.001;
double E = 1e-5;
Matrix3d rot(double r, double p, double y) {
  return (AngleAxisd(y, Vector3d::UnitZ()) * AngleAxisd(p, Vector3d::UnitY()) * AngleAxisd(r, Vector3d::UnitX()))
      .toRotationMatrix();
}
M6 Minv(const double* t, const double* gam) {
  Matrix3d R = rot(t[3], t[4], t[5]);
  Vector3d p(t[0], t[1], t[2]);
  M6 M;
  for (int i = 0; i < 6; i++) {
    Vector3d A(Ab[i][0] + H * gam[6 * i], Ab[i][1] + H * gam[6 * i + 1], Ab[i][2] + H * gam[6 * i + 2]);
    Vector3d b(Bb[i][0] + H * gam[6 * i + 3], Bb[i][1] + H * gam[6 * i + 4], Bb[i][2] + H * gam[6 * i + 5]);
    Vector3d Rb = R * b;
    Vector3d n = (p + Rb - A).normalized();
    M.block<1, 3>(i, 0) = n.transpose();
    M.block<1, 3>(i, 3) = Rb.cross(n).transpose();
  }
  return M;
}
M6 Jac(const double* t, const double* g) { return Minv(t, g).inverse(); }
double f(const double* t, const double* g, int k) {
  M6 J = Jac(t, g);
  double s = 0;
  for (int j = 0; j < 6; j++) s += std::abs(J(k, j)) * E;
  return s;
}
int main(int argc, char** argv) {
  int k = argc > 1 ? atoi(argv[1]) : 0;
  std::mt19937 rng(argc > 2 ? atoi(argv[2]) : 1);
  std::uniform_real_distribution<double> U(-1, 1);
  double lo[6] = {-0.15, -0.15, 0.45, -0.2618, -0.2618, -0.2618}, hi[6] = {0.15, 0.15, 0.5, 0.2618, 0.2618, 0.2618};
  double g0[36] = {0};
  double best = -1, bt[6];
  for (int it = 0; it < 200000; it++) {
    double t[6];
    for (int i = 0; i < 6; i++) {
      double u = U(rng);
      if (it % 2) u = u > 0 ? 1 : -1;
      t[i] = lo[i] + (hi[i] - lo[i]) * (u + 1) / 2;
    }
    double v = f(t, g0, k);
    if (v > best) {
      best = v;
      for (int i = 0; i < 6; i++) bt[i] = t[i];
    }
  }
  const double* t = bt;
  printf("pose");
  for (int i = 0; i < 6; i++) printf(" %.4f", t[i]);
  printf("  f0=%.6e\n", best);
  M6 J0 = Jac(t, g0);
  V6 u;
  for (int j = 0; j < 6; j++) u[j] = (J0(k, j) > 0 ? E : -E);
  auto F = [&](const double* g) { return Jac(t, g).row(k).dot(u); };
  double F0 = F(g0);
  double L[36], Q[36][36];
  double st = 1e-2;
  for (int p = 0; p < 36; p++) {
    double g[36] = {0};
    g[p] = st;
    double a = F(g);
    g[p] = -st;
    double b = F(g);
    L[p] = (a - b) / (2 * st);
  }
  for (int p = 0; p < 36; p++)
    for (int q = 0; q < 36; q++) {
      double g[36] = {0};
      g[p] += st;
      g[q] += st;
      double a = F(g);
      g[q] -= 2 * st;
      double b = F(g);
      g[p] -= 2 * st;
      double d = F(g);
      g[q] += 2 * st;
      double c = F(g);
      Q[p][q] = (a - b - c + d) / (4 * st * st) / 2;
    }
  double sumL = 0, sumQ = 0, sQs = 0;
  double s[36];
  for (int p = 0; p < 36; p++) {
    s[p] = L[p] > 0 ? 1 : -1;
    sumL += std::abs(L[p]);
  }
  for (int p = 0; p < 36; p++)
    for (int q = 0; q < 36; q++) {
      sumQ += std::abs(Q[p][q]);
      sQs += s[p] * s[q] * Q[p][q];
    }
  // true max by greedy flips from s + random restarts
  auto Fg = [&](const double* gm) { return F(gm) - F0; };
  double bestv = -1e9;
  double gb[36];
  for (int r = 0; r < 40; r++) {
    double g[36];
    for (int p = 0; p < 36; p++) g[p] = r == 0 ? s[p] : (U(rng) > 0 ? 1 : -1);
    double v = Fg(g);
    bool imp = true;
    while (imp) {
      imp = false;
      for (int p = 0; p < 36; p++) {
        g[p] = -g[p];
        double w = Fg(g);
        if (w > v + 1e-18) {
          v = w;
          imp = true;
        } else
          g[p] = -g[p];
      }
    }
    if (v > bestv) {
      bestv = v;
      for (int p = 0; p < 36; p++) gb[p] = g[p];
    }
  }
  int flips = 0;
  for (int p = 0; p < 36; p++) flips += gb[p] != s[p];
  // structured old bound (point): A_ii' = sum_{p in row i} |dF...|
  // via exact derivatives: dM/dgamma_p row i(p): finite diff
  M6 dM[36];
  for (int p = 0; p < 36; p++) {
    double g[36] = {0};
    g[p] = st;
    M6 a = Minv(t, g);
    g[p] = -st;
    M6 b = Minv(t, g);
    dM[p] = (a - b) / (2 * st);
  }
  V6 w = J0 * u;
  M6 A = M6::Zero();
  V6 Bw = V6::Zero();
  for (int p = 0; p < 36; p++) {
    int i = p / 6;
    V6 d = dM[p].row(i).transpose();
    for (int j = 0; j < 6; j++) A(i, j) += std::abs(d.dot(J0.col(j)));
    Bw[i] += std::abs(d.dot(w));
  }
  V6 B = Bw;
  for (int it = 0; it < 200; it++) B = Bw + A * B;
  double old = 0;
  V6 AB = A * B;
  for (int i = 0; i < 6; i++) old += std::abs(J0(k, i)) * AB[i];
  double oldw = 0;
  V6 ABw = A * Bw;
  for (int i = 0; i < 6; i++) oldw += std::abs(J0(k, i)) * ABw[i];
  {
    double R[36];
    int nd = 0;
    double outside = 0, inside = 0;
    bool D[36];
    for (int p = 0; p < 36; p++) {
      R[p] = 0;
      for (int q = 0; q < 36; q++) R[p] += std::abs(Q[p][q]) + std::abs(Q[q][p]);
      D[p] = std::abs(L[p]) > R[p];
      nd += D[p];
      if (!D[p]) outside += R[p] / 2;
    }
    // one-sided with symmetric Q: gamma^T Q gamma = sum_p gamma_p (Q gamma)_p, (Q gamma)_p in +-R_p/2 using Qsym rows
    for (int q = 0; q < 36; q++) {
      double v = 0;
      for (int p = 0; p < 36; p++)
        if (D[p]) v += s[p] * Q[p][q];
      inside += std::abs(v);
    }
    double pen = 0, rho[36];
    for (int p = 0; p < 36; p++) {
      double a = 0, b = 0;
      for (int q = 0; q < 36; q++) {
        a += (Q[p][q] + Q[q][p]) * s[q];
        b += std::abs(Q[p][q]);
      }
      rho[p] = std::abs(a) + 2 * b;
      pen += 2 * std::max(0.0, rho[p] - std::abs(L[p]));
    }
    int nd2 = 0;
    for (int p = 0; p < 36; p++) nd2 += rho[p] < std::abs(L[p]);
    printf("  D %d/36 one-sided %.2f%% (inside %.2f%% outside %.2f%%) | two-sided: dominated %d/36, sQs+pen %.2f%%\n",
           nd, 100 * (inside + outside) / F0, 100 * inside / F0, 100 * outside / F0, nd2, 100 * (sQs + pen) / F0);
  }
  {  // cancellation ratios
    double num = 0, den = 0, num2 = 0, den2 = 0;
    M6 Jabs = J0.cwiseAbs();
    M6 dMt[6];
    for (int i = 0; i < 6; i++) {
      double tp[6], tm[6];
      for (int j = 0; j < 6; j++) {
        tp[j] = t[j];
        tm[j] = t[j];
      }
      double dt = 1e-6;
      tp[i] += dt;
      tm[i] -= dt;
      dMt[i] = (Minv(tp, g0) - Minv(tm, g0)) / (2 * dt);
    }
    double wid[6] = {0.04, 0.04, 0.006, 0.035, 0.035, 0.035};
    for (int p = 0; p < 36; p++) {
      V6 d = dM[p].row(p / 6).transpose();
      V6 dc = J0.transpose() * d;
      V6 dcm = Jabs.transpose() * d.cwiseAbs();
      num += dc.cwiseAbs().sum();
      den += dcm.sum();
      for (int i = 0; i < 6; i++) {
        M6 Ti = J0 * dMt[i] * wid[i];
        Matrix<double, 1, 6> a = d.transpose() * Ti;
        Matrix<double, 1, 6> b = d.cwiseAbs().transpose() * Ti.cwiseAbs();
        num2 += a.cwiseAbs().sum();
        den2 += b.sum();
      }
    }
    printf("  |J0^T d|/|J0|^T|d| = %.3f   |d^T T_i|/|d|^T|T_i| = %.3f\n", num / den, num2 / den2);
  }
  printf("F0 %.4e  sum|L| %.4e (%.2f%%)  true max-F0 %.4e -> second-order at max %.4e (%.2f%%), flips from s: %d\n", F0,
         sumL, 100 * sumL / F0, bestv, bestv - sumL, 100 * (bestv - sumL) / F0, flips);
  printf(
      "F(s)-F0-sumL %.4e (%.2f%%)  sQs %.4e (%.2f%%)  sum|Qsym| %.4e (%.2f%%)  old(A B) %.4e (%.2f%%)  old(A Bw) "
      "%.2f%%  rho(A)~%.3f\n",
      Fg(s) - sumL, 100 * (Fg(s) - sumL) / F0, sQs, 100 * sQs / F0, sumQ, 100 * sumQ / F0, old, 100 * old / F0,
      100 * oldw / F0, A.eigenvalues().cwiseAbs().maxCoeff());
}
