// The `BOX depth active lo_1 hi_1 .. lo_6 hi_6 r_1 .. r_6` lines that pkm_verify writes on stderr with
// session35_oracles.patch and PKM_DUMP set (r_k: component k's bound over its threshold), for the session-35 probes.
#pragma once

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "pkm_accuracy/core/Types.hpp"

namespace pkm_accuracy {
namespace bench {

struct DumpedBox {
  int depth = 0;
  unsigned active = 0;  ///< the components still to decide when the box was enclosed
  IVec box;
  double ratio[6] = {0, 0, 0, 0, 0, 0};  ///< bound / threshold per component (inf where unbounded)
};

/// The dumped boxes of depths d0 to d1, in file order.
inline std::vector<DumpedBox> readDumpedBoxes(const char* path, int d0, int d1) {
  std::vector<DumpedBox> out;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string tag;
    DumpedBox b;
    s >> tag >> b.depth >> b.active;
    if (tag != "BOX" || b.depth < d0 || b.depth > d1) continue;
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

}  // namespace bench
}  // namespace pkm_accuracy
