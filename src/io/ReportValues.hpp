// Values that the reports (ReportDocument, the human summary) both derive from a verifier result. Internal to the io
// library.
#pragma once

#include "pkm_accuracy/core/Types.hpp"
#include "pkm_accuracy/core/verify/VerifierResult.hpp"
#include "pkm_accuracy/io/ResultWriter.hpp"

namespace pkm_accuracy {
namespace io {

/// Midpoints of a pose enclosure.
inline DVec midpoints(const IVec& v) {
  DVec p(v.size());
  for (int i = 0; i < v.size(); ++i) p[i] = v[i].mid();
  return p;
}

/// The pose of the witness: the midpoints of its enclosure (exact for a workspace, whose poses are the variables).
inline DVec witnessPose(const verify::VerifierResult& r) {
  return r.witness_pose.size() == 0 ? r.witness : midpoints(r.witness_pose);
}

/// UNSAFE with a witness point and the component it violates.
inline bool hasWitness(const verify::VerifierResult& r) {
  return r.verdict == verify::Verdict::Unsafe && r.witness_component >= 0 && r.witness.size() > 0;
}

/// The domain is a trajectory (its first variable maps to a time, RunInfo::timeOf).
inline bool isTrajectory(const RunInfo& info) { return info.domain == "trajectory"; }

}  // namespace io
}  // namespace pkm_accuracy
