// accuracy_checker: the pkm_accuracy ROS node. See docs/ros_api.md and AccuracyCheckerNode.hpp.
#include <exception>
#include <string>

#include <ros/ros.h>

#include "pkm_accuracy/ros/AccuracyCheckerNode.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "accuracy_checker");
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  try {
    pkm_accuracy::ros_layer::AccuracyCheckerNode node(nh, pnh);
    std::string error;
    if (!node.start(error)) {
      ROS_FATAL("accuracy_checker: no robot could be loaded, exiting. %s", error.c_str());
      return 1;
    }
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("accuracy_checker: %s", e.what());
    return 2;
  }
  return 0;
}
