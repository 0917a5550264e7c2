#include "pkm_accuracy/core/domain/ParametricVariety.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "pkm_accuracy/core/Exceptions.hpp"

namespace pkm_accuracy {
namespace domain {
namespace {

const char* kParameters[6] = {"u", "v", "w", "u4", "u5", "u6"};

}  // namespace

ParametricVariety::ParametricVariety(int m, std::array<std::vector<Monomial>, kMaxDof> coordinates)
    : ParametricVariety(m, std::move(coordinates), PoseCoordinates()) {}

ParametricVariety::ParametricVariety(int m, std::array<std::vector<Monomial>, kMaxDof> coordinates,
                                     PoseCoordinates pose)
    : m_(m), coordinates_(std::move(coordinates)), pose_(std::move(pose)) {
  if (m < 1 || m > kMaxDof) {
    throw InvalidArgument("variety parameters: expected 1 to " + std::to_string(kMaxDof) + ", got " +
                          std::to_string(m));
  }
  checkMonomials();
  initial_.resize(m);
  for (int i = 0; i < m; ++i) initial_[i] = Interval(0.0, 1.0);
}

void ParametricVariety::checkMonomials() {
  const int n = pose_.size();
  for (int i = n; i < kMaxDof; ++i) {
    if (!coordinates_[i].empty()) {
      throw InvalidArgument("variety: expected monomials for " + std::to_string(n) + " pose coordinates (" +
                            pose_.names() + ") of " + pose_.type() + ", got some for coordinate " + std::to_string(i));
    }
  }
  for (int i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < coordinates_[i].size(); ++j) {
      const Monomial& mono = coordinates_[i][j];
      const std::string where = "variety." + pose_.name(i) + "[" + std::to_string(j) + "]";
      if (!std::isfinite(mono.coefficient)) {
        std::ostringstream os;
        os << where << ": expected a finite coefficient, got " << mono.coefficient;
        throw InvalidArgument(os.str());
      }
      for (int v = 0; v < kMaxDof; ++v) {
        const int e = mono.exponents[v];
        if (e < 0 || e > kMaxExponent || (v >= m_ && e != 0)) {
          throw InvalidArgument(where + ": exponent of parameter " + std::to_string(v) + ": expected 0 to " +
                                std::to_string(v < m_ ? kMaxExponent : 0) + ", got " + std::to_string(e));
        }
        maxExponent_ = std::max(maxExponent_, e);
      }
    }
  }
}

void ParametricVariety::setRegion(PositionRegion region) {
  const std::array<int, 3> xyz = pose_.positionIndices();
  if (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0) {
    throw InvalidArgument("region: a position region needs the pose coordinates x, y, z; " + pose_.describe());
  }
  position_ = xyz;
  region_ = std::move(region);
}

std::string ParametricVariety::variableName(int i) const { return i >= 0 && i < m_ ? kParameters[i] : "?"; }

std::string ParametricVariety::description() const {
  std::size_t terms = 0;
  for (const auto& c : coordinates_) terms += c.size();
  return "variety, " + std::to_string(m_) + " parameter" + (m_ == 1 ? "" : "s") + ", " + std::to_string(terms) +
         " monomials";
}

template <typename D>
void ParametricVariety::evaluate(const std::array<D, kMaxDof>& vars, std::array<D, kMaxDof>& out) const {
  using T = typename D::Scalar;
  // powers[v][e] = vars[v]^e by repeated products (the parameters are >= 0, where products are tight).
  std::array<std::array<D, kMaxExponent + 1>, kMaxDof> powers;
  for (int v = 0; v < m_; ++v) {
    powers[v][0] = D(T(1.0));
    for (int e = 1; e <= maxExponent_; ++e) powers[v][e] = powers[v][e - 1] * vars[v];
  }
  for (int i = 0; i < pose_.size(); ++i) {
    D sum(T(0.0));
    for (const Monomial& mono : coordinates_[i]) {
      D term(T(mono.coefficient));
      for (int v = 0; v < m_; ++v)
        if (mono.exponents[v] > 0) term = term * powers[v][mono.exponents[v]];
      sum = sum + term;
    }
    out[i] = sum;
  }
}

void ParametricVariety::poseView(const IVec& box, bool gradient, enclosure::BoxInput& out) const {
  std::array<DualI, kMaxDof> vars;
  for (int v = 0; v < m_; ++v) vars[v] = DualI::variable(intersect(box[v], Interval(0.0, 1.0)), v);
  evaluate(vars, out.dualPose);
  const int n = pose_.size();
  for (int i = n; i < kMaxDof; ++i) out.dualPose[i] = DualI(Interval(0.0));
  out.variables = m_;
  out.hasGradient = gradient;
  out.pose.resize(n);
  for (int i = 0; i < n; ++i) out.pose[i] = out.dualPose[i].value();
  IVec centre(m_);
  out.deviation.resize(m_);
  for (int v = 0; v < m_; ++v) {
    const double c = box[v].mid();
    centre[v] = Interval(c);
    out.deviation[v] = box[v] - centre[v];
  }
  out.centrePose = values(centre);
}

IVec ParametricVariety::values(const IVec& box) const {
  using ValueDual = interval::Dual<Interval, 1>;  // values only: no gradient to carry
  std::array<ValueDual, kMaxDof> vars, pose;
  for (int v = 0; v < m_; ++v) vars[v] = ValueDual(intersect(box[v], Interval(0.0, 1.0)));
  evaluate(vars, pose);
  IVec p(pose_.size());
  for (int i = 0; i < pose_.size(); ++i) p[i] = pose[i].value();
  return p;
}

Containment ParametricVariety::classify(const IVec& box) const {
  if (!region_) return Containment::Inside;
  const IVec p = values(box);
  return region_->classify(p[position_[0]], p[position_[1]], p[position_[2]]);
}

IVec ParametricVariety::poseAt(const DVec& t) const {
  IVec box(m_);
  for (int v = 0; v < m_; ++v) box[v] = Interval(t[v]);
  return values(box);
}

void ParametricVariety::pointAt(const DVec& t, DVec& pose, DMat& jacobian) const {
  using DualD = interval::Dual<double, kMaxDof>;
  std::array<DualD, kMaxDof> vars, out;
  for (int v = 0; v < m_; ++v) vars[v] = DualD::variable(t[v], v);
  evaluate(vars, out);
  pose.resize(pose_.size());
  jacobian.resize(pose_.size(), m_);
  for (int i = 0; i < pose_.size(); ++i) {
    pose[i] = out[i].value();
    for (int v = 0; v < m_; ++v) jacobian(i, v) = out[i].d(v);
  }
}

}  // namespace domain
}  // namespace pkm_accuracy
