#!/usr/bin/env python3
"""Multi-process fleet tests: a real coordinator, real robot agents and an independent safety
monitor, talking DDS over loopback, each test on its own domain. Every wait is on a condition
with a generous deadline, so a loaded machine only makes the tests slower."""
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import yaml

BIN = os.environ.get("CTSFLEET_BIN", os.path.join(os.path.dirname(__file__), "../../build/bin"))
ROOT = os.environ.get("CTSFLEET_ROOT", os.path.join(os.path.dirname(__file__), "../.."))
CONFIG = os.path.join(ROOT, "config/fleet.yaml")
DDS_DIR = os.path.join(ROOT, "config/dds")
MISSION = os.path.join(ROOT, "config/default/mission-8.yaml")
STEP = "0.05"
TESTS = [
    "test_mission_completes_safely",
    "test_cross_vendor_cyclone_coordinator_fastdds_agents",
    "test_cross_vendor_fastdds_coordinator_cyclone_agents",
    "test_killed_agent_is_detected_and_the_others_finish",
    "test_new_agent_takes_over_the_dead_robots_role",
    "test_jitter_up_to_three_times_the_step",
    "test_hostile_messages_change_nothing",
    "test_bad_configuration_and_arguments",
    "test_silent_robot_is_taken_out",
    "test_extra_robot_takes_over_a_lost_role",
    "test_ctrl_c_stops_the_whole_fleet",
    "test_fastdds_hears_more_than_ten_robots",
    "test_restarted_robot_with_the_same_id_rejoins",
    "test_duplicate_id_is_refused_and_reported",
    "test_impostor_started_first_one_body_moves_and_nobody_collides",
    "test_robot_moved_by_hand_is_taken_out_and_planned_around",
    "test_robot_deaf_to_commands_is_taken_out_and_rejoins",
    "test_fastdds_robot_deaf_to_commands_is_taken_out_and_rejoins",
    "test_mission_with_turns_completes_safely",
    "test_robot_restarted_facing_another_way_in_a_fleet_that_turns",
]


def role_starts():
    with open(MISSION) as f:
        mission = yaml.safe_load(f)
    return [tuple(a["start"]) for a in mission["agents"]]


def wait_for(predicate, timeout, what):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return
        time.sleep(0.1)
    raise AssertionError(f"timed out after {timeout} s waiting for {what}")


def read(path):
    with open(path, errors="replace") as f:
        return f.read()


class Fleet:
    """The processes of one test; everything is stopped by close()."""

    def __init__(self, test_name, domain=None):
        # Apart, so no test ever hears another: 40-79 here, 100-139 in test_failover.py.
        self.domain = 40 + 2 * TESTS.index(test_name) if domain is None else domain
        self.dir = tempfile.mkdtemp(prefix=f"ctsfleet-{test_name}-")
        self.processes = {}
        self.files = []
        self.fleet_ca = None  # set by secure(): every process then runs with DDS Security

    def enrol(self, role, name, fleet_ca=None, days=None):
        """Enrols one participant in the fleet CA with ctsfleet-ca."""
        args = [f"{BIN}/ctsfleet-ca", f"add-{role}", fleet_ca or self.fleet_ca, name]
        if days is not None:
            args += ["--days", str(days)]
        subprocess.run(args, check=True, capture_output=True, timeout=60)

    def secure(self, robots, coordinators=("coordinator",), observers=("monitor",)):
        """Makes this test's fleet CA and enrols these participants; the processes started after it
        present their identities."""
        self.fleet_ca = os.path.join(self.dir, "fleet-ca")
        subprocess.run([f"{BIN}/ctsfleet-ca", "init", self.fleet_ca], check=True, capture_output=True, timeout=60)
        for name in coordinators:
            self.enrol("coordinator", name)
        for name in observers:
            self.enrol("observer", name)
        for name in robots:
            self.enrol("robot", name)

    def security(self, identity=None):
        """The options that make a process present `identity` (none when the fleet is open)."""
        if self.fleet_ca is None:
            return []
        return ["--security", self.fleet_ca] + (["--identity", identity] if identity else [])

    def log(self, name):
        return os.path.join(self.dir, name + ".log")

    def start(self, name, args):
        out = open(self.log(name), "w")
        self.files.append(out)
        self.processes[name] = subprocess.Popen(args, stdout=out, stderr=subprocess.STDOUT)
        return self.processes[name]

    def agent(self, robot_id, cell, dds="cyclone", extra=()):
        return self.start(robot_id, [f"{BIN}/ctsfleet-agent", "--id", robot_id, "--start", f"{cell[0]},{cell[1]}",
                                     "--dds", dds, "--domain", str(self.domain), "--step", STEP,
                                     "--dds-config-dir", DDS_DIR, *self.security(), *extra])

    def agents(self, dds="cyclone", extra=()):
        for index, cell in enumerate(role_starts()):
            self.agent(f"robot{index}", cell, dds, extra)

    def config_with(self, quorum=None, **timing):
        """The shipped config with these timing settings (and robots.quorum), written beside the logs."""
        with open(CONFIG) as f:
            config = yaml.safe_load(f)
        config["mission"] = os.path.abspath(MISSION)
        config["dds"]["config_dir"] = os.path.abspath(DDS_DIR)
        config["timing"].update(timing)
        if quorum is not None:
            config["robots"]["quorum"] = quorum
        path = os.path.join(self.dir, "fleet.yaml")
        with open(path, "w") as f:
            yaml.safe_dump(config, f)
        return path

    def coordinator(self, dds="cyclone", config=CONFIG, extra=()):
        return self.start("coordinator", [f"{BIN}/ctsfleet-coordinator", "--config", config, "--dds", dds,
                                          "--domain", str(self.domain), *self.security(), *extra])

    def monitor(self, dds="cyclone"):
        return self.start("monitor", [f"{BIN}/ctsfleet-monitor", "--dds", dds, "--domain", str(self.domain),
                                      "--dds-config-dir", DDS_DIR, *self.security("monitor")])

    def kill_robot(self, robot_id):
        """SIGKILLs robot_id's agent; returns the cell it was last at once the coordinator took it out."""
        log = self.log("coordinator")
        process = self.processes[robot_id]
        process.send_signal(signal.SIGKILL)
        process.wait()
        wait_for(lambda: f"robot {robot_id} taken out" in read(log), 60, f"the loss of {robot_id} detected")
        line = next(l for l in read(log).splitlines() if f"robot {robot_id} taken out" in l)
        return tuple(int(v) for v in re.search(r"last at \((\d+),(\d+)\)", line).groups())

    def wait_exit(self, name, timeout):
        try:
            return self.processes[name].wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            raise AssertionError(f"{name} still running after {timeout} s; its log:\n" + read(self.log(name))[-3000:])

    def monitor_verdict(self):
        self.processes["monitor"].send_signal(signal.SIGINT)
        code = self.wait_exit("monitor", 60)
        return code, read(self.log("monitor"))

    def close(self, keep_logs=False):
        """Stops every process; removes the test's folder unless `keep_logs` (a failed test)."""
        for process in self.processes.values():
            if process.poll() is None:
                process.send_signal(signal.SIGTERM)
        for process in self.processes.values():
            try:
                process.wait(timeout=20)
            except subprocess.TimeoutExpired:
                process.kill()
        for out in self.files:
            out.close()
        if keep_logs:
            print(f"logs kept in {self.dir}", file=sys.stderr)
        else:
            shutil.rmtree(self.dir, ignore_errors=True)


def failed(test):
    """True when `test` (a TestCase in its tearDown) has failed or raised so far."""
    result = getattr(getattr(test, "_outcome", None), "result", None)
    return result is None or any(case is test for case, _ in result.failures + result.errors)


class FleetTest(unittest.TestCase):
    def setUp(self):
        self.fleet = Fleet(self._testMethodName)

    def tearDown(self):
        self.fleet.close(keep_logs=failed(self))

    def assert_pending_explained(self, text, role_without_robot=None):
        """Every task or goal left undone is the lost robot's role, or was blocked by the lost robot
        (it may stand on another robot's goal or task cell)."""
        for line in text.splitlines():
            if not line.startswith("pending:"):
                continue
            if role_without_robot is not None and f"role {role_without_robot} (no robot)" in line:
                continue
            if "could not reach its goal (blocked)" in line:
                continue
            task = re.search(r"task (\d+)", line)
            self.assertTrue(task and f"task {task.group(1)} unreachable" in text, "unexplained: " + line)

    def assert_safe(self):
        code, text = self.fleet.monitor_verdict()
        self.assertIn("overlaps 0", text, text)
        self.assertEqual(code, 0, text)
        match = re.search(r"states (\d+)", text)
        self.assertTrue(match and int(match.group(1)) > 100, "the monitor heard almost nothing:\n" + text)

    def run_mission(self, coordinator_dds, agent_dds):
        self.fleet.monitor(coordinator_dds)
        self.fleet.agents(agent_dds)
        self.fleet.coordinator(coordinator_dds)
        code = self.fleet.wait_exit("coordinator", 240)
        text = read(self.fleet.log("coordinator"))
        self.assertEqual(code, 0, text[-3000:])
        self.assertIn("mission completed: tasks 16/16", text)
        self.assert_safe()

    def test_mission_completes_safely(self):
        self.fleet.monitor()
        launcher = self.fleet.start("sim", [f"{BIN}/ctsfleet-sim", "--robots", "8", "--config", CONFIG,
                                            "--domain", str(self.fleet.domain), "--step", STEP,
                                            "--log-dir", os.path.join(self.fleet.dir, "agents")])
        code = self.fleet.wait_exit("sim", 240)
        text = read(self.fleet.log("sim"))
        self.assertEqual(code, 0, text[-3000:])
        self.assertIn("mission completed: tasks 16/16", text)
        self.assert_safe()

    def test_mission_with_turns_completes_safely(self):
        """Plans with turns (--actions rotate) on robots that take time to turn and are delayed as
        the league's 2026 rules delay robots: every move starts facing its way (no agent had to turn
        on its own), every robot ends the mission, nobody collides."""
        self.fleet.monitor()
        agents_dir = os.path.join(self.fleet.dir, "agents")
        delays = os.path.join(self.fleet.dir, "delays.json")
        with open(delays, "w") as f:
            f.write('{"seed": 0, "minDelay": 2, "maxDelay": 6, "eventModel": "bernoulli", "pDelay": 0.05, '
                    '"durationModel": "uniform", "gaussMeanRatio": 0.5, "gaussStdRatio": 0.2}')
        self.fleet.start("sim", [f"{BIN}/ctsfleet-sim", "--robots", "8", "--config", CONFIG,
                                 "--domain", str(self.fleet.domain), "--step", STEP, "--turn", STEP,
                                 "--actions", "rotate", "--delay-config", delays, "--log-dir", agents_dir])
        code = self.fleet.wait_exit("sim", 240)
        text = read(self.fleet.log("sim"))
        self.assertEqual(code, 0, text[-3000:])
        self.assertRegex(text, r"plan epoch 1: 8 robots, \d+ task visits, flowtime \d+, makespan \d+ with turns")
        self.assertIn("mission completed: tasks 16/16", text)
        self.assert_safe()
        logs = [read(os.path.join(agents_dir, name)) for name in sorted(os.listdir(agents_dir)) if name.endswith(".log")]
        self.assertEqual(len(logs), 8)
        for log in logs:
            self.assertNotIn("turned first", log)
            self.assertNotIn("rejected command", log)
        self.assertTrue(any("this move delayed" in log for log in logs), "no robot was delayed")

    def test_robot_restarted_facing_another_way_in_a_fleet_that_turns(self):
        """Plans with turns, robots that take time to turn: robot3's process is killed mid-mission and
        started again where it stands, facing north (carried and put down turned; no log tells which
        way it faced before, so north may now and then be that way: the exact heading rule is unit
        tested, FleetCoordinator.ARobotRestartedFacingAnotherWayIsReplannedFromItsNewHeading). It
        rejoins, is replanned from the heading it reports, no move it is sent finds it facing the
        wrong way, the mission completes, and nobody collides."""
        self.fleet.monitor()
        for index, cell in enumerate(role_starts()):
            self.fleet.agent(f"robot{index}", cell, extra=["--turn", STEP])
        self.fleet.coordinator(extra=["--actions", "rotate"])
        log = self.fleet.log("coordinator")
        wait_for(lambda: "plan epoch 1" in read(log), 120, "the first plan")
        wait_for(lambda: any(int(done) >= 2 for done in re.findall(r"tasks (\d+)/16", read(log))), 120,
                 "the mission under way (two tasks done)")
        cell = self.fleet.kill_robot("robot3")
        self.fleet.agent("robot3", cell, extra=["--turn", STEP, "--heading", "N"])
        wait_for(lambda: "replanning: robot robot3 joined" in read(log), 60, "the restarted robot back in")
        code = self.fleet.wait_exit("coordinator", 240)
        text = read(log)
        self.assertEqual(code, 0, text[-3000:])  # robot3 did its role's remaining tasks
        self.assertRegex(text[text.index("replanning: robot robot3 joined"):], r"plan epoch \d+: .* with turns")
        self.assert_safe()
        restarted = read(self.fleet.log("robot3"))  # the new process's log only
        self.assertNotIn("turned first", restarted)
        self.assertNotIn("rejected command", restarted)

    def test_ctrl_c_stops_the_whole_fleet(self):
        launcher = self.fleet.start("sim", [f"{BIN}/ctsfleet-sim", "--robots", "8", "--config", CONFIG,
                                            "--domain", str(self.fleet.domain), "--step", STEP,
                                            "--log-dir", os.path.join(self.fleet.dir, "agents")])
        wait_for(lambda: "plan epoch 1" in read(self.fleet.log("sim")), 120, "the first plan")
        launcher.send_signal(signal.SIGINT)
        self.assertEqual(self.fleet.wait_exit("sim", 60), 130)
        left = subprocess.run(["pgrep", "-f", f"--domain {self.fleet.domain}( |$)"], capture_output=True, text=True)
        self.assertEqual(left.stdout.strip(), "", "processes left behind")

    def test_cross_vendor_cyclone_coordinator_fastdds_agents(self):
        self.run_mission("cyclone", "fastdds")
        # Stopped by hand, each agent says goodbye; its log then holds no middleware warning
        # about the fleet working as meant (robots' channels in their own partitions) or about
        # a call the middleware does not implement.
        for index in range(len(role_starts())):
            self.fleet.processes[f"robot{index}"].send_signal(signal.SIGINT)
        for index in range(len(role_starts())):
            robot = f"robot{index}"
            self.assertEqual(self.fleet.wait_exit(robot, 60), 0)
            text = read(self.fleet.log(robot))
            self.assertIn("goodbye", text)
            for noise in ("INCOMPATIBLE QOS", "not implemented"):
                self.assertNotIn(noise, text, robot)

    def test_cross_vendor_fastdds_coordinator_cyclone_agents(self):
        self.run_mission("fastdds", "cyclone")

    def kill_role3_robot_mid_run(self, extra_robot=False, config=CONFIG):
        """Kills (SIGKILL) the robot that plays role 3 once two tasks are done; returns its id."""
        self.fleet.monitor()
        self.fleet.agents()
        if extra_robot:
            self.fleet.agent("robot8", (1, 1))
        self.fleet.coordinator(config=config)
        wait_for(lambda: "plan epoch 1" in read(self.fleet.log("coordinator")), 120, "the first plan")
        wait_for(lambda: any(int(done) >= 2 for done in re.findall(r"tasks (\d+)/16", read(self.fleet.log("coordinator")))),
                 120, "the mission under way (two tasks done)")
        victim = re.search(r"robot (robot\d+) takes role 3", read(self.fleet.log("coordinator"))).group(1)
        self.fleet.processes[victim].send_signal(signal.SIGKILL)
        killed_at = time.time()
        wait_for(lambda: f"robot {victim} taken out" in read(self.fleet.log("coordinator")), 60, "the loss detected")
        line = next(l for l in read(self.fleet.log("coordinator")).splitlines() if f"robot {victim} taken out" in l)
        stamp = time.mktime(time.strptime(line[1:20], "%Y-%m-%d %H:%M:%S")) + int(line[21:24]) / 1000
        print(f"loss detected {stamp - killed_at:.2f} s after SIGKILL ({line.strip()})")
        self.assertIn("liveliness lost", line)
        # Lease 1 s: detection within two leases, plus slack for a loaded machine's scheduling.
        self.assertLess(stamp - killed_at, 2 * 1.0 + 1.0)
        return victim

    def coordinator_stamp(self, line):
        """Wall-clock time of a coordinator log line."""
        return time.mktime(time.strptime(line[1:20], "%Y-%m-%d %H:%M:%S")) + int(line[21:24]) / 1000

    def test_restarted_robot_with_the_same_id_rejoins(self):
        # robot3 has run long: its sequence numbers are far above a fresh process's.
        self.fleet.monitor()
        for index, cell in enumerate(role_starts()):
            self.fleet.agent(f"robot{index}", cell, extra=["--first-seq", "1000000000"] if index == 3 else [])
        self.fleet.coordinator()
        log = self.fleet.log("coordinator")
        wait_for(lambda: "plan epoch 1" in read(log), 120, "the first plan")
        wait_for(lambda: any(int(done) >= 2 for done in re.findall(r"tasks (\d+)/16", read(log))), 120,
                 "the mission under way (two tasks done)")
        cell = self.fleet.kill_robot("robot3")
        # The process restarts where the robot stands, with the same id and a new incarnation.
        restarted_at = time.time()
        self.fleet.agent("robot3", cell)
        wait_for(lambda: "replanning: robot robot3 joined" in read(log), 30, "the restarted robot back in")
        text = read(log)
        after = text[text.index("replanning: robot robot3 joined"):]
        wait_for(lambda: re.search(r"plan epoch \d+", read(log)[read(log).index("replanning: robot robot3 joined"):]),
                 30, "a plan with the restarted robot")
        after = read(log)[read(log).index("replanning: robot robot3 joined"):]
        plan_line = next(l for l in after.splitlines() if "plan epoch" in l)
        print(f"restarted robot back in a sent plan {self.coordinator_stamp(plan_line) - restarted_at:.2f} s after "
              f"its process started")
        code = self.fleet.wait_exit("coordinator", 240)
        text = read(log)
        self.assertEqual(code, 0, text[-3000:])  # robot3 did its role's remaining tasks
        self.assertNotIn("duplicate robot id", text)
        self.assert_safe()

    def test_duplicate_id_is_refused_and_reported(self):
        self.fleet.monitor()
        self.fleet.agents()
        # The duplicate's cell stays walled: should it block some work, the mission ends 5 s after.
        self.fleet.coordinator(config=self.fleet.config_with(replacement_timeout_s=5))
        log = self.fleet.log("coordinator")
        wait_for(lambda: "plan epoch 1" in read(log), 120, "the first plan")
        # A second process claims robot6's id from a cell of its own.
        self.fleet.start("duplicate", [f"{BIN}/ctsfleet-agent", "--id", "robot6", "--start", "1,1", "--domain",
                                       str(self.fleet.domain), "--step", STEP, "--dds-config-dir", DDS_DIR])
        wait_for(lambda: "duplicate robot id robot6" in read(log), 30, "the coordinator refusing the duplicate")
        code = self.fleet.wait_exit("coordinator", 240)
        text = read(log)
        self.assertIn(code, (0, 3), text[-3000:])
        self.assertNotIn("robot robot6 taken out", text)  # the robot it drives stays in
        self.fleet.processes["duplicate"].send_signal(signal.SIGTERM)
        monitor_code, monitor_text = self.fleet.monitor_verdict()
        self.assertIn("overlaps 0", monitor_text, monitor_text)
        self.assertIn("duplicate ids 1", monitor_text, monitor_text)
        self.assertEqual(monitor_code, 1, monitor_text)  # a duplicate id is an alarm
        # The second process was told, stood still, and was never commanded.
        duplicate = read(self.fleet.log("duplicate"))
        self.assertIn("refused by coordinator", duplicate, duplicate[-3000:])
        cells = [int(n) for n in re.findall(r"duplicate robot6: process [0-9a-f]+ on (\d+) cells", monitor_text)]
        self.assertEqual(len(cells), 2, monitor_text)
        self.assertEqual(min(cells), 1, monitor_text)  # the refused process never moved
        self.assertGreater(max(cells), 1, monitor_text)  # the driven one did its work

    def test_impostor_started_first_one_body_moves_and_nobody_collides(self):
        # The attack as reported: a process claiming robot6 starts 3 s before the real robot6 (each
        # on a free cell of its own), then the coordinator. Which process drives the id is the one
        # heard first (without DDS Security nothing tells an impostor from the robot; with it, an
        # impostor has no certificate for the id); the other is refused, told so, and never
        # moves; no two bodies ever share a cell.
        self.fleet.monitor()
        starts = role_starts()
        for index, cell in enumerate(starts):
            if index != 6:
                self.fleet.agent(f"robot{index}", cell)
        self.fleet.start("impostor", [f"{BIN}/ctsfleet-agent", "--id", "robot6", "--start", "1,1", "--domain",
                                      str(self.fleet.domain), "--step", STEP, "--dds-config-dir", DDS_DIR])
        time.sleep(3)  # the attack's head start (part of the scenario, not a wait for anything)
        self.fleet.agent("robot6", starts[6])
        self.fleet.coordinator(config=self.fleet.config_with(quorum=8, replacement_timeout_s=5))
        log = self.fleet.log("coordinator")
        wait_for(lambda: "duplicate robot id robot6" in read(log), 60, "the coordinator refusing one robot6")
        code = self.fleet.wait_exit("coordinator", 240)
        text = read(log)
        self.assertIn(code, (0, 3), text[-3000:])
        self.assertNotIn("restarted: incarnation", text)  # the driven process kept the id while heard
        refused = [name for name in ("impostor", "robot6") if "refused by coordinator" in read(self.fleet.log(name))]
        self.assertEqual(len(refused), 1, text[-3000:])
        for name in ("impostor", "robot6"):
            self.fleet.processes[name].send_signal(signal.SIGTERM)
        monitor_code, monitor_text = self.fleet.monitor_verdict()
        self.assertIn("overlaps 0", monitor_text, monitor_text)
        self.assertIn("duplicate ids 1", monitor_text, monitor_text)
        cells = [int(n) for n in re.findall(r"duplicate robot6: process [0-9a-f]+ on (\d+) cells", monitor_text)]
        self.assertEqual(sorted(cells)[0], 1, monitor_text)  # the refused process never moved

    def test_robot_moved_by_hand_is_taken_out_and_planned_around(self):
        # robot5 is carried to (1,1) after its 10th move, off its plan.
        self.fleet.monitor()
        for index, cell in enumerate(role_starts()):
            self.fleet.agent(f"robot{index}", cell, extra=["--teleport-after", "10", "--to", "1,1"] if index == 5 else [])
        self.fleet.coordinator(config=self.fleet.config_with(replacement_timeout_s=5), extra=["--json"])
        log = self.fleet.log("coordinator")
        wait_for(lambda: "robot robot5 taken out: off its plan: reports (1,1)" in read(log), 120,
                 "the coordinator seeing robot5 off its plan")
        code = self.fleet.wait_exit("coordinator", 240)
        text = read(log)
        self.assertIn(code, (0, 3), text[-3000:])
        self.assertIn("replanning: robot robot5 joined", text)  # back in, from where it was put down
        summary = json.loads(next(l for l in reversed(text.splitlines()) if l.startswith("{")))
        self.assertEqual(summary["off_plan"], 1, summary)
        if code == 3:
            self.assert_pending_explained(text)
        self.assert_safe()

    def test_robot_deaf_to_commands_is_taken_out_and_rejoins(self):
        self.deaf_robot_is_taken_out_and_rejoins("cyclone")

    def test_fastdds_robot_deaf_to_commands_is_taken_out_and_rejoins(self):
        self.deaf_robot_is_taken_out_and_rejoins("fastdds")

    def deaf_robot_is_taken_out_and_rejoins(self, dds):
        # robot2 loses every command after its 3rd for 6 s while its states still go out (a broken
        # command channel). The coordinator must not wait on it for ever: it is taken out after
        # timing.command_timeout_s, the others are planned around it, and once it hears commands
        # again it rejoins.
        self.fleet.monitor(dds)
        for index, cell in enumerate(role_starts()):
            extra = ["--test-deaf-after", "3", "--test-deaf-s", "6"] if index == 2 else []
            self.fleet.agent(f"robot{index}", cell, dds, extra=extra)
        self.fleet.coordinator(dds, config=self.fleet.config_with(command_timeout_s=3), extra=["--json"])
        log = self.fleet.log("coordinator")
        wait_for(lambda: "robot robot2 taken out: move" in read(log), 120, "robot2 taken out as deaf")
        self.assertIn("deaf to commands for 6", read(self.fleet.log("robot2")))
        code = self.fleet.wait_exit("coordinator", 240)
        text = read(log)
        self.assertEqual(code, 0, text[-3000:])
        self.assertIn("not acknowledged in", text)
        self.assertIn("replanning: robot robot2 joined", text)
        summary = json.loads(next(l for l in reversed(text.splitlines()) if l.startswith("{")))
        self.assertTrue(summary["completed"], summary)
        self.assertEqual(summary["tasks_done"], 16, summary)
        self.assertGreaterEqual(summary["robots_lost"], 1, summary)
        self.assert_safe()

    def test_killed_agent_is_detected_and_the_others_finish(self):
        # With a replacement timeout set, the mission ends that long after only role 3's work is left.
        victim = self.kill_role3_robot_mid_run(config=self.fleet.config_with(replacement_timeout_s=5))
        code = self.fleet.wait_exit("coordinator", 240)
        text = read(self.fleet.log("coordinator"))
        self.assertEqual(code, 3, text[-3000:])  # completed for the others, role 3's tasks pending
        pending = [l for l in text.splitlines() if l.startswith("pending:")]
        self.assertTrue(pending, text[-2000:])
        self.assert_pending_explained(text, role_without_robot=3)
        self.assertIn(f"replanning: robot {victim} lost", text)
        self.assert_safe()

    def test_new_agent_takes_over_the_dead_robots_role(self):
        # Without a replacement timeout (the shipped config) the robots hold for as long as it takes:
        # the new robot starts only once the coordinator has been waiting a while.
        self.kill_role3_robot_mid_run()
        wait_for(lambda: "waiting for a robot to join" in read(self.fleet.log("coordinator")), 120,
                 "the others done and the coordinator waiting for a robot")
        waiting = next(l for l in read(self.fleet.log("coordinator")).splitlines() if "waiting for a robot to join" in l)
        wait_for(lambda: time.time() > self.coordinator_stamp(waiting) + 3, 10, "3 s of waiting")
        self.assertIsNone(self.fleet.processes["coordinator"].poll(), "the mission ended while waiting for a robot")
        self.fleet.agent("robot9", (1, 1))
        code = self.fleet.wait_exit("coordinator", 240)
        text = read(self.fleet.log("coordinator"))
        self.assertIn("robot robot9 takes role 3", text)
        # Completed, unless the dead robot happens to stand where another robot must go.
        self.assertIn(code, (0, 3), text[-3000:])
        self.assert_pending_explained(text)
        self.assert_safe()

    def test_extra_robot_takes_over_a_lost_role(self):
        victim = self.kill_role3_robot_mid_run(extra_robot=True, config=self.fleet.config_with(replacement_timeout_s=5))
        code = self.fleet.wait_exit("coordinator", 240)
        text = read(self.fleet.log("coordinator"))
        # Completed, unless the dead robot happens to stand where another robot must go.
        self.assertIn(code, (0, 3), text[-3000:])
        self.assert_pending_explained(text)
        # Nine robots, eight roles: whichever robot was left without a role takes the lost robot's role.
        self.assertIn("stays as an extra robot", text)
        after_loss = text[text.index(f"robot {victim} taken out"):]
        self.assertRegex(after_loss, r"robot robot\d takes role 3")
        self.assert_safe()

    def test_jitter_up_to_three_times_the_step(self):
        self.fleet.monitor()
        jitter = ("--jitter", "2.0", "--delay-probability", "0.05", "--delay", "0.3")
        for index, cell in enumerate(role_starts()):
            stall = ("--stall-at", "4", "--stall-for", "3") if index == 2 else ()  # stuck 3 s mid-move
            self.fleet.agent(f"robot{index}", cell, extra=jitter + stall)
        self.fleet.coordinator()
        code = self.fleet.wait_exit("coordinator", 240)
        self.assertEqual(code, 0, read(self.fleet.log("coordinator"))[-3000:])
        self.assert_safe()

    def test_hostile_messages_change_nothing(self):
        self.fleet.monitor()
        self.fleet.agents()
        self.fleet.coordinator()
        wait_for(lambda: "plan epoch 1" in read(self.fleet.log("coordinator")), 120, "the first plan")
        inject = subprocess.run([f"{BIN}/ctsfleet-test-inject", "--domain", str(self.fleet.domain),
                                 "--dds-config-dir", DDS_DIR, "--victim", "robot0"],
                                capture_output=True, text=True, timeout=60)
        self.assertEqual(inject.returncode, 0, inject.stderr)
        code = self.fleet.wait_exit("coordinator", 240)
        coordinator = read(self.fleet.log("coordinator"))
        self.assertEqual(code, 0, coordinator[-3000:])
        self.assertIn("unknown robot intruder", coordinator)
        self.assertIn("duplicate id", coordinator)
        victim = read(self.fleet.log("robot0"))
        self.assertIn("not a move to a neighbouring cell", victim)
        self.assertIn("stale plan epoch", victim)
        self.assertIn("this robot follows", victim)
        for name, process in self.fleet.processes.items():
            if name.startswith("robot"):
                self.assertIsNone(process.poll(), f"{name} died:\n" + read(self.fleet.log(name))[-2000:])
        self.assert_safe()

    def test_silent_robot_is_taken_out(self):
        self.fleet.monitor()
        for index, cell in enumerate(role_starts()):
            extra = ("--silent-at", "6") if index == 5 else ()
            self.fleet.agent(f"robot{index}", cell, extra=extra)
        # Role 5 is left without a robot: the mission ends 5 s after only its work is left.
        self.fleet.coordinator(config=self.fleet.config_with(replacement_timeout_s=5))
        code = self.fleet.wait_exit("coordinator", 240)
        text = read(self.fleet.log("coordinator"))
        self.assertIn("robot robot5 taken out: no state for", text)
        self.assertIn("replanning: robot robot5 lost", text)
        # Completed for the others; what is pending is robot5's role, or tasks its cell now blocks.
        self.assertIn(code, (0, 3), text[-3000:])
        self.assert_pending_explained(text, role_without_robot=5)
        self.assert_safe()

    def test_bad_configuration_and_arguments(self):
        def coordinator_with(text, name):
            path = os.path.join(self.fleet.dir, name)
            with open(path, "w") as f:
                f.write(text)
            return subprocess.run([f"{BIN}/ctsfleet-coordinator", "--config", path, "--domain",
                                   str(self.fleet.domain)], capture_output=True, text=True, timeout=60)

        mission = os.path.abspath(MISSION)
        cases = [
            ("mission: [unclosed\n", "malformed.yaml", "malformed YAML"),
            (f"mission: {mission}\nspeed: 3\n", "unknown-key.yaml", "unknown key 'speed'"),
            (f"mission: {mission}\ndds:\n  vendor: opensplice\n", "vendor.yaml", "dds.vendor"),
            (f"mission: {mission}\nrobots:\n  quorum: many\n", "quorum.yaml", "robots.quorum"),
            (f"mission: {mission}\nplanner:\n  solver: magic\n", "solver.yaml", "unknown solver 'magic'"),
            (f"mission: {mission}\nplanner:\n  pibt_swap: maybe\n", "swap.yaml", "planner.pibt_swap"),
            ("mission: nowhere.yaml\n", "missing-mission.yaml", "nowhere.yaml"),
            (f"mission: {mission}\nplanner:\n  actions: fly\n", "actions.yaml", "planner.actions"),
            (f"mission: {mission}\nplanner:\n  lns_stall_iterations: -1\n", "stall.yaml",
             "planner.lns_stall_iterations"),
        ]
        for text, name, expected in cases:
            result = coordinator_with(text, name)
            self.assertEqual(result.returncode, 2, f"{name}: {result.stdout}{result.stderr}")
            output = result.stdout + result.stderr
            self.assertIn(name if expected != "nowhere.yaml" else expected, output)
            self.assertIn(expected, output)
        # The lifelong planner's settings file the fleet config names: its own faults by its own name.
        with open(os.path.join(self.fleet.dir, "bad-lifelong.yaml"), "w") as f:
            f.write("guidance: auto\nrollouts: 0\n")
        for text, name, expected in [
                (f"mission: {mission}\nlifelong: true\nlifelong_planner: bad-lifelong.yaml\n", "uses-bad.yaml",
                 "bad-lifelong.yaml:2"),
                (f"mission: {mission}\nlifelong_planner: nowhere-lifelong.yaml\n", "uses-missing.yaml",
                 "nowhere-lifelong.yaml"),
                (f"mission: {mission}\nlifelong_planner: [a, b]\n", "uses-list.yaml", "lifelong_planner")]:
            result = coordinator_with(text, name)
            self.assertEqual(result.returncode, 2, f"{name}: {result.stdout}{result.stderr}")
            self.assertIn(expected, result.stdout + result.stderr)
        agent = subprocess.run([f"{BIN}/ctsfleet-agent", "--id", "x", "--start", "nonsense"],
                               capture_output=True, text=True, timeout=60)
        self.assertEqual(agent.returncode, 2)
        self.assertIn("--start: must be x,y", agent.stdout + agent.stderr)
        heading = subprocess.run([f"{BIN}/ctsfleet-agent", "--id", "x", "--start", "1,1", "--heading", "up"],
                                 capture_output=True, text=True, timeout=60)
        self.assertEqual(heading.returncode, 2)
        self.assertIn("--heading", heading.stdout + heading.stderr)
        too_long = subprocess.run([f"{BIN}/ctsfleet-agent", "--id", "r" * 40], capture_output=True, text=True,
                                  timeout=60)
        self.assertEqual(too_long.returncode, 2)

    def test_fastdds_hears_more_than_ten_robots(self):
        # Fast DDS readers keep 10 instances by default and every robot is one: without room for
        # the fleet, an eleventh robot would never be heard.
        self.fleet.monitor("fastdds")
        robots = [f"robot{i}" for i in range(14)]
        for i, robot in enumerate(robots):
            self.fleet.agent(robot, (i, 0), dds="fastdds")
        for robot in robots:
            seen = subprocess.run([f"{BIN}/ctsfleet-test-drive", "--dds", "fastdds", "--domain", str(self.fleet.domain),
                                   "--dds-config-dir", DDS_DIR, "--robot", robot, "--wait-status", "ready",
                                   "--timeout", "60"], capture_output=True, text=True, timeout=120)
            self.assertEqual(seen.returncode, 0, f"{robot} never heard: {seen.stdout}")
        code, text = self.fleet.monitor_verdict()
        self.assertIn("robots 14", text)


if __name__ == "__main__":
    unittest.main(argv=[sys.argv[0], *sys.argv[1:]], verbosity=2)
