#!/usr/bin/env python3
"""Hosts whose clocks disagree: robot agents whose wall clocks run seconds ahead or behind
(--test-clock-skew-ms) still take their coordinator's commands in time, and the safety monitor,
which puts every robot's stamps on its own clock, still finds a planted overlap and reports no
false one. Real processes on loopback, domains 172-179."""
import os
import re
import signal
import subprocess
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(__file__))
from test_fleet import BIN, DDS_DIR, Fleet, failed, read, role_starts, wait_for  # noqa: E402

TESTS = [
    "test_mission_with_clocks_seconds_apart_completes_safely",
    "test_monitor_judges_skewed_robots_on_one_clock",
]
SKEW_MS = 2500  # more than a command's deadline margin at these steps (4 steps + 1 s = 1.2 s)


class ClockTest(unittest.TestCase):
    def setUp(self):
        self.fleet = Fleet(self._testMethodName, domain=172 + 2 * TESTS.index(self._testMethodName))

    def tearDown(self):
        self.fleet.close(keep_logs=failed(self))

    def verdict(self, name):
        self.fleet.processes[name].send_signal(signal.SIGINT)
        code = self.fleet.wait_exit(name, 60)
        return code, read(self.fleet.log(name))

    def test_mission_with_clocks_seconds_apart_completes_safely(self):
        self.fleet.monitor()
        for index, cell in enumerate(role_starts()):
            skew = SKEW_MS if index % 2 == 0 else -SKEW_MS
            self.fleet.agent(f"robot{index}", cell, extra=["--test-clock-skew-ms", str(skew)])
        self.fleet.coordinator()
        code = self.fleet.wait_exit("coordinator", 240)
        text = read(self.fleet.log("coordinator"))
        self.assertEqual(code, 0, text[-3000:])
        self.assertIn("mission completed: tasks 16/16", text)
        for index in range(8):
            self.assertNotIn("deadline passed", read(self.fleet.log(f"robot{index}")))
        code, text = self.verdict("monitor")
        self.assertIn("overlaps 0", text, text)
        self.assertEqual(code, 0, text)

    def drive(self, robot, path):
        result = subprocess.run([f"{BIN}/ctsfleet-test-drive", "--robot", robot, "--domain", str(self.fleet.domain),
                                 "--dds-config-dir", DDS_DIR, "--path", path, "--epoch", "1"],
                                capture_output=True, text=True, timeout=120)
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)

    def start_monitor(self, name, robots):
        self.fleet.start(name, [f"{BIN}/ctsfleet-monitor", "--domain", str(self.fleet.domain),
                                "--dds-config-dir", DDS_DIR])
        for robot in robots:
            wait_for(lambda: f"first state of {robot}" in read(self.fleet.log(name)), 60, f"{name} hearing {robot}")

    def test_monitor_judges_skewed_robots_on_one_clock(self):
        skew = 10000  # well beyond how long the drives below take, whatever the load
        # A (clock 10 s ahead) and B (10 s behind) hold cell (2,1) in turn, a second apart, B staying
        # there: on their own stamps B arrives long before A leaves.
        self.fleet.agent("robotA", (1, 1), extra=["--test-clock-skew-ms", str(skew)])
        self.fleet.agent("robotB", (3, 1), extra=["--test-clock-skew-ms", str(-skew)])
        # C (10 s behind) and D (10 s ahead, staying) really meet on (6,1): on their own stamps C has
        # left long before D arrives.
        self.fleet.agent("robotC", (5, 1), extra=["--test-clock-skew-ms", str(-skew)])
        self.fleet.agent("robotD", (7, 1), extra=["--test-clock-skew-ms", str(skew)])
        self.start_monitor("monitor1", ("robotA", "robotB"))
        self.drive("robotA", "2,1")
        self.drive("robotA", "1,1")
        time.sleep(1.0)  # the gap between the two visits; load only makes it longer
        self.drive("robotB", "2,1")
        code, text = self.verdict("monitor1")
        self.assertIn("overlaps 0", text, text)
        self.assertEqual(code, 0, text)
        self.start_monitor("monitor2", ("robotC", "robotD"))
        self.drive("robotD", "6,1")
        self.drive("robotC", "6,1")  # onto D: a collision the monitor must see
        self.drive("robotC", "5,1")
        code, text = self.verdict("monitor2")
        self.assertRegex(text, r"overlaps [1-9]", text)
        self.assertIn("robotC", text)
        self.assertEqual(code, 1, text)

if __name__ == "__main__":
    unittest.main()
