#include "pkm_accuracy/core/enclosure/GeometryIncrement.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/LU>

#include "pkm_accuracy/core/model/RobotModel.hpp"

namespace pkm_accuracy {
namespace enclosure {
namespace {

using interval::rounding::up;  // a non-negative quantity computed in double: up() bounds the exact one

/// The rounding margin of the sums and dot products below (each of at most 64 terms, any rounding mode): the computed
/// sum is within kSumMargin times the sum of its terms' magnitudes of the exact one.
constexpr double kSumMargin = interval::rounding::gamma(64);

/// Rounds of GeometryIncrement::tightenFixedPoint.
constexpr int kPhiRounds = 1;

/// Upper bound of the magnitude of a form over the box.
inline double mag(const GeometryIncrement::Form& f) { return f.toInterval().mag(); }

}  // namespace

GeometryIncrement::Preparation GeometryIncrement::prepare(const model::RobotModel& model, const BoxInput& box,
                                                          const PreconditionedInverseEnclosure& act,
                                                          const PreconditionedInverseEnclosure::AffineMatrix& j0) {
  n_ = model.dof();
  params_ = model.geometryParameterCount();
  if (n_ != kMaxDof || !box.variablesArePose(n_) || params_ <= 0 || params_ > kMaxGeometryParameters)
    return Preparation::Unsupported;
  if (j0.rows != n_ || j0.cols != n_ || j0.vars != n_) return Preparation::Unsupported;
  double kappa[kMaxDof];
  if (!poseScales(box, kappa)) return Preparation::Unsupported;
  if (!loadDerivatives(model, box)) return Preparation::Unsupported;
  for (int k = 0; k < n_; ++k) {
    for (int j = 0; j < n_; ++j) {
      j0_[k][j] = entryForm(j0, k, j);
      magJ0_[k][j] = mag(j0_[k][j]);
    }
  }
  storeDerivativeForms(kappa);
  if (!boundDerivativesTimesPosePart(act)) return Preparation::Unsupported;
  double dotCentre[GeometryDerivatives::kCapacity][kMaxDof], dotDev[GeometryDerivatives::kCapacity][kMaxDof];
  boundCouplings(j0, dotCentre, dotDev);
  buildPhiTables(dotCentre, dotDev);
  for (int i = 0; i < n_; ++i)
    for (int j = 0; j < n_; ++j) a_[i][j] = up(a_[i][j]);
  if (!boundJacobianIncrease()) return Preparation::Unverified;
  certifySigns();
  return Preparation::Ready;
}

bool GeometryIncrement::poseScales(const BoxInput& box, double* kappa) const {
  // The box variables are the pose coordinates, centred at the box midpoint: then the nominal forms' symbols
  // tau_i = (t_i - t0_i) / dev_i and the model's tau'_i = (t_i - mid_i) / a_i (a_i >= the half-width, the scale
  // AffineForm::variable gives) are related by tau'_i = kappa_i tau_i, kappa_i = dev_i / a_i.
  for (int i = 0; i < n_; ++i) {
    const Interval& c = box.centrePose[i];
    if (!(c.lower() == c.upper() && c.lower() == box.pose[i].mid())) return false;
    const double a = Form::variable(box.pose[i], i).coefficient(i);
    const double dev = box.deviation[i].mag();
    if (!(a > 0.0) && dev > 0.0) return false;
    kappa[i] = a > 0.0 ? dev / a : 0.0;
  }
  return true;
}

bool GeometryIncrement::loadDerivatives(const model::RobotModel& model, const BoxInput& box) {
  GeometryDerivatives& geo = derivatives_;
  geo.count = 0;
  geo.withParameterSlopes = true;
  if (!model.geometryDerivatives(box.pose, geo) || geo.count <= 0 || geo.count > GeometryDerivatives::kCapacity)
    return false;
  entries_ = geo.count;
  for (int e = 0; e < entries_; ++e)
    if (!geo.entries[e].affine) return false;
  e_ = model.sensorError();
  for (int p = 0; p < params_; ++p)
    h_[p] = (model.geometryParameterRange(p) - Interval(model.geometryParameterCentre(p))).mag();
  return true;
}

void GeometryIncrement::storeDerivativeForms(const double* kappa) {
  for (int e = 0; e < entries_; ++e) {
    const GeometryRowDerivative& g = derivatives_.entries[e];
    param_[e] = g.parameter;
    row_[e] = g.row;
    entryH_[e] = h_[g.parameter];
    for (int l = 0; l < n_; ++l) {
      double a[kMaxDof], sum = 0.0;
      for (int m = 0; m < kMaxDof; ++m) {
        a[m] = g.slope[l][m] * kappa[m];  // off by at most 2 ulps of the exact product: in the radius
        sum += std::abs(a[m]);
      }
      dC_[l][e] = g.centre[l];
      double dev = 0.0;
      for (int m = 0; m < kMaxDof; ++m) {
        dA_[l][m][e] = a[m];
        dev += std::abs(a[m]);
      }
      dR_[l][e] = up(g.radius[l] + 1e-15 * sum);
      dSlope_[l][e] = up(dev);
      dDev_[l][e] = up(dev + dR_[l][e]);
      // The parameter terms (where the model gives them): dbar_e's are half of d_e's (below), kept apart.
      double half = 0.0;
      for (int s = 0; s < kMaxDof; ++s) {
        const bool used = g.parameterSlopes && g.slopeParameter[s] >= 0;
        dK_[l][s][e] = used ? g.parameterSlope[l][s] : 0.0;
        half += std::abs(dK_[l][s][e]);
      }
      dDevK_[l][e] = up(0.5 * half);
    }
  }
}

bool GeometryIncrement::boundDerivativesTimesPosePart(const PreconditionedInverseEnclosure& act) {
  // |dbar_e^T S| <= |c_e^T S| + dev_e^T |S| (dbar_e in c_e +- dev_e componentwise over the box), with
  // |c_e^T S| <= |c_e^T E0m| + |c_e|^T E0r + sum_i (|c_e^T D_i,m| + |c_e|^T D_i,r) dev_i; the products c_e^T X in
  // double are off by less than kSumMargin |c_e|^T |X| (sums of 6 products).
  const DMat& magS = act.poseMagnitude();
  if (magS.rows() != n_ || magS.cols() != n_) return false;
  for (int l = 0; l < n_; ++l)
    for (int e = 0; e < entries_; ++e) dS_[l][e] = 0.0;
  // (Entries innermost: contiguous, vectorisable loops.)
  double absC[kMaxDof][GeometryDerivatives::kCapacity], dev[kMaxDof][GeometryDerivatives::kCapacity];
  for (int m = 0; m < n_; ++m)
    for (int e = 0; e < entries_; ++e) {
      absC[m][e] = std::abs(dC_[m][e]);
      dev[m][e] = dDev_[m][e] + dDevK_[m][e] + kSumMargin * absC[m][e];
    }
  const auto addRow = [&](const DMat& xm, const DMat& xr, double scale) {
    for (int l = 0; l < n_; ++l) {
      double dot[GeometryDerivatives::kCapacity], mag[GeometryDerivatives::kCapacity];
      for (int e = 0; e < entries_; ++e) dot[e] = mag[e] = 0.0;
      for (int m = 0; m < n_; ++m) {
        const double x = xm(m, l), y = std::abs(x) * kSumMargin + xr(m, l);
        const double* c = dC_[m];
        const double* a = absC[m];
        for (int e = 0; e < entries_; ++e) {
          dot[e] += c[e] * x;
          mag[e] += a[e] * y;
        }
      }
      for (int e = 0; e < entries_; ++e) dS_[l][e] += (std::abs(dot[e]) + mag[e]) * scale;
    }
  };
  addRow(act.residualMid(), act.residualRad(), 1.0);
  for (int i = 0; i < n_; ++i) addRow(act.poseSlopeMid(i), act.poseSlopeRad(i), act.deviation(i));
  for (int l = 0; l < n_; ++l) {
    double s[GeometryDerivatives::kCapacity];
    for (int e = 0; e < entries_; ++e) s[e] = 0.0;
    for (int m = 0; m < n_; ++m) {
      const double x = magS(m, l);
      for (int e = 0; e < entries_; ++e) s[e] += dev[m][e] * x;
    }
    for (int e = 0; e < entries_; ++e) dS_[l][e] = up(up(dS_[l][e]) + up(s[e]));
  }
  return true;
}

void GeometryIncrement::boundCouplings(const PreconditionedInverseEnclosure::AffineMatrix& j0,
                                       double (*dotCentre)[kMaxDof], double (*dotDev)[kMaxDof]) {
  // A(i, j) >= |delta r_i . J0_{.,j}| (per (i, j) the entries added in the same order as entry by entry).
  for (int i = 0; i < n_; ++i)
    for (int j = 0; j < n_; ++j) a_[i][j] = 0.0;
  for (int j = 0; j < n_; ++j) {
    Form column[kMaxDof], out[GeometryDerivatives::kCapacity];
    double kw[GeometryDerivatives::kCapacity];
    for (int l = 0; l < n_; ++l) column[l] = j0_[l][j];
    columnDots(column, SeparablePart::ofColumn(j0, j), out);
    parameterDots(column, kw);
    for (int e = 0; e < entries_; ++e) {
      a_[row_[e]][j] += entryH_[e] * up(mag(out[e]) + kw[e]);
      // dbar_e . J0_{.,j} in centre +- deviation (with its parameter terms) over the box and every geometry.
      dotCentre[e][j] = out[e].centre();
      dotDev[e][j] = up(out[e].deviation() + kw[e]);
    }
  }
}

void GeometryIncrement::buildPhiTables(const double (*dotCentre)[kMaxDof], const double (*dotDev)[kMaxDof]) {
  // phi(): per row i and sign pattern eta of its entries (the first one +1: |.| is even), |sum_e eta_e h_e c_ej|
  // (sums of at most kPhiEntries products, rounding below kSumMargin times the sum of their magnitudes), and D.
  for (int i = 0; i < n_; ++i) rowEntries_[i] = 0;
  for (int e = 0; e < entries_; ++e) rowEntry_[row_[e]][rowEntries_[row_[e]]++] = e;
  for (int i = 0; i < n_; ++i) {
    const int m = rowEntries_[i];
    for (int j = 0; j < n_; ++j) {
      double d = 0.0;
      for (int q = 0; q < m; ++q) d += entryH_[rowEntry_[i][q]] * dotDev[rowEntry_[i][q]][j];
      phiD_[i][j] = up(d);
    }
    if (m > kPhiEntries) continue;
    const int patterns = m > 0 ? 1 << (m - 1) : 1;
    for (int eta = 0; eta < patterns; ++eta)
      for (int j = 0; j < n_; ++j) {
        double sum = 0.0, magnitude = 0.0;
        for (int q = 0; q < m; ++q) {
          const int e = rowEntry_[i][q];
          const double t = entryH_[e] * dotCentre[e][j];
          sum += (q > 0 && ((eta >> (q - 1)) & 1)) ? -t : t;
          magnitude += std::abs(t);
        }
        phiP_[i][eta * n_ + j] = std::abs(sum) + kSumMargin * magnitude;
      }
  }
}

bool GeometryIncrement::boundJacobianIncrease() {
  // Y = Delta M J (row i: delta r_i^T J, J = J(t, g)) satisfies Y = Delta M J0 + Delta M Delta J = Delta M J0 -
  // Delta M J0 Y (Delta J = -J0 Delta M J = -J0 Y), so |Y| <= A + A |Y|: a bound Ybar > 0 with A + A Ybar <= Ybar
  // proves rho(A) < 1 and |Y| <= Ybar; then |Delta J| <= |J0| Ybar = DJ. (A keeps the cancellations inside the dot
  // products dbar_p . J0_{.,j}; the magnitude product |J0| |Delta M| does not, and its spectral radius is close to 1.)
  aMat_.resize(n_, n_);
  for (int i = 0; i < n_; ++i)
    for (int j = 0; j < n_; ++j) aMat_(i, j) = a_[i][j];
  aApprox_ = (DMat::Identity(n_, n_) - aMat_).inverse();
  if (!aApprox_.allFinite()) aApprox_ = DMat::Identity(n_, n_);
  DMat ybar;
  if (!PreconditionedInverseEnclosure::fixedPointBound(aMat_, aApprox_, aMat_, ybar)) return false;
  // Column j of Y: |Y_ij| <= A_ij + |sum_i' (delta r_i . J0_{.,i'}) Y_i'j| <= A_ij + phi_i(|Y_.j|) (the signs of the
  // Y_i'j chosen jointly with leg i's geometry).
  for (int j = 0; j < n_; ++j) {
    double rhs[kMaxDof], z[kMaxDof];
    for (int i = 0; i < n_; ++i) {
      rhs[i] = a_[i][j];
      z[i] = ybar(i, j);
    }
    tightenFixedPoint(rhs, z, kPhiRounds);
    for (int i = 0; i < n_; ++i) ybar(i, j) = z[i];
  }
  for (int k = 0; k < n_; ++k)
    for (int j = 0; j < n_; ++j) {
      double s = 0.0;
      for (int i = 0; i < n_; ++i) s += magJ0_[k][i] * ybar(i, j);
      dj_[k][j] = up(s);
    }
  return true;
}

void GeometryIncrement::certifySigns() {
  signs_ = SignPattern();
  for (int k = 0; k < n_; ++k)
    for (int j = 0; j < n_; ++j) {
      const Interval range = j0_[k][j].toInterval();
      const int bit = k * n_ + j;
      if (range.lower() > dj_[k][j]) signs_.positive |= std::uint64_t(1) << bit;
      if (range.upper() < -dj_[k][j]) signs_.negative |= std::uint64_t(1) << bit;
    }
}

void GeometryIncrement::dots(const Form* w, Form* out) const {
  // The products of interval::AffineForm (the square terms' mean to the centre), summed over the components l in
  // one pass over the entries: centre sum_l (c_l wc_l + sum_m a_lm wa_lm / 2), coefficients sum_l (c_l wa_lm +
  // wc_l a_lm), radius sum_l (|c_l| wr_l + |wc_l| r_l + dev_l devw_l - sum_m |a_lm wa_lm| / 2). Each coefficient and
  // the centre are sums of at most 6 * (2 + 6) = 48 products and sums: their rounding errors are below 48 * 2^-52 /
  // (1 - 48 * 2^-52) < kSumMargin times the sum of the magnitudes of their terms (err); the radius terms are >= 0
  // (dev_l devw_l >= sum_m |a_lm wa_lm|) and up() covers their relative rounding.
  double c[GeometryDerivatives::kCapacity], a[kMaxDof][GeometryDerivatives::kCapacity];
  double r[GeometryDerivatives::kCapacity], err[GeometryDerivatives::kCapacity];
  for (int e = 0; e < entries_; ++e) c[e] = r[e] = err[e] = 0.0;
  for (int m = 0; m < kMaxDof; ++m)
    for (int e = 0; e < entries_; ++e) a[m][e] = 0.0;
  for (int l = 0; l < n_; ++l) {
    const double wc = w[l].centre(), awc = std::abs(wc), wr = w[l].radius();
    double wa[kMaxDof], devw = wr, waMag = 0.0;
    for (int m = 0; m < kMaxDof; ++m) {
      wa[m] = w[l].coefficient(m);
      devw += std::abs(wa[m]);
      waMag += std::abs(wa[m]);
    }
    // (Entries innermost, each entry's sums in the same order as entry by entry: contiguous, vectorisable loops.)
    const double* dc = dC_[l];
    double half[GeometryDerivatives::kCapacity], halfMag[GeometryDerivatives::kCapacity];
    for (int e = 0; e < entries_; ++e) half[e] = halfMag[e] = 0.0;
    for (int m = 0; m < kMaxDof; ++m) {
      const double wam = wa[m];
      const double* dm = dA_[l][m];
      double* am = a[m];
      for (int e = 0; e < entries_; ++e) {
        am[e] += dc[e] * wam + wc * dm[e];
        const double d = dm[e] * wam;
        half[e] += d;
        halfMag[e] += std::abs(d);
      }
    }
    // (The magnitudes of the terms of the centre and coefficients, sum_m (|c_l| |wa_lm| + |wc_l| |a_lm|) + |c_l wc_l|,
    // from the sums of the slopes' magnitudes: the same sum but for rounding far below the kSumMargin margin's slack.)
    for (int e = 0; e < entries_; ++e) {
      const double x = dc[e], ax = std::abs(x);
      c[e] += x * wc + 0.5 * half[e];
      r[e] += ax * wr + awc * dR_[l][e] + (dDev_[l][e] * devw - 0.5 * (1.0 - kSumMargin) * halfMag[e]);
      err[e] += ax * (awc + waMag) + awc * dSlope_[l][e] + halfMag[e];
    }
  }
  for (int e = 0; e < entries_; ++e) {
    double coefficients[kMaxDof];
    for (int m = 0; m < kMaxDof; ++m) coefficients[m] = a[m][e];
    out[e] = Form::fromParts(c[e], coefficients, up(r[e] + kSumMargin * err[e]));
  }
}

double GeometryIncrement::centreIncrease(int k, const double* wc) const {
  double b[kMaxGeometryParameters];
  for (int p = 0; p < params_; ++p) b[p] = 0.0;
  for (int e = 0; e < entries_; ++e) {
    double dw = 0.0;
    for (int l = 0; l < n_; ++l) dw += dC_[l][e] * wc[l];
    b[param_[e]] += j0_[k][row_[e]].centre() * dw;
  }
  double s = 0.0;
  for (int p = 0; p < params_; ++p) s += h_[p] * std::abs(b[p]);
  return s;
}

void GeometryIncrement::rowBound(int k, Row& out) const {
  double s = 0.0;
  for (int j = 0; j < n_; ++j) s += e_[j] * dj_[k][j];
  out.linear = Form(0.0);
  out.params = params_;
  out.constant = out.magnitude = up(s);
  for (int p = 0; p < params_; ++p) out.coefficient[p] = 0.0;
}

GeometryIncrement::SeparablePart GeometryIncrement::SeparablePart::ofColumn(
    const PreconditionedInverseEnclosure::AffineMatrix& a, int j) {
  SeparablePart part;
  for (int l = 0; l < a.rows; ++l) {
    part.ssy[l] = a.ssy(l, j);
    part.sy[l] = a.sy(l, j);
    part.splitRadius[l] = a.splitRadius(l, j);
  }
  return part;
}

void GeometryIncrement::columnDots(const Form* w, const SeparablePart& part, Form* out) const {
  // w_l = (its affine part) + r_l + x_l, |r_l| <= splitRadius_l - ssy_l, x = S S y, |x_l| <= ssy_l: |dbar_e . x| <=
  // min(sum_l |dbar_e|_l ssy_l, sum_l |dbar_e^T S|_l sy_l). That is one complete bound; dots(w) with w's own radius
  // (|w_l - its affine part| <= radius_l) is another with the same centre and coefficients: the smaller radius holds.
  const double* ssy = part.ssy;
  Form reduced[kMaxDof];
  double coefficients[kMaxDof];
  bool tightened = false;
  for (int l = 0; l < n_; ++l) {
    const double split = part.splitRadius[l];
    if (!(ssy[l] >= 0.0) || !(ssy[l] <= split)) return dots(w, out);
    tightened = tightened || w[l].radius() < split;
    for (int m = 0; m < kMaxDof; ++m) coefficients[m] = w[l].coefficient(m);
    reduced[l] = Form::fromParts(w[l].centre(), coefficients, interval::rounding::subUp(split, ssy[l]));
  }
  Form whole[GeometryDerivatives::kCapacity];
  if (tightened) dots(w, whole);
  dots(reduced, out);
  // (Entries innermost: contiguous, vectorisable loops; each entry's sums in the order l = 0, 1, ...)
  double plain[GeometryDerivatives::kCapacity], structured[GeometryDerivatives::kCapacity];
  for (int e = 0; e < entries_; ++e) plain[e] = structured[e] = 0.0;
  for (int l = 0; l < n_; ++l) {
    const double* c = dC_[l];
    const double* dev = dDev_[l];
    const double* devK = dDevK_[l];
    const double* ds = dS_[l];
    for (int e = 0; e < entries_; ++e) {
      plain[e] += (std::abs(c[e]) + dev[e] + devK[e]) * ssy[l];
      structured[e] += ds[e] * part.sy[l];
    }
  }
  for (int e = 0; e < entries_; ++e) {
    const double extra = up(std::min(plain[e], structured[e]));
    const double radius = up(out[e].radius() + extra);
    for (int m = 0; m < kMaxDof; ++m) coefficients[m] = out[e].coefficient(m);
    out[e] = Form::fromParts(out[e].centre(), coefficients, radius);
    if (tightened && whole[e].radius() < radius) out[e] = whole[e];
  }
}

void GeometryIncrement::parameterDots(const Form* w, double* out) const {
  // Each dot product kappa_s . w_c in double is off by less than kSumMargin sum_l |kappa_ls| |w_c,l| (6 products).
  double wc[kMaxDof], wd[kMaxDof];
  for (int l = 0; l < n_; ++l) {
    wc[l] = w[l].centre();
    wd[l] = w[l].deviation() + kSumMargin * std::abs(wc[l]);
  }
  // sum_s |kappa_s . w| <= sum_s |kappa_s . w_c| + sum_l (sum_s |kappa_ls|) wd_l, the inner sums 2 dDevK_ (>= them).
  double mag[GeometryDerivatives::kCapacity];
  for (int e = 0; e < entries_; ++e) out[e] = mag[e] = 0.0;
  for (int l = 0; l < n_; ++l) {
    const double* x = dDevK_[l];
    for (int e = 0; e < entries_; ++e) mag[e] += x[e] * wd[l];
  }
  for (int q = 0; q < kMaxDof; ++q) {
    double dot[GeometryDerivatives::kCapacity];
    for (int e = 0; e < entries_; ++e) dot[e] = 0.0;
    for (int l = 0; l < n_; ++l) {
      const double* x = dK_[l][q];
      for (int e = 0; e < entries_; ++e) dot[e] += x[e] * wc[l];
    }
    for (int e = 0; e < entries_; ++e) out[e] += std::abs(dot[e]);
  }
  for (int e = 0; e < entries_; ++e) out[e] = up(0.5 * up(out[e]) + up(mag[e]));
}

GeometryIncrement::Form GeometryIncrement::entryForm(const PreconditionedInverseEnclosure::AffineMatrix& a, int k,
                                                     int j) {
  double coefficients[kMaxDof];
  for (int i = 0; i < kMaxDof; ++i) coefficients[i] = i < a.vars ? a.pose[i](k, j) : 0.0;
  return Form::fromParts(a.centre(k, j), coefficients, a.radius(k, j));
}

bool GeometryIncrement::bound(int k, const Form* w, const SeparablePart& part, Row& out) const {
  DMat rowB0 = DMat::Zero(n_, 1);  // >= |Delta M w|_i = |delta r_i . w|
  ParameterForms b;
  double cross = 0.0;
  parameterForms(k, w, part, b, rowB0, cross);
  // B_i >= |delta r_i . y|, y = J u = w - J0 Delta M y: |Delta M y| <= B0 + A |Delta M y|.
  for (int i = 0; i < n_; ++i) rowB0(i, 0) = up(rowB0(i, 0));
  DMat rowB;
  if (!PreconditionedInverseEnclosure::fixedPointBound(aMat_, aApprox_, rowB0, rowB)) return false;
  double constant = 0.0, magnitude = 0.0;
  firstOrderBound(b, out, constant, magnitude);
  out.second = up(secondOrderSum(k, rowB0, rowB) + up(cross));
  out.constant = up(up(constant) + out.second);
  out.magnitude = up(up(magnitude) + out.second);
  return out.linear.finite() && std::isfinite(out.constant) && std::isfinite(out.magnitude);
}

void GeometryIncrement::parameterForms(int k, const Form* w, const SeparablePart& part, ParameterForms& b, DMat& rowB0,
                                       double& cross) const {
  Form dws[GeometryDerivatives::kCapacity];
  columnDots(w, part, dws);
  // With the parameter terms (GeometryRowDerivative::parameterSlopes), dbar_e = (its pose form) + sum_s kappa_s
  // gamma'_s / 2: dbar_e . w = dws_e + sum_s gamma'_s (kappa_s . w) / 2, so b_p gets terms gamma'_s gamma_p
  // (second order in the geometry), bounded in magnitude: sum_e h_e |J0_{k,row(e)}| parameterDots(w)_e.
  double kw[GeometryDerivatives::kCapacity];
  parameterDots(w, kw);
  // b_p = sum over p's entries of J0_{k,row(e)} dws_e, the products of interval::AffineForm (the square terms' mean
  // to the centre) summed per parameter in arrays: every centre and coefficient is a sum of at most 8 products and
  // sums per entry, at most 6 entries per parameter, so its rounding error is below kSumMargin times the sum of the
  // magnitudes of its terms (berr); the radius terms are >= 0 and up() covers their relative rounding.
  for (int q = 0; q < params_; ++q) {
    b.bc[q] = b.br[q] = b.berr[q] = 0.0;
    for (int m = 0; m < kMaxDof; ++m) b.ba[m][q] = 0.0;
  }
  for (int e = 0; e < entries_; ++e) {
    const Form& x = j0_[k][row_[e]];
    const Form& y = dws[e];
    const int q = param_[e];
    const double xc = x.centre(), yc = y.centre(), axc = std::abs(xc), ayc = std::abs(yc);
    double half = 0.0, halfMag = 0.0, err = 0.0, sx = x.radius(), sy2 = y.radius();
    for (int m = 0; m < kMaxDof; ++m) {
      const double xm = x.coefficient(m), ym = y.coefficient(m);
      b.ba[m][q] += xc * ym + yc * xm;
      const double d = xm * ym;
      half += d;
      halfMag += std::abs(d);
      err += axc * std::abs(ym) + ayc * std::abs(xm);
      sx += std::abs(xm);
      sy2 += std::abs(ym);
    }
    const double c = xc * yc + 0.5 * half;
    b.bc[q] += c;
    b.br[q] += axc * y.radius() + ayc * x.radius() + (sx * sy2 - 0.5 * (1.0 - kSumMargin) * halfMag);
    b.berr[q] += err + std::abs(xc * yc) + std::abs(c) + 2.0 * halfMag + std::abs(b.bc[q]);
    rowB0(row_[e], 0) += entryH_[e] * up(mag(y) + kw[e]);
    cross += entryH_[e] * up(magJ0_[k][row_[e]] * kw[e]);
  }
}

void GeometryIncrement::firstOrderBound(const ParameterForms& b, Row& out, double& constant, double& magnitude) const {
  // First order: max over gamma of sum_q gamma_q h_q b_q = sum_q h_q |b_q| <= sum_q (weight_q b_q + offset_q).
  // The parameters whose b_q has a certain sign have exact secants (weight +-h_q, offset 0): the others (ranges
  // across 0) are also kept as they are (Row::straddling), for the exact maximum at the vertices. The sums of
  // weight_q b_q (linear, fixed) in arrays too: at most 48 terms each, rounding below kSumMargin times their
  // magnitudes.
  double lc[2] = {0.0, 0.0}, la[2][kMaxDof] = {}, lr[2] = {0.0, 0.0}, lerr[2] = {0.0, 0.0};
  out.straddling = 0;
  out.params = params_;
  for (int q = 0; q < params_; ++q) {
    double dev = 0.0, coefficients[kMaxDof];
    for (int m = 0; m < kMaxDof; ++m) {
      coefficients[m] = b.ba[m][q];
      dev += std::abs(b.ba[m][q]);
    }
    const double radius = up(b.br[q] + kSumMargin * b.berr[q]);
    dev = up(dev + radius);
    const Interval range(interval::rounding::subDown(b.bc[q], dev), interval::rounding::addUp(b.bc[q], dev));
    const interval::AbsSecant secant = interval::absSecant(range, h_[q]);
    const double weight = secant.weight;
    const bool straddles = range.lower() < 0.0 && range.upper() > 0.0;
    for (int part = 0; part < (straddles ? 1 : 2); ++part) {  // (0: linear, every q; 1: fixed, the others)
      const double t = weight * b.bc[q];
      lc[part] += t;
      lerr[part] += std::abs(t);
      for (int m = 0; m < kMaxDof; ++m) {
        const double u = weight * b.ba[m][q];
        la[part][m] += u;
        lerr[part] += std::abs(u);
      }
      lr[part] += std::abs(weight) * radius;
    }
    if (straddles) {
      out.straddle[out.straddling] = Form::fromParts(b.bc[q], coefficients, radius);
      out.straddleH[out.straddling++] = h_[q];
    }
    constant += secant.offset;
    magnitude += h_[q] * range.mag();
    out.coefficient[q] = -h_[q] * b.bc[q];
  }
  out.linear = Form::fromParts(lc[0], la[0], up(lr[0] + kSumMargin * lerr[0]));
  out.fixed = Form::fromParts(lc[1], la[1], up(lr[1] + kSumMargin * lerr[1]));
}

double GeometryIncrement::secondOrderSum(int k, const DMat& rowB0, const DMat& rowB) const {
  // Second order: sum_i J0_ki sum_i' (delta r_i . J0_{.,i'}) (delta r_i' . y) <= sum_i |J0_ki| phi_i(B), B >= |delta r
  // . y| the fixed point of B <= B0 + phi(B) (B0 >= |delta r . w|; y = w - J0 Delta M y), tightened from the linear
  // one. (The signs of the delta r_i' . y are chosen jointly for row i, where (A B)_i takes every pair (i, i') at its
  // own worst geometry: about 9% fewer boxes at +-1 mm, 14% at 1% above the maxima; with it, a bound of this sum as a
  // function of the pose beside the constant one gains nothing, docs/design-notes.md.)
  double b0[kMaxDof], b[kMaxDof];
  for (int i = 0; i < n_; ++i) {
    b0[i] = rowB0(i, 0);
    b[i] = rowB(i, 0);
  }
  tightenFixedPoint(b0, b, kPhiRounds);
  double second = 0.0;
  for (int i = 0; i < n_; ++i) second += magJ0_[k][i] * phi(i, b);
  return up(second);
}

double GeometryIncrement::phi(int i, const double* x) const {
  const int m = rowEntries_[i];
  if (m > kPhiEntries) {
    double s = 0.0;
    for (int j = 0; j < n_; ++j) s += a_[i][j] * x[j];
    return up(s);
  }
  double base = 0.0;
  for (int j = 0; j < n_; ++j) base += x[j] * phiD_[i][j];
  const int patterns = m > 0 ? 1 << (m - 1) : 1;
  double best = 0.0;
  for (int eta = 0; eta < patterns; ++eta) {
    const double* p = phiP_[i] + eta * n_;
    double t = 0.0;
    for (int j = 0; j < n_; ++j) t += x[j] * p[j];
    best = std::max(best, t);
  }
  return up(up(best) + up(base));
}

void GeometryIncrement::tightenFixedPoint(const double* rhs, double* z, int rounds) const {
  // With z >= rhs + A z >= rhs + phi(z) (phi <= A x), z' = min(z, rhs + phi(z)) satisfies rhs + phi(z') <= rhs +
  // phi(z) <= z' (phi is monotone): again such a bound. And any x >= 0 with x <= rhs + phi(x) (the true |Delta M y|,
  // |Y_.j|) is below it: x <= rhs + phi(z' + (x - z')+) <= z' + phi((x - z')+) (phi subadditive), so
  // (x - z')+ <= phi((x - z')+) <= A (x - z')+, which is 0 as A's spectral radius is below 1.
  for (int round = 0; round < rounds; ++round) {
    double next[kMaxDof];
    for (int i = 0; i < n_; ++i) next[i] = interval::rounding::addUp(rhs[i], phi(i, z));
    for (int i = 0; i < n_; ++i) z[i] = std::min(z[i], next[i]);
  }
}

}  // namespace enclosure
}  // namespace pkm_accuracy
