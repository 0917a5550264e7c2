// A stand-in for tf2_ros' static_transform_publisher, whose executable Debian's ROS packages do not ship; same
// command line and the same quaternion (tf2::Quaternion::setRPY), published latched on /tf_static:
//   static_transform_publisher_node x y z yaw pitch roll frame_id child_frame_id
//   static_transform_publisher_node x y z qx qy qz qw frame_id child_frame_id
// Used by frames.test (not a gtest: it publishes until shut down).
#include <cstdlib>
#include <string>
#include <vector>

#include <geometry_msgs/TransformStamped.h>
#include <ros/ros.h>
#include <tf2/LinearMath/Quaternion.h>
#include <tf2_ros/static_transform_broadcaster.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "static_transform_publisher", ros::init_options::AnonymousName);
  std::vector<std::string> args;
  ros::removeROSArgs(argc, argv, args);
  if (args.size() != 9 && args.size() != 10) {
    ROS_FATAL("usage: %s x y z yaw pitch roll frame_id child_frame_id | x y z qx qy qz qw frame_id child_frame_id",
              args.empty() ? "static_transform_publisher_node" : args[0].c_str());
    return 1;
  }
  ros::NodeHandle nh;
  geometry_msgs::TransformStamped t;
  t.header.stamp = ros::Time::now();
  t.transform.translation.x = std::atof(args[1].c_str());
  t.transform.translation.y = std::atof(args[2].c_str());
  t.transform.translation.z = std::atof(args[3].c_str());
  tf2::Quaternion q;
  if (args.size() == 9) {
    q.setRPY(std::atof(args[6].c_str()), std::atof(args[5].c_str()), std::atof(args[4].c_str()));
  } else {
    q = tf2::Quaternion(std::atof(args[4].c_str()), std::atof(args[5].c_str()), std::atof(args[6].c_str()),
                        std::atof(args[7].c_str()));
  }
  t.transform.rotation.x = q.x();
  t.transform.rotation.y = q.y();
  t.transform.rotation.z = q.z();
  t.transform.rotation.w = q.w();
  t.header.frame_id = args[args.size() - 2];
  t.child_frame_id = args[args.size() - 1];
  tf2_ros::StaticTransformBroadcaster broadcaster;
  broadcaster.sendTransform(t);
  ros::spin();
  return 0;
}
