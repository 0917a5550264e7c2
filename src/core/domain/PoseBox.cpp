#include "pkm_accuracy/core/domain/PoseBox.hpp"

#include <sstream>
#include <utility>

#include "pkm_accuracy/core/Exceptions.hpp"

namespace pkm_accuracy {
namespace domain {

PoseBox::PoseBox(std::vector<std::string> names, const IVec& ranges) : names_(std::move(names)), initial_(ranges) {
  if (names_.empty() || static_cast<int>(names_.size()) > kMaxDof || ranges.size() != static_cast<int>(names_.size())) {
    throw InvalidArgument("workspace: expected 1 to " + std::to_string(kMaxDof) + " ranges, one per pose coordinate (" +
                          std::to_string(names_.size()) + "), got " + std::to_string(ranges.size()));
  }
  for (int i = 0; i < ranges.size(); ++i) {
    if (ranges[i].isEmpty() || !ranges[i].isBounded()) {
      std::ostringstream os;
      os << names_[static_cast<std::size_t>(i)] << ": expected a finite range [min, max] with min <= max, got "
         << ranges[i];
      throw InvalidArgument(os.str());
    }
  }
}

std::string PoseBox::variableName(int i) const {
  return (i >= 0 && i < variables()) ? names_[static_cast<std::size_t>(i)] : "?";
}

void PoseBox::poseView(const IVec& box, bool gradient, enclosure::BoxInput& out) const {
  identityPoseView(box, gradient, out);
}

Containment PoseBox::classify(const IVec& box) const {
  bool inside = true;
  for (int k = 0; k < variables(); ++k) {
    if (box[k].isEmpty() || box[k].lower() > initial_[k].upper() || box[k].upper() < initial_[k].lower()) {
      return Containment::Outside;
    }
    if (box[k].lower() < initial_[k].lower() || box[k].upper() > initial_[k].upper()) inside = false;
  }
  return inside ? Containment::Inside : Containment::Partial;
}

IVec PoseBox::poseAt(const DVec& t) const {
  IVec p(t.size());
  for (int i = 0; i < t.size(); ++i) p[i] = Interval(t[i]);
  return p;
}

}  // namespace domain
}  // namespace pkm_accuracy
