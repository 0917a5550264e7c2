#!/usr/bin/python3
"""planner_example.py: a rospy motion planner that asks the accuracy_checker node before it executes a motion.

The planner plans a timed motion of the platform and:
  1. asks the service /verify_trajectory, giving the motion as a nav_msgs/Path (the times are the poses' stamps),
     whether every pose of it keeps the worst-case error within the task's tolerances (mode "verify"). It executes
     the motion only on a certified SAFE; UNSAFE (a pose provably violating a tolerance, reported with its time and
     pose), UNDECIDED and failures all mean "do not execute".
  2. asks the action ~verify_trajectory (actionlib), giving the same motion as a trajectory_msgs/
     MultiDOFJointTrajectory, for the certified worst-case errors along it (mode "max_error"), printing the
     feedback while it runs and cancelling the goal if no result arrives within ~timeout: the margin to each
     tolerance, for the planner's log.
A "busy" answer (the node runs ~max_parallel_jobs jobs already) is retried until ~timeout.

Parameters (private; on the command line as _name:=value, lists as _tolerances:="[1.0e-4, 1.0e-4, 1.0e-4, 1.0e-3,
1.0e-3, 1.0e-3]"; numbers written as strings, such as YAML 1.1's 1e-4, are read as numbers):
  ~tolerances      [dx, dy, dz (m), drx, dry, drz (rad)]; default [1e-3, 1e-3, 1e-3, 1e-2, 1e-2, 1e-2]
  ~waypoints       flat list, 7 numbers per waypoint: t (s, from now), x, y, z (m, ~frame_id), roll, pitch, yaw (rad),
                   R = Rz(yaw) Ry(pitch) Rx(roll); default 3 waypoints over 3 s inside a 2 cm box around [0, 0, 0.475]
  ~frame_id        frame of the waypoints ("" = the robot's base frame; any tf2 frame)
  ~time_budget     s, per check (default 10)
  ~timeout         s, for the node to appear and answer each check (default 60)
  ~service         default /verify_trajectory
  ~action          default /pkm_accuracy/verify_trajectory
  ~report_errors   bool, default true: step 2
  ~exit_when_done  bool, default true: exit after the decision; false: keep running until shut down (the latched
                   ~decision stays available)
Topic: ~decision (std_msgs/String, latched): "executing" or "not executing: <why>".
Exit status: 0 executed, 1 not executed (the motion is not certified SAFE), 2 no answer or an invalid parameter.

  rosrun pkm_accuracy planner_example.py
  rosrun pkm_accuracy planner_example.py _tolerances:="[1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-6]"   (UNSAFE)
"""
import math
import sys

import actionlib
import rospy
from geometry_msgs.msg import PoseStamped, Quaternion, Transform
from nav_msgs.msg import Path
from std_msgs.msg import String
from trajectory_msgs.msg import MultiDOFJointTrajectory, MultiDOFJointTrajectoryPoint

from pkm_accuracy.msg import VerifyTrajectoryAction, VerifyTrajectoryGoal
from pkm_accuracy.srv import VerifyTrajectory, VerifyTrajectoryRequest, VerifyTrajectoryResponse

COMPONENTS = ["dx", "dy", "dz", "drx", "dry", "drz"]
UNITS = ["m", "m", "m", "rad", "rad", "rad"]
DEFAULT_TOLERANCES = [1e-3, 1e-3, 1e-3, 1e-2, 1e-2, 1e-2]
DEFAULT_WAYPOINTS = [0.0, -0.01, 0.01, 0.47, 0.0, -0.01, 0.005,
                     1.5, 0.0, -0.005, 0.475, 0.01, 0.0, -0.01,
                     3.0, 0.01, -0.01, 0.48, -0.01, 0.01, 0.0]


class ParameterError(Exception):
    pass


def as_number(v):
    """A number, or a string that is one (YAML 1.1 reads 1e-6 as a string), as a float; None otherwise."""
    if isinstance(v, bool):
        return None
    if isinstance(v, (int, float)):
        return float(v)
    try:
        return float(v) if isinstance(v, str) else None
    except ValueError:
        return None


def numbers(name, default, count=None, per=None):
    """A private parameter that is a list of numbers (count of them, or a multiple of per)."""
    value = rospy.get_param("~" + name, default)
    full = rospy.resolve_name("~" + name)
    if not isinstance(value, list) or any(as_number(v) is None for v in value):
        raise ParameterError("%s: expected a list of numbers, got %r" % (full, value))
    value = [as_number(v) for v in value]
    if not all(math.isfinite(v) for v in value):
        raise ParameterError("%s: expected finite numbers, got %r" % (full, value))
    if count is not None and len(value) != count:
        raise ParameterError("%s: expected %d numbers, got %d" % (full, count, len(value)))
    if per is not None and (len(value) < 2 * per or len(value) % per != 0):
        raise ParameterError("%s: expected %d numbers per waypoint and at least 2 waypoints, got %d numbers"
                             % (full, per, len(value)))
    return value


def number(name, default, minimum=0.0):
    value = rospy.get_param("~" + name, default)
    x = as_number(value)
    if x is None or not x > minimum or not math.isfinite(x):
        raise ParameterError("%s: expected a finite number > %g, got %r" % (rospy.resolve_name("~" + name), minimum,
                                                                            value))
    return x


def quaternion(roll, pitch, yaw):
    """The unit quaternion of R = Rz(yaw) Ry(pitch) Rx(roll)."""
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return Quaternion(x=sr * cp * cy - cr * sp * sy, y=cr * sp * cy + sr * cp * sy,
                      z=cr * cp * sy - sr * sp * cy, w=cr * cp * cy + sr * sp * sy)


def plan(waypoints, frame_id, start):
    """The planned motion as a nav_msgs/Path (stamps start + t) and as a MultiDOFJointTrajectory (one joint)."""
    path = Path()
    path.header.frame_id = frame_id
    path.header.stamp = start
    trajectory = MultiDOFJointTrajectory()
    trajectory.header = path.header
    trajectory.joint_names = ["platform"]
    for i in range(0, len(waypoints), 7):
        t, x, y, z, roll, pitch, yaw = waypoints[i:i + 7]
        pose = PoseStamped()
        pose.header.stamp = start + rospy.Duration.from_sec(t)
        pose.header.frame_id = frame_id
        pose.pose.position.x, pose.pose.position.y, pose.pose.position.z = x, y, z
        pose.pose.orientation = quaternion(roll, pitch, yaw)
        path.poses.append(pose)
        transform = Transform()
        transform.translation.x, transform.translation.y, transform.translation.z = x, y, z
        transform.rotation = pose.pose.orientation
        point = MultiDOFJointTrajectoryPoint()
        point.transforms.append(transform)
        point.time_from_start = rospy.Duration.from_sec(t)
        trajectory.points.append(point)
    return path, trajectory


def describe_witness(answer, start):
    k = answer.witness_component
    p = answer.witness.position
    return ("the %s tolerance is exceeded at t=%.3f s (%.3f s into the motion), pose x=%.4f y=%.4f z=%.4f m: "
            "error >= %.3g %s" % (COMPONENTS[k], answer.witness_t, answer.witness_t - start.to_sec(), p.x, p.y, p.z,
                                  answer.witness_error[k], UNITS[k]))


def check_with_service(service, path, tolerances, time_budget, deadline):
    """Step 1: /verify_trajectory on the path, mode verify. Returns the response, or None if there was no answer."""
    request = VerifyTrajectoryRequest()
    request.path = path
    request.thresholds = tolerances
    request.mode = VerifyTrajectoryRequest.MODE_VERIFY
    request.time_budget = time_budget
    remaining = (deadline - rospy.Time.now()).to_sec()
    try:
        rospy.wait_for_service(service, timeout=max(remaining, 0.1))
    except rospy.ROSException:
        rospy.logerr("planner: %s did not appear within ~timeout", service)
        return None
    verify = rospy.ServiceProxy(service, VerifyTrajectory)
    while not rospy.is_shutdown():
        try:
            response = verify(request)
        except rospy.ServiceException as e:
            rospy.logerr("planner: %s failed: %s", service, e)
            return None
        if not response.busy or rospy.Time.now() > deadline:
            return response
        rospy.loginfo("planner: the node is busy; retrying")
        rospy.sleep(0.5)
    return None


def report_errors(action, trajectory, tolerances, time_budget, deadline):
    """Step 2: ~verify_trajectory on the MultiDOFJointTrajectory, mode max_error. Returns the result or None."""
    client = actionlib.SimpleActionClient(action, VerifyTrajectoryAction)
    if not client.wait_for_server(rospy.Duration(max((deadline - rospy.Time.now()).to_sec(), 0.1))):
        rospy.logerr("planner: the action %s did not appear within ~timeout", action)
        return None
    goal = VerifyTrajectoryGoal()
    goal.multi_dof_trajectory = trajectory
    goal.mode = VerifyTrajectoryRequest.MODE_MAX_ERROR
    goal.alpha = 0.05
    goal.time_budget = time_budget

    def feedback(f):
        rospy.loginfo("planner: job %d: %d boxes, %.0f%% of the motion bounded, %.2f s", f.job_id, f.boxes,
                      100.0 * f.safe_fraction, f.seconds)

    while not rospy.is_shutdown():
        client.send_goal(goal, feedback_cb=feedback)
        remaining = (deadline - rospy.Time.now()).to_sec()
        if not client.wait_for_result(rospy.Duration(max(remaining, 0.1))):
            rospy.logwarn("planner: no result within ~timeout; cancelling the goal")
            client.cancel_goal()
            client.wait_for_result(rospy.Duration(5.0))
            return None
        result = client.get_result()
        if result is not None and result.busy and rospy.Time.now() < deadline:
            rospy.loginfo("planner: the node is busy; retrying")
            rospy.sleep(0.5)
            continue
        if result is None or not result.success:
            rospy.logerr("planner: the action failed: %s", result.message if result else client.get_goal_status_text())
            return None
        return result
    return None


def main():
    rospy.init_node("planner_example")
    decision = rospy.Publisher("~decision", String, queue_size=1, latch=True)

    def decide(text, status):
        rospy.loginfo("planner: %s", text)
        print("planner: " + text, flush=True)
        decision.publish(String(data=text))
        if not rospy.get_param("~exit_when_done", True):
            rospy.spin()  # (until shut down: the latched ~decision stays available)
        return status

    try:
        tolerances = numbers("tolerances", DEFAULT_TOLERANCES, count=6)
        if not all(t > 0 for t in tolerances):
            raise ParameterError("%s: expected 6 numbers > 0, got %r" % (rospy.resolve_name("~tolerances"), tolerances))
        waypoints = numbers("waypoints", DEFAULT_WAYPOINTS, per=7)
        frame_id = rospy.get_param("~frame_id", "")
        if not isinstance(frame_id, str):
            raise ParameterError("%s: expected a string, got %r" % (rospy.resolve_name("~frame_id"), frame_id))
        time_budget = number("time_budget", 10.0)
        timeout = number("timeout", 60.0)
        service = rospy.get_param("~service", "/verify_trajectory")
        action = rospy.get_param("~action", "/pkm_accuracy/verify_trajectory")
        errors = rospy.get_param("~report_errors", True)
    except ParameterError as e:
        return decide("not executing: invalid parameter: %s" % e, 2)

    while rospy.Time.now().is_zero() and not rospy.is_shutdown():  # (simulated time: wait for /clock)
        rospy.sleep(0.01)
    start = rospy.Time.now()
    path, trajectory = plan(waypoints, frame_id, start)
    deadline = start + rospy.Duration.from_sec(timeout)

    answer = check_with_service(service, path, tolerances, time_budget, deadline)
    if answer is None:
        return decide("not executing: no answer from %s" % service, 2)
    if not answer.success:
        return decide("not executing: the check failed: %s" % answer.message, 2)
    rospy.loginfo("planner: %s: %s (%s)", service, answer.verdict, answer.message)
    print("planner: service %s: %s" % (service, answer.verdict), flush=True)

    if errors:
        result = report_errors(action, trajectory, tolerances, time_budget, deadline)
        if result is None:
            return decide("not executing: no worst-case errors from %s" % action, 2)
        for k in range(6):
            print("planner: action %s: worst %s in [%.4g, %.4g] %s (tolerance %.4g)" % (
                action, COMPONENTS[k], result.lower_bound[k], result.upper_bound[k], UNITS[k], tolerances[k]),
                flush=True)

    if answer.verdict == VerifyTrajectoryResponse.VERDICT_SAFE:
        return decide("executing", 0)
    if answer.verdict == VerifyTrajectoryResponse.VERDICT_UNSAFE and answer.has_witness:
        return decide("not executing: UNSAFE, " + describe_witness(answer, start), 1)
    return decide("not executing: %s %s: %s" % (answer.verdict, answer.reason, answer.message), 1)


if __name__ == "__main__":
    sys.exit(main())
