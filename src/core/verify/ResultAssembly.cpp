#include "ResultAssembly.hpp"

#include <algorithm>

namespace pkm_accuracy {
namespace verify {

VerifierResult ResultAssembly::assemble(SearchState& state) const {
  VerifierResult r = state.takeResult();
  r.stats = state.snapshot();
  const Stop stop = state.stop();
  UndecidedReason reason = UndecidedReason::PrecisionLimit;
  if (stop == Stop::BoxBudget) reason = UndecidedReason::BoxBudget;
  if (stop == Stop::TimeBudget) reason = UndecidedReason::TimeBudget;
  if (stop == Stop::Cancelled) reason = UndecidedReason::Cancelled;
  std::ostringstream msg;
  if (c_.options.mode == Mode::Verify) {
    verifyVerdict(r, reason, state.haveWitness(), msg);
  } else {
    bracket(r, state);
    maxErrorVerdict(r, reason, msg);
  }
  r.message = msg.str();
  return r;
}

void ResultAssembly::verifyVerdict(VerifierResult& r, UndecidedReason reason, bool haveWitness,
                                   std::ostringstream& msg) const {
  if (haveWitness) {
    r.verdict = Verdict::Unsafe;
    r.reason = UndecidedReason::None;
    msg << "UNSAFE: " << c_.model.componentName(r.witness_component) << " error >= " << r.witness_lower_bound
        << " > threshold " << c_.options.thresholds[r.witness_component] << " at a certified witness";
    if (r.singular) msg << ", near a certified singular pose (" << singularText(r) << ")";
  } else if (r.singular) {
    r.verdict = Verdict::Unsafe;
    r.reason = UndecidedReason::None;
    msg << "UNSAFE: the domain contains a singular pose (" << singularText(r)
        << "), near which the error exceeds any threshold";
  } else if (r.sensitive_count > 0) {
    r.verdict = Verdict::Undecided;
    r.reason = UndecidedReason::UncertaintySensitive;
    sensitiveText(r, msg);
  } else if (r.undecided_box_count == 0) {
    r.verdict = Verdict::Safe;
    r.reason = UndecidedReason::None;
    msg << "SAFE: every pose is within every threshold (" << r.stats.boxes << " boxes)";
  } else {
    r.verdict = Verdict::Undecided;
    r.reason = reason;
    msg << "UNDECIDED (" << toString(reason) << "): " << r.undecided_box_count << " boxes could not be decided, "
        << r.stats.undecided_fraction * 100.0 << "% of the volume";
  }
}

void ResultAssembly::sensitiveText(const VerifierResult& r, std::ostringstream& msg) const {
  const SensitivePose& s = r.sensitive.front();
  msg << "UNDECIDED (uncertainty_sensitive): " << c_.model.componentName(s.component)
      << " exceeds its threshold for some admissible geometries (certified error >= " << s.failing_lower << " > "
      << c_.options.thresholds[s.component] << ")";
  if (!s.passing_geometry.empty()) {
    msg << " and stays below it for others (<= " << s.passing_upper << ")";
  }
  msg << " at " << r.sensitive_count << " certified pose(s), e.g. in the region";
  for (int i = 0; i < s.region.size(); ++i) {
    msg << (i == 0 ? " " : ", ") << c_.domain.variableName(i) << " [" << s.region[i].lower() << ", "
        << s.region[i].upper() << "]";
  }
  msg << "; no pose was found where it exceeds for every admissible geometry";
}

void ResultAssembly::bracket(VerifierResult& r, const SearchState& state) const {
  const std::vector<DVec>& argmax = state.argmax();
  r.max_lower = DVec(c_.n);
  r.max_upper = DVec(c_.n);
  r.max_argmax = argmax;
  r.max_argmax_pose.assign(argmax.size(), IVec());
  for (std::size_t k = 0; k < argmax.size(); ++k)
    if (argmax[k].size() == c_.m) r.max_argmax_pose[k] = c_.domain.poseAt(argmax[k]);
  if (c_.params > 0) r.max_argmax_geometry = state.argmaxGeometry();
  r.converged = r.undecided_box_count == 0;
  for (int k = 0; k < c_.n; ++k) {
    r.max_lower[k] = state.lower(k);
    r.max_upper[k] = std::max({r.max_lower[k], state.discardedMax(k), state.undecidedMax(k)});
    // (Singular: some component is unbounded, and which is not known: none keeps a finite upper bound.)
    if (r.singular) r.max_upper[k] = kInf;
    if (r.max_upper[k] - r.max_lower[k] > c_.tolerance(r.max_lower[k]) * (1.0 + 1e-12) + 1e-300) r.converged = false;
  }
}

void ResultAssembly::maxErrorVerdict(VerifierResult& r, UndecidedReason reason, std::ostringstream& msg) const {
  if (r.singular) reason = UndecidedReason::NoThresholds;  // (the bracket is final: [lower, +inf])
  if (!c_.hasThresholds) {
    r.verdict = Verdict::Undecided;
    r.reason = r.converged ? UndecidedReason::NoThresholds : reason;
  } else {
    int exceeded = -1;
    bool allBelow = true;
    for (int k = 0; k < c_.n; ++k) {
      if (r.max_lower[k] > c_.options.thresholds[k] && exceeded < 0) exceeded = k;
      if (!(r.max_upper[k] <= c_.options.thresholds[k])) allBelow = false;
    }
    if (exceeded >= 0 && r.max_argmax[exceeded].size() == c_.m) {
      r.verdict = Verdict::Unsafe;
      r.witness = r.max_argmax[exceeded];
      r.witness_pose = c_.domain.poseAt(r.witness);
      r.witness_component = exceeded;
      r.witness_lower_bound = r.max_lower[exceeded];
    } else if (r.singular) {
      r.verdict = Verdict::Unsafe;
      r.reason = UndecidedReason::None;
    } else if (allBelow) {
      r.verdict = Verdict::Safe;
    } else {
      r.verdict = Verdict::Undecided;
      r.reason = r.converged ? UndecidedReason::PrecisionLimit : reason;
    }
  }
  if (r.singular) {
    msg << "the maximal error is unbounded: the domain contains a singular pose (" << singularText(r) << "); after "
        << r.stats.boxes << " boxes";
  } else {
    msg << (r.converged ? "maximal errors bracketed to alpha" : "maximal errors NOT bracketed to alpha (")
        << (r.converged ? "" : toString(reason) + ")") << " after " << r.stats.boxes << " boxes";
  }
}

std::string ResultAssembly::singularText(const VerifierResult& r) const {
  std::ostringstream os;
  os << "det J^-1 has certified opposite signs, for "
     << (r.singular_geometry.empty() ? "every admissible geometry" : "the nominal geometry") << ", at";
  for (const DVec* t : {&r.singular_from, &r.singular_to}) {
    os << (t == &r.singular_from ? " " : " and at ");
    for (int i = 0; i < t->size(); ++i) os << (i == 0 ? "" : ", ") << c_.domain.variableName(i) << " = " << (*t)[i];
  }
  return os.str();
}

}  // namespace verify
}  // namespace pkm_accuracy
