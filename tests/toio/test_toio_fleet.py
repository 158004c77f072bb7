#!/usr/bin/env python3
"""The toio path end to end: ctsfleet-agent --backend toio against the cube emulator, which serves
a fake BlueZ on a private dbus-daemon, with the coordinator and the safety monitor over DDS on
loopback. Every wait is on a condition with a generous deadline."""
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "../fleet"))
from test_fleet import BIN, DDS_DIR, ROOT, Fleet, failed, read, wait_for  # noqa: E402

import yaml  # noqa: E402

TOIO_CONFIG = os.path.join(ROOT, "config/toio/fleet.yaml")
TOIO_MISSION = os.path.join(ROOT, "config/toio/mission-4.yaml")
MAT = os.path.join(ROOT, "config/mats/toio-collection-ring.yaml")
ORIGIN, PITCH = 75, 50  # of the ring mat file above
TESTS = [
    "test_agent_drives_a_cube_three_cells",
    "test_lifted_cube_is_a_fault_until_put_back",
    "test_mission_with_four_cubes_completes_safely",
    "test_cube_that_loses_its_link_rejoins_and_the_mission_completes",
    "test_cube_lifted_mid_mission_rejoins_and_the_mission_completes",
    "test_sim_launcher_runs_the_toio_demo",
    "test_calibration_fits_a_rotated_grid_then_drives_the_corners",
]


def centre(cell):
    return ORIGIN + PITCH * cell[0], ORIGIN + PITCH * cell[1]


class ToioFleet(Fleet):
    """A Fleet plus a private bus with the cube emulator on it."""

    def __init__(self, test_name):
        super().__init__("test_mission_completes_safely")
        self.domain = 70 + 2 * TESTS.index(test_name)
        self.bus = None
        # Real robots run with DDS Security (config/toio/fleet.yaml requires it): so do these.
        self.secure([f"robot{i}" for i in range(6)], coordinators=("coordinator", "test-driver"))

    def emulator(self, cubes):
        socket = os.path.join(self.dir, "bus")
        self.bus = "unix:path=" + socket
        self.start("dbus", ["dbus-daemon", "--session", "--nofork", "--nopidfile", "--address=" + self.bus])
        wait_for(lambda: os.path.exists(socket), 60, "the private dbus-daemon")
        args = [f"{BIN}/ctsfleet-toio-emulator", "--bus", self.bus, "--mat", MAT]
        for name, cell in cubes:
            args += ["--cube", f"{name}@cell:{cell[0]},{cell[1]}"]
        self.start("emulator", args)
        wait_for(lambda: "toio-emulator ready" in read(self.log("emulator")), 60, "the emulator")

    def control(self, method, *args):
        """Calls the emulator's control interface (lift, place, drop a connection, pose)."""
        result = subprocess.run(["dbus-send", f"--bus={self.bus}", "--print-reply", "--dest=org.bluez",
                                 "/io/ctsfleet/emulator", f"io.ctsfleet.ToioEmulator1.{method}", *args],
                                capture_output=True, text=True, timeout=30)
        if result.returncode != 0:
            raise AssertionError(f"{method} failed: {result.stderr}")
        return result.stdout

    def pose(self, cube):
        values = re.findall(r"(?:boolean|double|int32) (\S+)", self.control("Pose", f"string:{cube}"))
        return {"on_mat": values[0] == "true", "x": float(values[1]), "y": float(values[2]),
                "connected": values[4] == "true"}

    def toio_agent(self, robot_id, cube):
        env = dict(os.environ, DBUS_SYSTEM_BUS_ADDRESS=self.bus)
        out = open(self.log(robot_id), "w")
        self.files.append(out)
        self.processes[robot_id] = subprocess.Popen(
            [f"{BIN}/ctsfleet-agent", "--id", robot_id, "--backend", "toio", "--cube", cube, "--mat", MAT,
             "--domain", str(self.domain), "--dds-config-dir", DDS_DIR, *self.security()],
            stdout=out, stderr=subprocess.STDOUT, env=env)

    def wait_agent_up(self, robot_id):
        """Waits (generously: a loaded 2-core machine) for the agent's first line, which it logs
        once its DDS participant is up; an agent that exits first fails with its exit status."""
        process = self.processes[robot_id]

        def up():
            if process.poll() is not None:
                raise AssertionError(f"{robot_id} exited with {process.returncode}:\n{read(self.log(robot_id))[-3000:]}")
            return " robot on " in read(self.log(robot_id))
        try:
            wait_for(up, 180, f"{robot_id} to start (its log: {self.log(robot_id)})")
        except AssertionError as e:
            raise AssertionError(f"{e}\n{backtraces(process.pid)}") from None

    def drive(self, robot_id, *args, timeout=60):
        return subprocess.run([f"{BIN}/ctsfleet-test-drive", "--robot", robot_id, "--domain", str(self.domain),
                               "--dds-config-dir", DDS_DIR, "--timeout", str(timeout),
                               *self.security("test-driver"), *args],
                              capture_output=True, text=True, timeout=300)


def backtraces(pid):
    """Where a process that hangs stands (every thread), when gdb is at hand."""
    if shutil.which("gdb") is None:
        return "(no gdb: no backtraces)"
    try:
        result = subprocess.run(["gdb", "-p", str(pid), "-batch", "-ex", "thread apply all bt"],
                                capture_output=True, text=True, timeout=120)
        return result.stdout[-6000:]
    except subprocess.TimeoutExpired:
        return "(gdb timed out)"


def role_starts():
    with open(TOIO_MISSION) as f:
        return [tuple(a["start"]) for a in yaml.safe_load(f)["agents"]]


class ToioFleetTest(unittest.TestCase):
    def setUp(self):
        self.fleet = ToioFleet(self._testMethodName)

    def tearDown(self):
        self.fleet.close(keep_logs=failed(self))

    def assert_safe(self):
        code, text = self.fleet.monitor_verdict()
        self.assertIn("overlaps 0", text, text)
        self.assertEqual(code, 0, text)

    def start_mission(self, coordinator_extra=()):
        self.fleet.emulator([(f"toio-{i}", cell) for i, cell in enumerate(role_starts())])
        self.fleet.monitor()
        for i in range(len(role_starts())):
            self.fleet.toio_agent(f"robot{i}", f"toio-{i}")
        self.fleet.coordinator(config=TOIO_CONFIG, extra=coordinator_extra)
        wait_for(lambda: "plan epoch 1" in read(self.fleet.log("coordinator")), 120, "the first plan")

    def finish_mission(self):
        code = self.fleet.wait_exit("coordinator", 240)
        text = read(self.fleet.log("coordinator"))
        self.assertEqual(code, 0, text[-4000:])
        self.assertIn("mission completed: tasks 6/6", text)
        self.assert_safe()
        return text

    def wait_tasks_done(self, count):
        wait_for(lambda: any(int(done) >= count for done in
                             re.findall(r"tasks (\d+)/6", read(self.fleet.log("coordinator")))),
                 120, f"{count} tasks done")

    def test_agent_drives_a_cube_three_cells(self):
        self.fleet.emulator([("toio-a", (1, 1)), ("toio-b", (5, 5))])
        self.fleet.toio_agent("robot0", "toio-a")
        self.fleet.wait_agent_up("robot0")
        result = self.fleet.drive("robot0", "--path", "2,1 2,2 1,2", timeout=120)
        self.assertEqual(result.returncode, 0, result.stdout + read(self.fleet.log("robot0"))[-3000:])
        self.assertIn("arrived 2 at 1,2", result.stdout)
        x, y = centre((1, 2))
        wait_for(lambda: abs(self.fleet.pose("toio-a")["x"] - x) < 2 and abs(self.fleet.pose("toio-a")["y"] - y) < 2,
                 60, "the cube on the centre of cell (1,2)")
        self.assertFalse(self.fleet.pose("toio-b")["connected"])

    def test_lifted_cube_is_a_fault_until_put_back(self):
        self.fleet.emulator([("toio-a", (3, 3))])
        self.fleet.toio_agent("robot0", "toio-a")
        self.fleet.wait_agent_up("robot0")
        self.assertEqual(self.fleet.drive("robot0", "--wait-status", "ready", timeout=120).returncode, 0)
        self.fleet.control("Lift", "string:toio-a")
        fault = self.fleet.drive("robot0", "--wait-status", "fault")
        self.assertEqual(fault.returncode, 0, fault.stdout + read(self.fleet.log("robot0"))[-2000:])
        self.assertIn("ID missed", read(self.fleet.log("robot0")))
        # A command while lifted is refused, not kept for later.
        refused = self.fleet.drive("robot0", "--even-in-fault", "--path", "3,4", timeout=5)
        self.assertEqual(refused.returncode, 3, refused.stdout)
        wait_for(lambda: "rejected command epoch 1 action 0 to (3,4): the robot is in fault" in
                 read(self.fleet.log("robot0")), 60, "the agent refusing the command")
        x, y = centre((4, 3))
        self.fleet.control("Place", "string:toio-a", f"double:{x}", "double:{}".format(y), "double:0")
        back = self.fleet.drive("robot0", "--wait-status", "ready")
        self.assertEqual(back.returncode, 0, back.stdout)
        self.assertIn("at 4,3", back.stdout)
        # And it drives again after the fault, with a new plan epoch.
        moved = self.fleet.drive("robot0", "--epoch", "2", "--path", "4,4")
        self.assertEqual(moved.returncode, 0, moved.stdout + read(self.fleet.log("robot0"))[-2000:])

    def test_mission_with_four_cubes_completes_safely(self):
        self.start_mission()
        text = self.finish_mission()
        self.assertIn("robots lost 0", text)

    def test_cube_that_loses_its_link_rejoins_and_the_mission_completes(self):
        self.start_mission()
        # The link drops as soon as the robots set off: dropped once a task was reported done (the
        # report comes every 2 s), it once fell when 4 of 6 were, and the other three robots
        # finished the mission before the cube was back to rejoin it.
        self.fleet.control("DropConnection", "string:toio-1", "double:3")
        wait_for(lambda: "robot robot1 taken out: reports a fault" in read(self.fleet.log("coordinator")), 60,
                 "the coordinator taking the disconnected robot out")
        wait_for(lambda: "robot robot1 joined" in read(self.fleet.log("coordinator")), 120,
                 "the robot rejoining after reconnecting")
        self.assertIn("BLE link to the cube lost", read(self.fleet.log("robot1")))
        self.finish_mission()

    def test_cube_lifted_mid_mission_rejoins_and_the_mission_completes(self):
        self.start_mission()
        self.wait_tasks_done(1)
        pose = self.fleet.pose("toio-2")
        self.fleet.control("Lift", "string:toio-2")
        wait_for(lambda: "robot robot2 taken out: reports a fault" in read(self.fleet.log("coordinator")), 60,
                 "the coordinator taking the lifted robot out")
        # Put it back on the cell it was nearest to: its last cell or the one it was entering, both
        # of which the coordinator keeps clear of other robots meanwhile.
        cell = (round((pose["x"] - ORIGIN) / PITCH), round((pose["y"] - ORIGIN) / PITCH))
        x, y = centre(cell)
        time.sleep(0.5)  # a person takes a moment to put a cube back (not a synchronisation)
        self.fleet.control("Place", "string:toio-2", f"double:{x}", f"double:{y}", "double:0")
        wait_for(lambda: "robot robot2 joined" in read(self.fleet.log("coordinator")), 120, "the robot rejoining")
        self.finish_mission()

    def test_sim_launcher_runs_the_toio_demo(self):
        """The demo with cubes delayed as the league's 2026 rules delay robots (short delays: each
        stays well under the agent's move time-out)."""
        self.fleet.monitor()
        delays = os.path.join(self.fleet.dir, "delays.json")
        with open(delays, "w") as f:
            f.write('{"seed": 0, "minDelay": 2, "maxDelay": 4, "eventModel": "bernoulli", "pDelay": 0.03, '
                    '"durationModel": "uniform", "gaussMeanRatio": 0.5, "gaussStdRatio": 0.2}')
        sim_dir = os.path.join(self.fleet.dir, "sim")
        self.fleet.start("sim", [f"{BIN}/ctsfleet-sim", "--backend", "toio-emulated", "--robots", "4",
                                 "--domain", str(self.fleet.domain), "--log-dir", sim_dir,
                                 "--delay-config", delays, *self.fleet.security()])
        code = self.fleet.wait_exit("sim", 240)
        text = read(self.fleet.log("sim"))
        self.assertEqual(code, 0, text[-3000:])
        self.assertIn("mission completed: tasks 6/6", text)
        self.assertIn("emulated BlueZ with 4 toio cubes", text)
        self.assertRegex(read(os.path.join(sim_dir, "toio-emulator.log")), r"cube toio-\d delayed for [2-4] ticks")
        self.assert_safe()

    def test_calibration_fits_a_rotated_grid_then_drives_the_corners(self):
        # The grid truly lies rotated 90 degrees on the mat: cell (x, y) is centred at
        # (425 - 50 y, 75 + 50 x). A person places the cube on three cells, pressing Enter each time.
        def truth(cell):
            return 425 - 50 * cell[1], 75 + 50 * cell[0]
        self.fleet.emulator([("toio-a", (0, 0))])
        fitted = os.path.join(self.fleet.dir, "fitted.yaml")
        env = dict(os.environ, DBUS_SYSTEM_BUS_ADDRESS=self.fleet.bus)
        # First, find the cube: it is only known to BlueZ after discovery.
        scan = subprocess.run([f"{BIN}/ctsfleet-toio-calibrate", "scan", "--seconds", "1"], capture_output=True,
                              text=True, env=env, timeout=60)
        self.assertEqual(scan.returncode, 0, scan.stdout + scan.stderr)
        self.assertRegex(scan.stdout, r"toio-a\s+E0:7C:00:00:00:00\s+-55 dBm")
        calibrate = subprocess.Popen([f"{BIN}/ctsfleet-toio-calibrate", "fit", "--mat", MAT, "--out", fitted,
                                      "--cube", "toio-a", "--cells", "0,0 4,0 0,4 4,4"],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                     text=True, env=env)
        transcript = []
        for cell in [(0, 0), (4, 0), (0, 4), (4, 4)]:
            while True:  # the prompt for this cell
                line = calibrate.stdout.readline()
                transcript.append(line)
                self.assertTrue(line, "".join(transcript))
                if line.startswith("place toio-a on cell"):
                    break
            x, y = truth(cell)
            self.fleet.control("Place", "string:toio-a", f"double:{x}", f"double:{y}", "double:90")
            calibrate.stdin.write("\n")
            calibrate.stdin.flush()
        rest, _ = calibrate.communicate(timeout=120)
        output = "".join(transcript) + rest
        self.assertEqual(calibrate.returncode, 0, output)
        self.assertIn("grid x axis at 90.0 degrees", output)
        self.assertRegex(output, r"residual rms 0\.\d+")
        with open(fitted) as f:
            transform = yaml.safe_load(f)["transform"]
        self.assertAlmostEqual(transform["offset"][0], 425, delta=1)
        self.assertAlmostEqual(transform["offset"][1], 75, delta=1)
        # The corner check drives the cube around the fitted grid.
        corners = subprocess.run([f"{BIN}/ctsfleet-toio-calibrate", "corners", "--mat", fitted, "--cube", "toio-a"],
                                 capture_output=True, text=True, env=env, timeout=240)
        self.assertEqual(corners.returncode, 0, corners.stdout + corners.stderr)
        self.assertEqual(corners.stdout.count(": ok"), 4, corners.stdout)
        self.assertIn("corner (7,7): stopped at mat (75, 425)", corners.stdout)
        # A mat file the grid does not fit on is refused, naming the file.
        bad = os.path.join(self.fleet.dir, "bad.yaml")
        with open(bad, "w") as f:
            f.write("mat: {name: m, x_range: [45, 455], y_range: [45, 455]}\n"
                    "grid: {width: 12, height: 8, origin: [75, 75], pitch: 50}\n")
        refused = subprocess.run([f"{BIN}/ctsfleet-toio-calibrate", "corners", "--mat", bad, "--cube", "toio-a"],
                                 capture_output=True, text=True, env=env, timeout=60)
        self.assertEqual(refused.returncode, 2)
        self.assertIn("bad.yaml", refused.stdout + refused.stderr)
        self.assertIn("does not fit on the mat", refused.stdout + refused.stderr)


if __name__ == "__main__":
    unittest.main(argv=[sys.argv[0], *sys.argv[1:]], verbosity=2)
