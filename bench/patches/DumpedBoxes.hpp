// The `BOX depth active lo_1 hi_1 .. lo_6 hi_6 r_1 .. r_6` lines that pkm_verify writes on stderr with
// session35_oracles.patch and PKM_DUMP set (r_k: component k's bound over its threshold), for the session-35 probes.
#pragma once

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "pkm_accuracy/core/Types.hpp"
#include "pkm_accuracy/core/domain/Workspace.hpp"
#include "pkm_accuracy/core/enclosure/AffineInverseAction.hpp"
#include "pkm_accuracy/core/model/RobotModel.hpp"

namespace pkm_accuracy {
namespace bench {

struct DumpedBox {
  int depth = 0;
  unsigned active = 0;  ///< the components still to decide when the box was enclosed
  IVec box;
  double ratio[6] = {0, 0, 0, 0, 0, 0};  ///< bound / threshold per component (inf where unbounded)
};

/// The dumped boxes of depths d0 to d1, in file order; with `every` > 1 only every every-th of them (the first, then
/// every-th after it).
inline std::vector<DumpedBox> readDumpedBoxes(const char* path, int d0, int d1, int every = 1) {
  std::vector<DumpedBox> out;
  int seen = 0;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string tag;
    DumpedBox b;
    s >> tag >> b.depth >> b.active;
    if (tag != "BOX" || b.depth < d0 || b.depth > d1 || seen++ % every != 0) continue;
    b.box.resize(6);
    for (int i = 0; i < 6; ++i) {
      double lo, hi;
      s >> lo >> hi;
      b.box[i] = Interval(lo, hi);
    }
    for (int k = 0; k < 6; ++k) {
      std::string t;
      s >> t;
      b.ratio[k] = std::strtod(t.c_str(), nullptr);
    }
    out.push_back(b);
  }
  return out;
}

/// AffineInverseAction's expansion over a box of `ws` (exact geometry) and its affine forms of the columns of J, i.e.
/// of N C with C the expansion's preconditioner. @return false where either cannot be built.
inline bool formsOfJacobianColumns(const model::RobotModel& robot, const domain::Workspace& ws, const IVec& box,
                                   enclosure::AffineInverseAction& act,
                                   enclosure::AffineInverseAction::AffineMatrix& nv) {
  enclosure::BoxInput bi;
  ws.poseView(box, true, bi);
  if (!act.prepare(robot, bi, false)) return false;
  const DMat& c = act.preconditioner();
  IMat cols(c.rows(), c.cols());
  for (int j = 0; j < c.cols(); ++j)
    for (int l = 0; l < c.rows(); ++l) cols(l, j) = Interval(c(l, j));
  return act.apply(cols, nv, true);
}

}  // namespace bench
}  // namespace pkm_accuracy
