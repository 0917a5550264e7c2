// Shared by the action rostests (action_node, trajectory_action_node): the wire bytes of a message, conversion
// between message types with the same definition, a job outcome with every field set to its own value (so that a
// conversion that drops or swaps a field shows in the bytes), and a feedback recorder.
#pragma once

#include <boost/shared_ptr.hpp>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <vector>

#include <ros/ros.h>
#include <ros/serialization.h>

#include "pkm_accuracy/ros/WorkspaceQuery.hpp"

namespace pkm_accuracy_test {

template <class M>
std::vector<std::uint8_t> bytes(const M& m) {
  std::vector<std::uint8_t> b(ros::serialization::serializationLength(m));
  ros::serialization::OStream out(b.data(), static_cast<std::uint32_t>(b.size()));
  ros::serialization::serialize(out, m);
  return b;
}

/// A message of another type with the same definition (same checksum, hence the same wire format).
template <class To, class From>
To convert(const From& from) {
  std::vector<std::uint8_t> b = bytes(from);
  To to;
  ros::serialization::IStream in(b.data(), static_cast<std::uint32_t>(b.size()));
  ros::serialization::deserialize(in, to);
  return to;
}

/// Every field of the outcome (workspace, trajectory and variety ones) set to a value of its own.
inline pkm_accuracy::ros_layer::WorkspaceOutcome filledOutcome() {
  pkm_accuracy::ros_layer::WorkspaceOutcome o;
  o.success = true;
  o.message = "m";
  o.busy = true;
  o.job_id = 7;
  o.verdict = "UNSAFE";
  o.reason = "r";
  for (std::size_t k = 0; k < 6; ++k) {
    o.lower_bound[k] = 1.0 + static_cast<double>(k);
    o.upper_bound[k] = 2.0 + static_cast<double>(k);
    o.witness_pose[k] = 3.0 + static_cast<double>(k);
    o.witness_error[k] = 4.0 + static_cast<double>(k);
    o.undecided_min[k] = 5.0 + static_cast<double>(k);
    o.undecided_max[k] = 6.0 + static_cast<double>(k);
  }
  o.converged = true;
  o.lower_bound_poses.assign(36, 0.5);
  o.lower_bound_times.assign(6, 0.75);
  o.lower_bound_geometries = {29.5, 30.5, 31.5};
  o.has_witness = true;
  o.witness_t = 1.25;
  o.witness_component = 3;
  o.boxes = 8;
  o.max_depth = 9;
  o.threads = 10;
  o.seconds = 11.0;
  o.safe_fraction = 0.1;
  o.unsafe_fraction = 0.2;
  o.undecided_fraction = 0.3;
  o.outside_fraction = 0.4;
  o.undecided_boxes = 12;
  o.undecided_boxes_recorded = 13;
  o.undecided_times = {{1.0, 1.5}, {2.0, 2.5}};
  o.geometry_switches = 14;
  o.geometry_splits = 15;
  o.sensitive_poses = 16;
  o.sensitive.component = 2;
  o.sensitive.failing_lower = 17.5;
  o.sensitive.failing_geometry = {18.5, 19.5};
  o.sensitive.passing_geometry = {20.5, 21.5};
  o.sensitive.passing_upper = 22.5;
  o.sensitive.passes_all = true;
  for (std::size_t k = 0; k < 6; ++k) {
    o.sensitive.pose[k] = 23.0 + static_cast<double>(k);
    o.sensitive.region.lo[k] = 24.0 + static_cast<double>(k);
    o.sensitive.region.hi[k] = 25.0 + static_cast<double>(k);
  }
  o.sensitive.t = 26.5;
  o.sensitive.t_start = 27.5;
  o.sensitive.t_end = 28.5;
  // Variety fields (m = 2).
  o.lower_bound_parameters = {0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 1.0, 0.0625, 0.1875, 0.3125, 0.4375};
  o.witness_parameters = {0.5625, 0.6875};
  o.singular_parameters = {0.1, 0.2, 0.3, 0.4};
  o.undecided_parameters_lower = {0.01, 0.02, 0.03, 0.04};
  o.undecided_parameters_upper = {0.05, 0.06, 0.07, 0.08};
  o.sensitive.parameters = {0.81, 0.82};
  o.sensitive.region_lower = {0.71, 0.72};
  o.sensitive.region_upper = {0.91, 0.92};
  return o;
}

/// Records the feedback of a goal (Feedback: the action's feedback message).
template <class Feedback>
struct FeedbackLog {
  std::mutex mutex;
  std::vector<Feedback> got;
  std::function<void(const boost::shared_ptr<const Feedback>&)> callback() {
    return [this](const boost::shared_ptr<const Feedback>& f) {
      std::lock_guard<std::mutex> lock(mutex);
      got.push_back(*f);
    };
  }
  /// Waits until some feedback reports boxes processed.
  bool waitForBoxes(double timeout) {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
    while (ros::WallTime::now() < deadline) {
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (!got.empty() && got.back().boxes > 0) return true;
      }
      ros::WallDuration(0.02).sleep();
    }
    return false;
  }
};

}  // namespace pkm_accuracy_test
