// The scratch of MeanValueEnclosure's second-order forms: the expansion of N = (C J^-1)^-1 for the box
// (PreconditionedInverseEnclosure), its affine matrices, the geometry increase (GeometryIncrement), the error columns
// and the rows' largest columns. Every field is overwritten before it is read within one enclose(), so one workspace
// serves every box one after the other: it keeps its capacity (no heap allocation per box for these parts). One per
// thread: a workspace must not be used by two enclosures at once (ofThisThread() gives the calling thread's own one).
// Contracts and derivations: MeanValueEnclosure.hpp, docs/enclosures.md.
#pragma once

#include <vector>

#include "pkm_accuracy/core/enclosure/GeometryIncrement.hpp"
#include "pkm_accuracy/core/enclosure/PreconditionedInverseEnclosure.hpp"

namespace pkm_accuracy {
namespace enclosure {

struct MeanValueWorkspace {
  /// One column N v of a row's error: v = C w, w the weights of one choice of the row's undetermined signs.
  struct Column {
    int row = 0;
    IVec v;
  };
  PreconditionedInverseEnclosure act;
  /// jac: J = N C (the columns whose signs are needed; decomposed form: all of them); nv: the error columns N v.
  PreconditionedInverseEnclosure::AffineMatrix jac, nv;
  PreconditionedInverseEnclosure::Combination comb;  ///< the column being bounded
  GeometryIncrement increment;
  std::vector<Column> columns;
  /// Per row: its largest column (for the bisection hints) and, decomposed, that column's geometry coefficients.
  PreconditionedInverseEnclosure::Combination best[kMaxDof];
  double bestCoefficient[kMaxDof][kMaxGeometryParameters] = {};

  /// The calling thread's workspace (created on its first use, kept until the thread ends).
  static MeanValueWorkspace& ofThisThread() {
    static thread_local MeanValueWorkspace workspace;
    return workspace;
  }
};

}  // namespace enclosure
}  // namespace pkm_accuracy
