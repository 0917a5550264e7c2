// A robot model written once as templated kinematics (the habit of Ceres' AutoDiffCostFunction): the model gives its
// inverse Jacobian and its inverse kinematics as function templates, and KinematicModel instantiates them with the
// core's certified types to provide every ingredient the verifier uses (RobotModel):
//   double                             point J^-1 and joint coordinates (not certified)
//   Interval                           J^-1 over a pose box, every admissible geometry
//   Dual<Interval, kMaxDof>            J^-1 and its gradient along a domain's variables (trajectories, varieties)
//   Jet2<Interval, D>                  first and second derivatives in the pose (the second-order enclosures)
//   Jet2<AffineForm, D>                the second derivatives as affine forms in the pose over a box, so that their
//                                      products with a preconditioner keep their cancellations (SegmentAffineForm
//                                      when the remainder is split by its scaling towards the box centre)
//   Dual<Interval, 1>                  derivatives in one geometry parameter (geometry uncertainty as parameters)
//   Dual<AffineForm, 1>                the same as affine forms in the pose (the decomposed geometry form)
//   DependencyMask                     which rows of J^-1 each geometry value enters (exact, structural)
// and bisects or fixes geometry parameters by restricting their ranges. The derivation: docs/models.md.
//
// The Kinematics type K provides (a user's own robot: examples/, docs/models.md):
//   static constexpr int kDof;                    // pose coordinates = joints, 1..kMaxDof
//   template <class T> void inverseJacobian(const T* pose, const T* geometry, T* jinv) const;  // row-major
//   template <class T> void jointCoordinates(const T* pose, const T* geometry, T* joints) const;
// `geometry` holds the description's geometry values in order. The functions use only + - * /, the kin:: functions
// (KinematicsMath.hpp: sqr, sqrt, sin, cos, atan2, dot, cross, rotationRpy) and constants; no branch on a value of
// type T (an interval has no single sign). Where the formula is undefined (a pose the mechanism cannot reach),
// kin::sqrt makes the enclosures unbounded, so such boxes are never certified.
#pragma once

#include <cstdint>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/model/DependencyMask.hpp"
#include "pkm_accuracy/core/model/KinematicsMath.hpp"
#include "pkm_accuracy/core/model/RobotDescription.hpp"
#include "pkm_accuracy/core/model/RobotModel.hpp"

namespace pkm_accuracy {
namespace model {

/// The geometry values of a description as the model evaluates them: the interval each value ranges over, the point
/// the "at geometry centre" evaluations use, the admissible doubles, and which values are parameters. Shared by every
/// KinematicModel instantiation (not templated).
class GeometryValues {
 public:
  /// @throws InvalidGeometry if the description is invalid.
  explicit GeometryValues(const RobotDescription& description);

  int size() const { return static_cast<int>(range_.size()); }
  const std::vector<Interval>& ranges() const { return range_; }
  const std::vector<Interval>& centres() const { return centreInterval_; }
  const std::vector<double>& points() const { return point_; }
  /// Geometry-value index of parameter p.
  int valueOf(int p) const { return params_[static_cast<std::size_t>(p)]; }
  int parameterCount() const { return static_cast<int>(params_.size()); }
  bool uncertain() const;
  Interval admissible(int p) const;

  /// Parameter p restricted to ranges[p] (checked: non-empty, inside the current range).
  void restrict(const std::vector<Interval>& ranges, const RobotDescription& description);
  /// Parameters with a non-NaN value fixed there and removed from the parameter list (checked: inside the range).
  void fix(const GVec& values, const RobotDescription& description);

 private:
  void setRange(int value, const Interval& r);
  std::vector<Interval> range_, centreInterval_, admissible_;
  std::vector<double> point_;
  std::vector<int> params_;
};

/// Which rows of J^-1 (bit r) each geometry value enters, from the model's kinematics (DependencyMask).
template <typename K>
std::vector<std::uint32_t> rowsMovedByGeometry(const K& kinematics, int values) {
  constexpr int D = K::kDof;
  std::vector<DependencyMask> geometry(static_cast<std::size_t>(values));
  for (int v = 0; v < values; ++v) geometry[static_cast<std::size_t>(v)] = DependencyMask::on(v);
  DependencyMask pose[D], jinv[D * D];
  kinematics.inverseJacobian(pose, geometry.data(), jinv);
  std::vector<std::uint32_t> rows(static_cast<std::size_t>(values), 0u);
  for (int v = 0; v < values; ++v)
    for (int r = 0; r < D; ++r)
      for (int c = 0; c < D; ++c)
        if (jinv[r * D + c].bits.test(static_cast<std::size_t>(v))) rows[static_cast<std::size_t>(v)] |= 1u << r;
  return rows;
}

template <typename K>
class KinematicModel final : public RobotModel {
 public:
  static constexpr int D = K::kDof;
  static_assert(D >= 1 && D <= kMaxDof, "KinematicModel: kDof must lie in 1..kMaxDof");

  /// @throws InvalidGeometry if the description is invalid or has another number of pose components than K::kDof.
  KinematicModel(K kinematics, RobotDescription description)
      : k_(std::move(kinematics)),
        d_(std::make_shared<const RobotDescription>(checked(std::move(description)))),
        g_(*d_),
        rows_(std::make_shared<const std::vector<std::uint32_t>>(rowsMovedByGeometry(k_, g_.size()))),
        layout_(derivativeLayout()) {}

  const RobotDescription& description() const { return *d_; }
  const K& kinematics() const { return k_; }

  int dof() const override { return D; }
  std::string name() const override { return d_->type; }
  std::string componentName(int k) const override {
    return (k >= 0 && k < D) ? d_->pose[k].errorName() + " [" + d_->pose[k].unit + "]" : "?";
  }
  std::string jointName(int j) const override {
    return (j >= 0 && j < D) ? d_->joints[j].name + " [" + d_->joints[j].unit + "]" : "?";
  }
  bool isAngular(int k) const override { return k >= 0 && k < D && d_->pose[k].angular; }
  const std::vector<double>& sensorError() const override { return d_->sensor_error; }
  bool hasGeometryUncertainty() const override { return g_.uncertain(); }

  DMat inverseJacobian(const DVec& pose) const override {
    double jinv[D * D];
    k_.inverseJacobian(pose.data(), g_.points().data(), jinv);
    return toMatrix<double, DMat>(jinv);
  }
  DVec legLengths(const DVec& pose) const override {
    double q[D];
    k_.jointCoordinates(pose.data(), g_.points().data(), q);
    DVec out(D);
    for (int j = 0; j < D; ++j) out[j] = q[j];
    return out;
  }
  IMat inverseJacobian(const IVec& pose) const override { return intervalJinv(pose, g_.ranges()); }
  IMat inverseJacobianAtGeometryCentre(const IVec& pose) const override { return intervalJinv(pose, g_.centres()); }
  void inverseJacobian(const DualPose& pose, MatrixWithGradient& out) const override {
    dualJinv(pose, g_.ranges(), out);
  }
  void inverseJacobianAtGeometryCentre(const DualPose& pose, MatrixWithGradient& out) const override {
    dualJinv(pose, g_.centres(), out);
  }
  bool inverseJacobianHessianAtGeometryCentre(const IVec& pose, MatrixHessian& out, bool second) const override;
  bool preconditionedHessianMagnitude(const IVec& pose, const DMat& c, std::array<DMat, MatrixHessian::kPairs>& out,
                                      std::array<DMat, MatrixHessian::kPairs>* linear = nullptr,
                                      std::array<DMat, MatrixHessian::kPairs>* quadratic = nullptr,
                                      std::array<DMat, MatrixHessian::kPairs>* rest = nullptr,
                                      std::array<DMat, MatrixHessian::kPairs>* centre = nullptr) const override {
    if (pose.size() != D || c.rows() != D || c.cols() != D) return false;
    if (quadratic != nullptr && linear == nullptr) return false;
    if (quadratic != nullptr) {
      return affineHessianMagnitude<interval::SegmentAffineForm<kMaxDof>>(pose, c, out, linear, quadratic, rest,
                                                                          centre);
    }
    return affineHessianMagnitude<interval::AffineForm<kMaxDof>>(pose, c, out, linear, nullptr, rest, centre);
  }

  int geometryParameterCount() const override { return g_.parameterCount(); }
  std::string geometryParameterName(int p) const override {
    return validParameter(p) ? d_->geometry[g_.valueOf(p)].name : RobotModel::geometryParameterName(p);
  }
  Interval geometryParameterRange(int p) const override {
    return validParameter(p) ? g_.ranges()[g_.valueOf(p)] : RobotModel::geometryParameterRange(p);
  }
  double geometryParameterCentre(int p) const override {
    return validParameter(p) ? g_.centres()[g_.valueOf(p)].lower() : RobotModel::geometryParameterCentre(p);
  }
  Interval geometryParameterAdmissible(int p) const override {
    return validParameter(p) ? g_.admissible(p) : RobotModel::geometryParameterAdmissible(p);
  }
  int toolPointCoordinate(int p) const override {
    return validParameter(p) ? d_->geometry[g_.valueOf(p)].tool_point_coordinate : -1;
  }
  bool geometryDerivatives(const IVec& pose, GeometryDerivatives& out) const override;
  std::unique_ptr<RobotModel> restrictGeometry(const std::vector<Interval>& ranges) const override {
    if (g_.parameterCount() == 0) return RobotModel::restrictGeometry(ranges);
    auto out = std::make_unique<KinematicModel>(*this);
    out->g_.restrict(ranges, *d_);
    return out;
  }
  std::unique_ptr<RobotModel> fixGeometryParameters(const GVec& values) const override {
    if (g_.parameterCount() == 0) return RobotModel::fixGeometryParameters(values);
    auto out = std::make_unique<KinematicModel>(*this);
    out->g_.fix(values, *d_);
    out->layout_ = out->derivativeLayout();  // (the parameters are renumbered)
    return out;
  }

  /// Enclosure of the joint coordinates over a pose box (every admissible geometry).
  IVec jointCoordinates(const IVec& pose) const {
    Interval q[D];
    k_.jointCoordinates(pose.data(), g_.ranges().data(), q);
    IVec out(D);
    for (int j = 0; j < D; ++j) out[j] = q[j];
    return out;
  }

 private:
  static RobotDescription checked(RobotDescription d) {
    d.validate();
    if (static_cast<int>(d.pose.size()) != D) {
      throw InvalidGeometry(d.type + ": expected " + std::to_string(D) + " pose components, got " +
                            std::to_string(d.pose.size()));
    }
    return d;
  }
  bool validParameter(int p) const { return p >= 0 && p < g_.parameterCount(); }
  /// The rows of J^-1 geometry parameter p moves (bit r).
  std::uint32_t rowsOf(int p) const { return (*rows_)[static_cast<std::size_t>(g_.valueOf(p))]; }
  /// How geometryDerivatives() lays out its entries: parameters grouped so that the rows each group moves are
  /// pairwise disjoint (one evaluation per group), and the first entry of each parameter (parameter-major order;
  /// first.back() = the number of entries). Depends only on the parameter numbering, so restricted copies share it.
  struct DerivativeLayout {
    std::vector<std::vector<int>> groups;
    std::vector<int> first;
  };
  std::shared_ptr<const DerivativeLayout> derivativeLayout() const;
  template <typename G, typename A>
  void seedGeometry(const std::vector<int>& group, std::vector<G>& g, std::vector<A>& ga, bool on) const;
  template <typename G, typename A>
  static bool fillGeometryEntry(int p, int r, const G* jinv, const A* jinvA, GeometryRowDerivative& e);

  template <typename T, typename M>
  static M toMatrix(const T* jinv) {
    M m(D, D);
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) m(i, j) = jinv[i * D + j];
    return m;
  }
  IMat intervalJinv(const IVec& pose, const std::vector<Interval>& geometry) const {
    Interval jinv[D * D];
    k_.inverseJacobian(pose.data(), geometry.data(), jinv);
    return toMatrix<Interval, IMat>(jinv);
  }
  void dualJinv(const DualPose& pose, const std::vector<Interval>& geometry, MatrixWithGradient& out) const;
  /// preconditionedHessianMagnitude() with the second derivatives in the affine form type S.
  template <typename S>
  bool affineHessianMagnitude(const IVec& pose, const DMat& c, std::array<DMat, MatrixHessian::kPairs>& out,
                              std::array<DMat, MatrixHessian::kPairs>* linear,
                              std::array<DMat, MatrixHessian::kPairs>* quadratic,
                              std::array<DMat, MatrixHessian::kPairs>* rest,
                              std::array<DMat, MatrixHessian::kPairs>* centreOut) const;

  K k_;
  // Shared by the restricted and fixed copies the verifier makes per box (only the geometry values differ).
  std::shared_ptr<const RobotDescription> d_;
  GeometryValues g_;
  std::shared_ptr<const std::vector<std::uint32_t>> rows_;  ///< per geometry value: the rows of J^-1 it enters (bit r)
  std::shared_ptr<const DerivativeLayout> layout_;
};

// ---- template definitions -----------------------------------------------------------------------------------------

template <typename K>
void KinematicModel<K>::dualJinv(const DualPose& pose, const std::vector<Interval>& geometry,
                                 MatrixWithGradient& out) const {
  std::vector<DualI> g(geometry.begin(), geometry.end());
  DualI jinv[D * D];
  k_.inverseJacobian(pose.data(), g.data(), jinv);
  out.value.resize(D, D);
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) out.value(i, j) = jinv[i * D + j].value();
  for (int m = 0; m < kMaxDof; ++m) {
    out.d[m].resize(D, D);
    // Variables no pose coordinate depends on get exact zeros (outward-rounded products would give [-tiny, tiny]).
    bool depends = false;
    for (int k = 0; k < D; ++k) depends = depends || pose[k].d(m) != Interval(0.0);
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) out.d[m](i, j) = depends ? jinv[i * D + j].d(m) : Interval(0.0);
  }
}

template <typename K>
bool KinematicModel<K>::inverseJacobianHessianAtGeometryCentre(const IVec& pose, MatrixHessian& out,
                                                               bool second) const {
  using First = interval::Dual<Interval, D>;
  const std::vector<Interval>& centre = g_.centres();
  const IMat zero = IMat::Constant(D, D, Interval(0.0));
  for (int a = 0; a < kMaxDof; ++a) out.first[a] = zero;
  for (int p = 0; p < MatrixHessian::kPairs; ++p) out.d[p] = zero;
  bool finite = true;
  auto keep = [&finite](const Interval& v) {
    finite = finite && v.isBounded();
    return v;
  };
  if (!second) {
    First q[D], jinv[D * D];
    for (int a = 0; a < D; ++a) q[a] = First::variable(pose[a], a);
    std::vector<First> g(centre.begin(), centre.end());
    k_.inverseJacobian(q, g.data(), jinv);
    for (int a = 0; a < D; ++a)
      for (int i = 0; i < D; ++i)
        for (int j = 0; j < D; ++j) out.first[a](i, j) = keep(jinv[i * D + j].d(a));
    return finite;
  }
  using Second = interval::Jet2<Interval, D>;
  Second q[D], jinv[D * D];
  for (int a = 0; a < D; ++a) q[a] = Second::variable(pose[a], a);
  std::vector<Second> g(centre.begin(), centre.end());
  k_.inverseJacobian(q, g.data(), jinv);
  for (int i = 0; i < D; ++i) {
    for (int j = 0; j < D; ++j) {
      const Second& e = jinv[i * D + j];
      for (int a = 0; a < D; ++a) {
        out.first[a](i, j) = keep(e.d(a));
        for (int b = a; b < D; ++b) out.d[MatrixHessian::index(a, b)](i, j) = keep(e.d2(a, b));
      }
    }
  }
  return finite;
}

namespace detail {
template <int M>
double remainderParts(const interval::SegmentAffineForm<M>& f, double& r2) {
  r2 = f.quadraticRadius();
  return f.constantRadius();
}
template <int M>
double remainderParts(const interval::AffineForm<M>& f, double& r2) {
  r2 = 0.0;
  return f.radius();
}
}  // namespace detail

// The second derivatives in affine arithmetic, one symbol per pose coordinate: H_il(t) in Hc + sum_m A_m tau_m +- R
// entry by entry, so C H_il(t) in C Hc + sum_m (C A_m) tau_m +- |C| R, and |C H_il(t)| <= |C Hc| + sum_m |C A_m| +
// |C| R, plus the rounding of the products with C (sums of at most D <= 6 products: below 1e-13 of |C| times the
// magnitudes); with `linear` the middle term apart; with `quadratic` (SegmentAffineForm) R splits into R0 + s^2 R2
// (RobotModel::preconditionedHessianMagnitude).
template <typename K>
template <typename S>
bool KinematicModel<K>::affineHessianMagnitude(const IVec& pose, const DMat& c,
                                               std::array<DMat, MatrixHessian::kPairs>& out,
                                               std::array<DMat, MatrixHessian::kPairs>* linear,
                                               std::array<DMat, MatrixHessian::kPairs>* quadratic,
                                               std::array<DMat, MatrixHessian::kPairs>* rest,
                                               std::array<DMat, MatrixHessian::kPairs>* centreOut) const {
  using Second = interval::Jet2<S, D>;
  Second q[D], jinv[D * D];
  for (int a = 0; a < D; ++a) q[a] = Second::variable(S::variable(pose[a], a), a);
  std::vector<Second> g;
  g.reserve(g_.centres().size());
  for (const Interval& v : g_.centres()) g.emplace_back(S(v.lower()));
  k_.inverseJacobian(q, g.data(), jinv);
  const DMat absC = c.cwiseAbs();
  for (int a = 0; a < kMaxDof; ++a) {
    for (int b = a; b < kMaxDof; ++b) {
      const int p = MatrixHessian::index(a, b);
      if (a >= D || b >= D) {  // pose coordinates the model does not have
        out[p] = DMat::Zero(D, D);
        if (linear != nullptr) (*linear)[p] = DMat::Zero(D, D);
        if (quadratic != nullptr) (*quadratic)[p] = DMat::Zero(D, D);
        if (rest != nullptr) (*rest)[p] = DMat::Zero(D, D);
        if (centreOut != nullptr) (*centreOut)[p] = DMat::Zero(D, D);
        continue;
      }
      DMat centre(D, D), radius(D, D), quad = DMat::Zero(D, D), slopes = DMat::Zero(D, D), coeff(D, D);
      for (int i = 0; i < D; ++i) {
        for (int j = 0; j < D; ++j) {
          const S& f = jinv[i * D + j].d2(a, b);
          if (!f.finite()) return false;
          centre(i, j) = f.centre();
          radius(i, j) = quadratic != nullptr ? detail::remainderParts(f, quad(i, j)) : f.radius();
        }
      }
      DMat absSum = centre.cwiseAbs();
      for (int m = 0; m < D; ++m) {
        for (int i = 0; i < D; ++i)
          for (int j = 0; j < D; ++j) coeff(i, j) = jinv[i * D + j].d2(a, b).coefficient(m);
        slopes += (c * coeff).cwiseAbs();
        absSum += coeff.cwiseAbs();
      }
      const DMat scale = absC * absSum;  // the magnitudes of the products' terms
      DMat mag = (c * centre).cwiseAbs() + absC * radius;
      if (linear != nullptr) {
        (*linear)[p] = interval::rounding::upEach(DMat(slopes + 1e-13 * scale));
        if (!(*linear)[p].allFinite()) return false;
      } else {
        mag += slopes;
      }
      if (quadratic != nullptr) {
        (*quadratic)[p] = interval::rounding::upEach(DMat(absC * quad));
        if (!(*quadratic)[p].allFinite()) return false;
      }
      if (rest != nullptr) (*rest)[p] = interval::rounding::upEach(DMat(absC * radius + 1e-13 * scale));
      if (centreOut != nullptr) (*centreOut)[p] = c * centre;
      out[p] = interval::rounding::upEach(DMat(mag + 1e-13 * scale));
      if (!out[p].allFinite()) return false;
    }
  }
  return true;
}

// Each entry twice: the derivative in one geometry parameter as an interval dual (GeometryRowDerivative::d) and as a
// dual of first-order affine forms in the pose (centre + sum_m slope_m tau_m +- radius; one symbol per pose
// coordinate, the same for every entry; the geometry values enter as interval constants, so the radius covers every
// admissible geometry). The affine forms are only reported where every one of them is finite.
//
// Parameters that move disjoint sets of rows share one evaluation (the column compression of sparse Jacobians): they
// are seeded in the same derivative slot, and as no row's formula contains two of them (DependencyMask is exact and
// structural), each row's slot holds the derivative in the one parameter of the group that it contains. The Gough
// platform's 36 anchor coordinates need 6 evaluations instead of 36.
template <typename K>
bool KinematicModel<K>::geometryDerivatives(const IVec& pose, GeometryDerivatives& out) const {
  out.count = 0;
  if (g_.parameterCount() == 0) return true;
  const std::vector<int>& first = layout_->first;
  if (first.back() > GeometryDerivatives::kCapacity) return false;
  using G = interval::Dual<Interval, 1>;
  using A = interval::Dual<interval::AffineForm<kMaxDof>, 1>;
  std::vector<G> g(g_.ranges().begin(), g_.ranges().end());
  std::vector<A> ga;
  ga.reserve(g_.ranges().size());
  for (const Interval& v : g_.ranges()) ga.emplace_back(interval::AffineForm<kMaxDof>(v));
  G q[D], jinv[D * D];
  A qa[D], jinvA[D * D];
  for (int a = 0; a < D; ++a) {
    q[a] = G(pose[a]);
    qa[a] = A(interval::AffineForm<kMaxDof>::variable(pose[a], a));
  }
  bool affine = true;
  for (const std::vector<int>& group : layout_->groups) {
    seedGeometry(group, g, ga, true);
    k_.inverseJacobian(q, g.data(), jinv);
    k_.inverseJacobian(qa, ga.data(), jinvA);
    seedGeometry(group, g, ga, false);
    for (const int p : group) {
      int e = first[p];
      for (int r = 0; r < D; ++r) {
        if (!(rowsOf(p) & (1u << r))) continue;
        if (!fillGeometryEntry(p, r, jinv, jinvA, out.entries[e])) return false;
        affine = affine && out.entries[e++].affine;
      }
    }
  }
  out.count = first.back();
  for (int e = 0; e < out.count && !affine; ++e) out.entries[e].affine = false;
  return true;
}

/// The groups greedily: each parameter joins the first group whose rows (rowsOf) it does not share.
template <typename K>
std::shared_ptr<const typename KinematicModel<K>::DerivativeLayout> KinematicModel<K>::derivativeLayout() const {
  auto layout = std::make_shared<DerivativeLayout>();
  std::vector<std::uint32_t> used;
  layout->first.assign(static_cast<std::size_t>(g_.parameterCount()) + 1, 0);
  for (int p = 0; p < g_.parameterCount(); ++p) {
    const std::uint32_t rows = rowsOf(p);
    layout->first[p + 1] = layout->first[p] + __builtin_popcount(rows);
    if (rows == 0u) continue;
    std::size_t k = 0;
    while (k < used.size() && (used[k] & rows) != 0u) ++k;
    if (k == used.size()) {
      layout->groups.emplace_back();
      used.push_back(0u);
    }
    layout->groups[k].push_back(p);
    used[k] |= rows;
  }
  return layout;
}

/// Seeds (on) or unseeds (off) the derivative slot of every parameter of `group` in both duals.
template <typename K>
template <typename G, typename A>
void KinematicModel<K>::seedGeometry(const std::vector<int>& group, std::vector<G>& g, std::vector<A>& ga,
                                     bool on) const {
  for (const int p : group) {
    const std::size_t v = static_cast<std::size_t>(g_.valueOf(p));
    const Interval& range = g_.ranges()[v];
    g[v] = on ? G::variable(range, 0) : G(range);
    ga[v] = on ? A::variable(interval::AffineForm<kMaxDof>(range), 0) : A(interval::AffineForm<kMaxDof>(range));
  }
}

/// One entry (parameter p, row r) from the interval and affine duals of J^-1; false if the interval one is unbounded.
template <typename K>
template <typename G, typename A>
bool KinematicModel<K>::fillGeometryEntry(int p, int r, const G* jinv, const A* jinvA, GeometryRowDerivative& e) {
  e.parameter = p;
  e.row = r;
  e.parameterSlopes = false;
  e.affine = true;
  for (int l = 0; l < kMaxDof; ++l) {
    e.centre[l] = e.radius[l] = 0.0;
    e.slope[l].fill(0.0);
    if (l >= D) {
      e.d[l] = interval::MidRad(0.0);
      continue;
    }
    const Interval& d = jinv[r * D + l].d(0);
    if (!d.isBounded()) return false;
    e.d[l] = interval::MidRad(d);
    const auto& f = jinvA[r * D + l].d(0);
    if (!f.finite()) {
      e.affine = false;
      continue;
    }
    e.centre[l] = f.centre();
    e.radius[l] = f.radius();
    for (int m = 0; m < kMaxDof; ++m) e.slope[l][m] = f.coefficient(m);
  }
  return true;
}

}  // namespace model
}  // namespace pkm_accuracy
