#include "pkm_accuracy/core/enclosure/GeometryIncrement.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>

#include "pkm_accuracy/core/model/RobotModel.hpp"

namespace pkm_accuracy {
namespace enclosure {
namespace {

/// A non-negative quantity computed in double (sums of at most 64 non-negative products): up() bounds the exact one.
inline double up(double x) { return x * (1.0 + 1e-12) + 1e-300; }

/// Upper bound of the magnitude of a form over the box.
inline double mag(const GeometryIncrement::Form& f) { return f.toInterval().mag(); }

/// sum_l x[l] y[l] as an affine form.
inline GeometryIncrement::Form dot(const GeometryIncrement::Form* x, const GeometryIncrement::Form* y, int n) {
  GeometryIncrement::Form s = x[0] * y[0];
  for (int l = 1; l < n; ++l) s += x[l] * y[l];
  return s;
}

}  // namespace

bool GeometryIncrement::prepare(const model::RobotModel& model, const BoxInput& box,
                                const AffineInverseAction::AffineMatrix& j0) {
  n_ = model.dof();
  params_ = model.geometryParameterCount();
  if (n_ != kMaxDof || !box.variablesArePose(n_) || params_ <= 0 || params_ > kMaxGeometryParameters) return false;
  if (j0.rows != n_ || j0.cols != n_ || j0.vars != n_) return false;
  // The box variables are the pose coordinates, centred at the box midpoint: then the nominal forms' symbols
  // tau_i = (t_i - t0_i) / dev_i and the model's tau'_i = (t_i - mid_i) / a_i (a_i >= the half-width, the scale
  // AffineForm::variable gives) are related by tau'_i = kappa_i tau_i, kappa_i = dev_i / a_i.
  double kappa[kMaxDof];
  for (int i = 0; i < n_; ++i) {
    const Interval& c = box.centrePose[i];
    if (!(c.lower() == c.upper() && c.lower() == box.pose[i].mid())) return false;
    const double a = Form::variable(box.pose[i], i).coefficient(i);
    const double dev = box.deviation[i].mag();
    if (!(a > 0.0) && dev > 0.0) return false;
    kappa[i] = a > 0.0 ? dev / a : 0.0;
  }
  static thread_local GeometryDerivatives geo;
  geo.count = 0;
  if (!model.geometryDerivatives(box.pose, geo) || geo.count <= 0 || geo.count > GeometryDerivatives::kCapacity)
    return false;
  entries_ = geo.count;
  for (int e = 0; e < entries_; ++e)
    if (!geo.entries[e].affine) return false;
  e_ = model.sensorError();
  for (int p = 0; p < params_; ++p)
    h_[p] = (model.geometryParameterRange(p) - Interval(model.geometryParameterCentre(p))).mag();

  for (int k = 0; k < n_; ++k) {
    for (int j = 0; j < n_; ++j) {
      j0_[k][j] = entryForm(j0, k, j);
      magJ0_[k][j] = mag(j0_[k][j]);
    }
  }
  for (int e = 0; e < entries_; ++e) {
    const GeometryRowDerivative& g = geo.entries[e];
    param_[e] = g.parameter;
    row_[e] = g.row;
    entryH_[e] = h_[g.parameter];
    for (int l = 0; l < n_; ++l) {
      double a[kMaxDof], sum = 0.0;
      for (int m = 0; m < kMaxDof; ++m) {
        a[m] = g.slope[l][m] * kappa[m];  // off by at most 2 ulps of the exact product: in the radius
        sum += std::abs(a[m]);
      }
      d_[e][l] = Form::fromParts(g.centre[l], a, up(g.radius[l] + 1e-15 * sum));
      magD_[e][l] = mag(d_[e][l]);
    }
  }
  // A(i, j) >= |delta r_i . J0_{.,j}|.
  for (int i = 0; i < n_; ++i)
    for (int j = 0; j < n_; ++j) a_[i][j] = 0.0;
  for (int e = 0; e < entries_; ++e) {
    const int i = row_[e];
    Form column[kMaxDof];
    for (int j = 0; j < n_; ++j) {
      for (int l = 0; l < n_; ++l) column[l] = j0_[l][j];
      a_[i][j] += entryH_[e] * mag(dot(d_[e], column, n_));
    }
  }
  for (int i = 0; i < n_; ++i)
    for (int j = 0; j < n_; ++j) a_[i][j] = up(a_[i][j]);
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
  if (!AffineInverseAction::fixedPointBound(aMat_, aApprox_, aMat_, ybar)) return false;
  for (int k = 0; k < n_; ++k)
    for (int j = 0; j < n_; ++j) {
      double s = 0.0;
      for (int i = 0; i < n_; ++i) s += magJ0_[k][i] * ybar(i, j);
      dj_[k][j] = up(s);
    }
  signs_ = SignPattern();
  for (int k = 0; k < n_; ++k)
    for (int j = 0; j < n_; ++j) {
      const Interval range = j0_[k][j].toInterval();
      const int bit = k * n_ + j;
      if (range.lower() > dj_[k][j]) signs_.positive |= std::uint64_t(1) << bit;
      if (range.upper() < -dj_[k][j]) signs_.negative |= std::uint64_t(1) << bit;
    }
  return true;
}

GeometryIncrement::Form GeometryIncrement::entryForm(const AffineInverseAction::AffineMatrix& a, int k, int j) {
  double coefficients[kMaxDof];
  for (int i = 0; i < kMaxDof; ++i) coefficients[i] = i < a.vars ? a.pose[i](k, j) : 0.0;
  return Form::fromParts(a.centre(k, j), coefficients, a.radius(k, j));
}

bool GeometryIncrement::bound(int k, const Form* w, Row& out) const {
  Form b[kMaxGeometryParameters];
  for (int q = 0; q < params_; ++q) b[q] = Form(0.0);
  DMat rowB0 = DMat::Zero(n_, 1);  // >= |Delta M w|_i = |delta r_i . w|
  for (int e = 0; e < entries_; ++e) {
    const Form dw = dot(d_[e], w, n_);
    b[param_[e]] += j0_[k][row_[e]] * dw;
    rowB0(row_[e], 0) += entryH_[e] * mag(dw);
  }
  // B_i >= |delta r_i . y|, y = J u = w - J0 Delta M y: |Delta M y| <= B0 + A |Delta M y|.
  for (int i = 0; i < n_; ++i) rowB0(i, 0) = up(rowB0(i, 0));
  DMat rowB;
  if (!AffineInverseAction::fixedPointBound(aMat_, aApprox_, rowB0, rowB)) return false;
  // First order: max over gamma of sum_q gamma_q h_q b_q = sum_q h_q |b_q| <= sum_q (weight_q b_q + offset_q).
  out.linear = Form(0.0);
  out.params = params_;
  double constant = 0.0, magnitude = 0.0;
  for (int q = 0; q < params_; ++q) {
    const Interval range = b[q].toInterval();
    const interval::AbsSecant secant = interval::absSecant(range, h_[q]);
    out.linear += b[q] * secant.weight;
    constant += secant.offset;
    magnitude += h_[q] * range.mag();
    out.coefficient[q] = -h_[q] * b[q].centre();
  }
  // Second order: sum_i |J0_ki| sum_i' A_ii' B_i'.
  double second = 0.0;
  for (int i = 0; i < n_; ++i) {
    double s = 0.0;
    for (int i2 = 0; i2 < n_; ++i2) s += a_[i][i2] * rowB(i2, 0);
    second += magJ0_[k][i] * up(s);
  }
  second = up(second);
  out.constant = up(up(constant) + second);
  out.magnitude = up(up(magnitude) + second);
  return out.linear.finite() && std::isfinite(out.constant) && std::isfinite(out.magnitude);
}

}  // namespace enclosure
}  // namespace pkm_accuracy
