#!/usr/bin/python3
"""rostest (planner_example.test): scripts/planner_example.py, run as a program against the node.

The example is started the way a user starts it (the executable roslaunch and rosrun find for pkm_accuracy: the
devel-space or install-space relay, whose interpreter is /usr/bin/python3), with private parameters on its command
line; its exit status, its ~decision and its printed report are checked. The worst-case errors it prints (the node's
max_error bracket) are checked against the verdicts: SAFE tolerances lie above every lower bound, and the UNSAFE
witness's component has a lower bound above its tolerance.
"""
import os
import re
import signal
import subprocess
import sys
import unittest

import roslib.packages
import rospy
import rostest
from std_msgs.msg import String

PKG = "pkm_accuracy"
TINY = "[1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-6]"  # (YAML 1.1 strings: the example reads them as numbers)


def example():
    """The executable `rosrun pkm_accuracy planner_example.py` runs (the first one roslaunch would pick)."""
    found = [p for p in roslib.packages.find_node(PKG, "planner_example.py") if os.access(p, os.X_OK)]
    if not found:
        raise AssertionError("planner_example.py: not found for package %s" % PKG)
    return found[0]


def run(name, *args):
    """Runs the example as node `name`; returns (exit status, stdout)."""
    p = subprocess.run([example(), "__name:=" + name] + list(args), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       universal_newlines=True, timeout=90)
    return p.returncode, p.stdout


def bounds(out):
    """The printed worst-case errors: component -> (lower, upper, tolerance)."""
    pattern = r"worst (\w+) in \[([^,]+), ([^\]]+)\] \w+ \(tolerance ([^)]+)\)"
    return {m.group(1): tuple(float(m.group(i)) for i in (2, 3, 4)) for m in re.finditer(pattern, out)}


class PlannerExample(unittest.TestCase):
    def test_interpreter_is_debian_python(self):
        with open(example()) as f:
            self.assertEqual(f.readline().strip(), "#!/usr/bin/python3")

    def test_safe_motion_executes(self):
        status, out = run("planner_safe")
        self.assertEqual(status, 0, out)
        self.assertIn("service /verify_trajectory: SAFE", out)
        self.assertIn("planner: executing", out)
        b = bounds(out)
        self.assertEqual(sorted(b), sorted(["dx", "dy", "dz", "drx", "dry", "drz"]), out)
        for k, (lower, upper, tolerance) in b.items():
            self.assertGreater(lower, 0.0, k)
            self.assertLessEqual(lower, upper, k)
            self.assertLessEqual(lower, tolerance, k)  # SAFE: the worst error is within every tolerance

    def test_unsafe_motion_does_not_execute_and_says_when(self):
        status, out = run("planner_unsafe", "_tolerances:=" + TINY)
        self.assertEqual(status, 1, out)
        self.assertIn("service /verify_trajectory: UNSAFE", out)
        m = re.search(r"not executing: UNSAFE, the (\w+) tolerance is exceeded at t=([0-9.]+) s \(([0-9.]+) s into "
                      r"the motion\)", out)
        self.assertIsNotNone(m, out)
        self.assertGreaterEqual(float(m.group(3)), 0.0)
        self.assertLessEqual(float(m.group(3)), 3.0 + 1e-6)  # within the planned 3 s
        lower = bounds(out)[m.group(1)][0]
        self.assertGreater(lower, 1.0e-6)  # the action's certified lower bound agrees: the tolerance is exceeded

    def test_invalid_parameter_is_refused_by_name(self):
        status, out = run("planner_bad", "_tolerances:=[1.0e-3, 1.0e-3]")
        self.assertEqual(status, 2, out)
        self.assertIn("invalid parameter: /planner_bad/tolerances: expected 6 numbers, got 2", out)
        status, out = run("planner_bad_word", "_tolerances:=[1.0e-3, 1.0e-3, 1.0e-3, 1.0e-2, 1.0e-2, tight]")
        self.assertEqual(status, 2, out)
        self.assertIn("invalid parameter: /planner_bad_word/tolerances: expected a list of numbers", out)

    def test_decision_is_published_latched(self):
        got = []
        rospy.Subscriber("/planner_latched/decision", String, lambda m: got.append(m.data))
        proc = subprocess.Popen([example(), "__name:=planner_latched", "_report_errors:=false",
                                 "_exit_when_done:=false"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                universal_newlines=True)
        try:
            deadline = rospy.Time.now() + rospy.Duration(60.0)
            while not got and rospy.Time.now() < deadline and not rospy.is_shutdown():
                rospy.sleep(0.05)
            self.assertIsNone(proc.poll())  # still running: the decision stays latched
        finally:
            proc.send_signal(signal.SIGINT)
            out, _ = proc.communicate(timeout=30)
        self.assertEqual(got[:1], ["executing"], out)
        self.assertNotIn("worst dx", out)  # ~report_errors false: no action goal


if __name__ == "__main__":
    rospy.init_node("planner_example_test")
    rostest.rosrun(PKG, "planner_example", PlannerExample, sys.argv)
