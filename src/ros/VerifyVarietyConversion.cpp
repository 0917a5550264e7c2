#include "pkm_accuracy/ros/VerifyVarietyConversion.hpp"

#include "RequestFields.hpp"

#include <cmath>
#include <vector>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/Types.hpp"
#include "pkm_accuracy/core/domain/ParametricVariety.hpp"

namespace pkm_accuracy {
namespace ros_layer {
namespace {

using fields::num;
using Monomial = domain::ParametricVariety::Monomial;

/// The terms of one coordinate (`name`, unit `unit`) of a variety of m parameters.
bool readTerms(const std::vector<VarietyTerm>& terms, const char* name, const char* unit, std::uint32_t m,
               std::vector<Monomial>& out, std::string& error) {
  out.clear();
  for (std::size_t j = 0; j < terms.size(); ++j) {
    const VarietyTerm& term = terms[j];
    const std::string where = fields::idx(name, j);
    if (!std::isfinite(term.coefficient)) {
      error = where + ".coefficient: expected a finite number (" + unit + "), got " + num(term.coefficient);
      return false;
    }
    if (term.exponents.size() != m) {
      error = where + ".exponents: expected " + std::to_string(m) + " exponent" + (m == 1 ? "" : "s") +
              " (one per parameter), got " + std::to_string(term.exponents.size());
      return false;
    }
    Monomial mono;
    mono.coefficient = term.coefficient;
    for (std::size_t v = 0; v < m; ++v) {
      const std::uint32_t e = term.exponents[v];
      if (e > static_cast<std::uint32_t>(domain::ParametricVariety::kMaxExponent)) {
        error = where + ".exponents[" + std::to_string(v) + "]: expected an exponent from 0 to " +
                std::to_string(domain::ParametricVariety::kMaxExponent) + ", got " + std::to_string(e);
        return false;
      }
      mono.exponents[v] = static_cast<int>(e);
    }
    out.push_back(mono);
  }
  return true;
}

}  // namespace

bool fromRequest(const VerifyVariety::Request& req, const std::string& base_frame, const QueryDefaults& defaults,
                 WorkspaceQuery& out, std::string& error) {
  error = fields::rigidBodyOnly(defaults, "verify_variety");
  if (!error.empty()) return false;
  WorkspaceQuery q;
  q.domain = QueryDomain::Variety;
  // Another frame is looked up in tf2 by the node when the job starts (an unknown one is refused then).
  q.frame_id = fields::frameId(req.frame_id, base_frame);
  if (!fields::mode(req.mode, q.mode, error)) return false;
  if (req.parameters < 1 || req.parameters > static_cast<std::uint32_t>(kMaxDof)) {
    error = "parameters: expected the number of parameters of the variety, 1 to " + std::to_string(kMaxDof) + ", got " +
            std::to_string(req.parameters);
    return false;
  }
  q.variety.parameters = static_cast<int>(req.parameters);
  const std::vector<VarietyTerm>* coords[6] = {&req.x, &req.y, &req.z, &req.roll, &req.pitch, &req.yaw};
  const char* const* names = fields::kPoseFields;
  const char* const* units = fields::kPoseUnits;
  for (std::size_t k = 0; k < 6; ++k) {
    if (!readTerms(*coords[k], names[k], units[k], req.parameters, q.variety.coordinates[k], error)) return false;
  }
  // The core's own checks (the same as above; a backstop: its messages name variety.<coordinate>[j]).
  try {
    domain::ParametricVariety(q.variety.parameters, q.variety.coordinates);
  } catch (const InvalidArgument& e) {
    error = e.what();
    return false;
  }
  if (!fields::sharedOptions(req, defaults, q, error)) return false;
  if (!fields::option(req.min_width, 0.0, "min_width",
                      "a number >= 0 and < 1 (parameter units: the parameters are in [0, 1]; 0 = the verifier's "
                      "choice)",
                      q.min_width, error, 1.0)) {
    return false;
  }
  out = q;
  return true;
}

namespace {

// The response and the action result have the same fields.
template <class Response>
void fillResponse(const WorkspaceOutcome& o, Response& res) {
  fields::fillCommonResponse(o, res);
  res.busy = o.busy;
  res.lower_bound_parameters = o.lower_bound_parameters;
  res.lower_bound_poses = o.lower_bound_poses;
  res.witness_parameters = o.witness_parameters;
  res.singular_parameters = o.singular_parameters;
  res.undecided_lower = o.undecided_parameters_lower;
  res.undecided_upper = o.undecided_parameters_upper;
  res.sensitive_parameters = o.sensitive.parameters;
  res.sensitive_region_lower = o.sensitive.region_lower;
  res.sensitive_region_upper = o.sensitive.region_upper;
}

}  // namespace

void toResponse(const WorkspaceOutcome& o, VerifyVariety::Response& res) { fillResponse(o, res); }

void toResult(const WorkspaceOutcome& o, VerifyVarietyResult& result) { fillResponse(o, result); }

VerifyVariety::Request toRequest(const VerifyVarietyGoal& g) {
  VerifyVariety::Request r;
  r.parameters = g.parameters;
  r.x = g.x;
  r.y = g.y;
  r.z = g.z;
  r.roll = g.roll;
  r.pitch = g.pitch;
  r.yaw = g.yaw;
  fields::copyOptions(g, r);
  return r;
}

}  // namespace ros_layer
}  // namespace pkm_accuracy
