#!/usr/bin/env python3
"""Coordinator failures with real processes over loopback: a coordinator killed and restarted from
its journal, a standby taking over, two coordinators at once, missions in a row with the same
agents, a test tool commanding a robot mid-mission, bad journals. The safety monitor watches every
fleet. Every wait is on a condition with a generous deadline."""
import json
import os
import re
import signal
import sqlite3
import subprocess
import sys
import time
import unittest

import yaml

sys.path.insert(0, os.path.dirname(__file__))
from test_fleet import BIN, CONFIG, DDS_DIR, MISSION, STEP, Fleet, failed, read, wait_for  # noqa: E402

TESTS = [
    "test_coordinator_killed_and_restarted_with_its_journal_does_each_task_once",
    "test_standby_takes_over_when_the_active_coordinator_is_killed",
    "test_two_coordinators_started_together_one_stands_down",
    "test_coordinator_started_late_stands_down",
    "test_two_missions_in_a_row_with_the_same_agents",
    "test_test_drive_cannot_move_a_robot_the_coordinator_drives",
    "test_bad_journals_are_refused_clearly",
    "test_a_slow_replan_never_makes_the_standby_take_over",
]


def total_visits():
    with open(MISSION) as f:
        return sum(len(task["agents"]) for task in yaml.safe_load(f)["tasks"])


def summary_of(text):
    """The coordinator's --json summary: its last line that is a JSON object."""
    return json.loads(next(line for line in reversed(text.splitlines()) if line.startswith("{")))


def tasks_done(text):
    return max([int(done) for done in re.findall(r"tasks (\d+)/16", text)] or [0])


def first_plan_visits(text):
    """(epoch, task visits) of the first plan in a coordinator log."""
    match = re.search(r"plan epoch (\d+): \d+ robots, (\d+) task visits", text)
    return int(match.group(1)), int(match.group(2))


class FailoverTest(unittest.TestCase):
    def setUp(self):
        self.fleet = Fleet(self._testMethodName, domain=100 + 2 * TESTS.index(self._testMethodName))
        self.journal = os.path.join(self.fleet.dir, "mission.journal")

    def tearDown(self):
        self.fleet.close(keep_logs=failed(self))

    def coordinator(self, name, extra=(), config=CONFIG):
        return self.fleet.start(name, [f"{BIN}/ctsfleet-coordinator", "--config", config, "--dds", "cyclone",
                                       "--domain", str(self.fleet.domain), "--json", *extra])

    def wait_tasks(self, name, count):
        log = self.fleet.log(name)
        wait_for(lambda: "plan epoch" in read(log), 120, f"{name}'s first plan")
        wait_for(lambda: tasks_done(read(log)) >= count, 120, f"{count} tasks done under {name}")

    def assert_safe(self):
        code, text = self.fleet.monitor_verdict()
        self.assertIn("overlaps 0", text, text)
        self.assertIn("coordinators active together 0", text, text)
        self.assertEqual(code, 0, text)

    def journal_rows(self, sql):
        db = sqlite3.connect(self.journal)
        try:
            return db.execute(sql).fetchall()
        finally:
            db.close()

    def test_coordinator_killed_and_restarted_with_its_journal_does_each_task_once(self):
        self.fleet.monitor()
        self.fleet.agents()
        self.coordinator("first", ["--journal", self.journal])
        self.wait_tasks("first", 2)
        first = self.fleet.processes["first"]
        first.send_signal(signal.SIGKILL)
        first.wait()
        # What the dead coordinator had committed: the restart must not plan those visits again.
        done = self.journal_rows("SELECT count(*) FROM visits")[0][0]
        last_epoch = self.journal_rows("SELECT max(epoch) FROM epochs")[0][0]
        self.assertGreater(done, 0)
        restarted_at = time.time()
        self.coordinator("restarted", ["--journal", self.journal])
        code = self.fleet.wait_exit("restarted", 240)
        text = read(self.fleet.log("restarted"))
        self.assertEqual(code, 0, text[-3000:])
        self.assertIn("resuming run 1", text)
        epoch, visits = first_plan_visits(text)
        self.assertGreater(epoch, last_epoch)  # epochs only grow across restarts
        self.assertEqual(visits, total_visits() - done, text[-3000:])  # nothing done is planned again
        summary = summary_of(text)
        self.assertTrue(summary["completed"], summary)
        self.assertEqual(summary["term"], 2)
        print(f"restart: {done} visits from the journal; first command "
              f"{summary['first_command_wall_ms'] / 1000 - restarted_at:.2f} s after the process started")
        # Every (task, role) visit recorded exactly once, and the run closed.
        self.assertEqual(self.journal_rows("SELECT count(*) FROM visits")[0][0], total_visits())
        self.assertEqual(self.journal_rows("SELECT outcome FROM runs"), [("completed",)])
        self.assertEqual(self.journal_rows("SELECT term FROM claims ORDER BY term"), [(1,), (2,)])
        self.assert_safe()

    def test_standby_takes_over_when_the_active_coordinator_is_killed(self):
        self.fleet.monitor()
        self.fleet.agents()
        self.coordinator("active")
        wait_for(lambda: "plan epoch" in read(self.fleet.log("active")), 120, "the active coordinator's first plan")
        self.coordinator("standby", ["--standby"])
        wait_for(lambda: "standby: follows coordinator" in read(self.fleet.log("standby")), 60,
                 "the standby following the active one")
        self.wait_tasks("active", 2)
        active = self.fleet.processes["active"]
        active.send_signal(signal.SIGKILL)
        killed_at = time.time()
        active.wait()
        code = self.fleet.wait_exit("standby", 240)
        text = read(self.fleet.log("standby"))
        self.assertEqual(code, 0, text[-3000:])
        took_over = re.search(r"taking over as term 2 at epoch (\d+); (\d+) task visits", text)
        self.assertTrue(took_over, text[-3000:])
        epoch, visits = first_plan_visits(text[took_over.start():])
        self.assertGreater(epoch, int(took_over.group(1)))
        self.assertEqual(visits, total_visits() - int(took_over.group(2)))  # no visit planned twice
        summary = summary_of(text)
        self.assertTrue(summary["completed"] and summary["took_over"], summary)
        print(f"failover: the standby's first command {summary['first_command_wall_ms'] / 1000 - killed_at:.2f} s "
              f"after SIGKILL of the active coordinator")
        self.assert_safe()

    def test_two_coordinators_started_together_one_stands_down(self):
        self.fleet.monitor()
        self.fleet.agents()
        self.coordinator("one")
        self.coordinator("two")
        codes = {name: self.fleet.wait_exit(name, 240) for name in ("one", "two")}
        texts = {name: read(self.fleet.log(name)) for name in codes}
        self.assertEqual(sorted(codes.values()), [0, 5], texts)
        loser = next(name for name, code in codes.items() if code == 5)
        winner = next(name for name, code in codes.items() if code == 0)
        self.assertIn("standing down: coordinator", texts[loser])
        self.assertIn("--standby", texts[loser])  # says what to do instead
        self.assertNotIn("plan epoch", texts[loser])  # it never drove
        self.assertTrue(summary_of(texts[winner])["completed"])
        self.assert_safe()

    def test_coordinator_started_late_stands_down(self):
        self.fleet.monitor()
        self.fleet.agents()
        self.coordinator("first")
        self.wait_tasks("first", 1)
        self.coordinator("late")
        self.assertEqual(self.fleet.wait_exit("late", 60), 5, read(self.fleet.log("late"))[-3000:])
        late = read(self.fleet.log("late"))
        self.assertIn("it claimed the fleet first", late)
        self.assertIn("the same mission", late)
        code = self.fleet.wait_exit("first", 240)
        self.assertEqual(code, 0, read(self.fleet.log("first"))[-3000:])
        self.assert_safe()

    def test_two_missions_in_a_row_with_the_same_agents(self):
        self.fleet.monitor()
        self.fleet.agents()
        for run in ("mission1", "mission2"):
            self.coordinator(run, ["--journal", self.journal])
            code = self.fleet.wait_exit(run, 240)
            text = read(self.fleet.log(run))
            self.assertEqual(code, 0, text[-3000:])
            self.assertTrue(summary_of(text)["completed"])
            self.assertNotIn("resuming", text)  # the journal's run was closed: a new run starts
        self.assertEqual(self.journal_rows("SELECT run, outcome FROM runs"), [(1, "completed"), (2, "completed")])
        self.assert_safe()

    def test_test_drive_cannot_move_a_robot_the_coordinator_drives(self):
        self.fleet.monitor()
        self.fleet.agents()
        self.fleet.agent("robot8", (1, 1))  # an extra robot: in the plan, holding its cell
        # Plan only once all nine are heard: then robot8, on no role's start, is the one without a
        # role (with a quorum of 8, a robot heard late could be left out instead).
        self.coordinator("coordinator", config=self.fleet.config_with(quorum=9))
        log = self.fleet.log("coordinator")
        wait_for(lambda: "plan epoch" in read(log) and "robot robot8 has no role" in read(log), 120,
                 "a plan with robot8 in it")
        # A step to a free neighbour: the robot follows the coordinator (higher term, stronger command
        # ownership), so the test tool's command is never carried out.
        drive = subprocess.run([f"{BIN}/ctsfleet-test-drive", "--robot", "robot8", "--domain", str(self.fleet.domain),
                                "--dds-config-dir", DDS_DIR, "--path", "2,1", "--timeout", "3"],
                               capture_output=True, text=True, timeout=60)
        self.assertEqual(drive.returncode, 3, drive.stdout + drive.stderr)
        self.assertIn("no arrival at 2,1", drive.stdout)
        code = self.fleet.wait_exit("coordinator", 240)
        text = read(log)
        self.assertEqual(code, 0, text[-3000:])
        self.assertEqual(summary_of(text)["off_plan"], 0)
        self.assert_safe()

    def test_a_slow_replan_never_makes_the_standby_take_over(self):
        # Both coordinators replan with the anytime solver for 6 s (with no stall limit it uses its
        # whole limit, however few tasks are left); the active one plans beside its loop, so its
        # heartbeat goes on and the standby stays a standby.
        with open(CONFIG) as f:
            config = yaml.safe_load(f)
        config["mission"] = os.path.abspath(MISSION)
        config["dds"]["config_dir"] = os.path.abspath(DDS_DIR)
        config["planner"].update({"replan_solver": "cts-pll-v3", "replan_time_limit_s": 6.0, "lns_stall_iterations": 0})
        config["timing"]["replacement_timeout_s"] = 5
        slow = os.path.join(self.fleet.dir, "slow-replan.yaml")
        with open(slow, "w") as f:
            yaml.safe_dump(config, f)
        self.fleet.monitor()
        self.fleet.agents()
        self.fleet.agent("robot8", (1, 1))  # an extra robot: takes the lost role, so the mission can end
        self.coordinator("active", config=slow)
        wait_for(lambda: "plan epoch" in read(self.fleet.log("active")), 120, "the active coordinator's first plan")
        self.coordinator("standby", ["--standby"], config=slow)
        wait_for(lambda: "standby: follows coordinator" in read(self.fleet.log("standby")), 60,
                 "the standby following the active one")
        self.wait_tasks("active", 2)
        text = read(self.fleet.log("active"))
        victim = re.search(r"robot (robot\d+) takes role 3", text).group(1)
        self.fleet.processes[victim].send_signal(signal.SIGKILL)
        code = self.fleet.wait_exit("active", 240)
        text = read(self.fleet.log("active"))
        self.assertIn(code, (0, 3), text[-3000:])
        replans = [int(ms) for ms in re.findall(r"plan epoch \d+: .* planned in (\d+) ms", text)][1:]
        self.assertTrue(replans and max(replans) >= 5000, f"no slow replan happened: {replans}")
        summary = summary_of(text)
        self.assertFalse(summary["stood_down"], summary)
        standby = read(self.fleet.log("standby"))
        self.assertNotIn("taking over", standby, standby[-3000:])
        print(f"slow replan: replans of {replans} ms; the standby never took over; "
              f"{summary['tasks_done']}/{summary['tasks_total']} tasks")
        self.assert_safe()

    def test_bad_journals_are_refused_clearly(self):
        def coordinator(journal):
            return subprocess.run([f"{BIN}/ctsfleet-coordinator", "--config", CONFIG, "--domain",
                                   str(self.fleet.domain), "--journal", journal],
                                  capture_output=True, text=True, timeout=60)

        garbage = os.path.join(self.fleet.dir, "garbage.journal")
        content = b"this is not an SQLite file, but it is long enough to look like one" * 100
        with open(garbage, "wb") as f:
            f.write(content)
        result = coordinator(garbage)
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn(f"--journal {garbage}: not a readable journal", result.stderr)
        with open(garbage, "rb") as f:
            self.assertEqual(f.read(), content)  # left as it was

        other = os.path.join(self.fleet.dir, "other.journal")
        db = sqlite3.connect(other)
        db.execute("CREATE TABLE meta(key TEXT PRIMARY KEY, value TEXT NOT NULL)")
        db.execute("INSERT INTO meta VALUES('format', 'ctsfleet-journal-1'), ('mission', '0123456789abcdef'), "
                   "('description', 'some other mission')")
        db.commit()
        db.close()
        result = coordinator(other)
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("the journal of another mission (0123456789abcdef: some other mission)", result.stderr)

        # A live coordinator holds its journal: a second one with the same file is refused.
        self.coordinator("holder", ["--journal", self.journal])
        wait_for(lambda: "coordinator " in read(self.fleet.log("holder")), 60, "the first coordinator up")
        result = coordinator(self.journal)
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("in use by another coordinator", result.stderr)


if __name__ == "__main__":
    unittest.main(verbosity=2)
