#include "pkm_accuracy/core/domain/Domain.hpp"

namespace pkm_accuracy {
namespace domain {

DVec centreOf(const IVec& box) {
  DVec c(box.size());
  for (int i = 0; i < box.size(); ++i) c[i] = box[i].mid();
  return c;
}

}  // namespace domain
}  // namespace pkm_accuracy
