#!/usr/bin/env python3
"""Fast DDS fleets that discover through a discovery server (ctsfleet-discovery): a mission, the
server killed and restarted mid-mission while a robot restarts, and every way of giving the
options wrong. Real processes on loopback, each test on its own domain (160-169)."""
import json
import os
import re
import signal
import subprocess
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(__file__))
from test_fleet import BIN, CONFIG, DDS_DIR, Fleet, failed, read, role_starts, wait_for  # noqa: E402

TESTS = [
    "test_mission_through_a_discovery_server",
    "test_server_killed_and_restarted_while_a_robot_restarts",
    "test_bad_discovery_options_are_refused_clearly",
    "test_bad_network_options_are_refused_clearly",
    "test_a_server_that_crashes_starts_again_and_robots_find_it",
]


class DiscoveryFleet(Fleet):
    """A Fleet whose every process is a Fast DDS client of this test's discovery server."""

    def __init__(self, test_name):
        super().__init__(test_name, domain=160 + 2 * TESTS.index(test_name))
        self.server = f"127.0.0.1:{65000 + self.domain}"

    def discovery_server(self):
        log = self.log("discovery")
        process = self.start("discovery", [f"{BIN}/ctsfleet-discovery", "--domain", str(self.domain),
                                           "--listen", self.server, "--dds-config-dir", DDS_DIR,
                                           "--state-dir", os.path.join(self.dir, "discovery-state")])
        wait_for(lambda: "listening on" in read(log) or process.poll() is not None, 30, "the discovery server")
        self.assertRunning(process, log)
        return process

    @staticmethod
    def assertRunning(process, log):
        if process.poll() is not None:
            raise AssertionError("the discovery server exited:\n" + read(log))

    def client(self):
        return ["--discovery-server", self.server]

    def agent(self, robot_id, cell, dds="fastdds", extra=()):
        return super().agent(robot_id, cell, dds, [*self.client(), *extra])

    def coordinator(self, dds="fastdds", config=CONFIG, extra=()):
        return super().coordinator(dds, config, [*self.client(), *extra])

    def monitor(self, dds="fastdds"):
        return self.start("monitor", [f"{BIN}/ctsfleet-monitor", "--dds", dds, "--domain", str(self.domain),
                                      "--dds-config-dir", DDS_DIR, *self.client()])


def children_of(pid):
    """The pids of the processes whose parent is `pid`."""
    children = []
    for entry in os.listdir("/proc"):
        try:
            with open(f"/proc/{entry}/stat") as f:
                fields = f.read().rsplit(")", 1)[1].split()
        except (OSError, IndexError):
            continue  # not a process, or one that just ended
        if entry.isdigit() and int(fields[1]) == pid:
            children.append(int(entry))
    return children


def participants_in(state_file):
    """How many participants a discovery server's state file holds (0 while it is not complete JSON)."""
    try:
        with open(state_file) as f:
            return len(json.load(f)["participants"])
    except (OSError, ValueError, KeyError):
        return 0


def run(args, timeout=60, cwd=None):
    return subprocess.run(args, capture_output=True, text=True, timeout=timeout, cwd=cwd)


class DiscoveryTest(unittest.TestCase):
    def setUp(self):
        self.fleet = DiscoveryFleet(self._testMethodName)

    def tearDown(self):
        self.fleet.close(keep_logs=failed(self))

    def assert_completed_safely(self):
        code = self.fleet.wait_exit("coordinator", 240)
        text = read(self.fleet.log("coordinator"))
        self.assertEqual(code, 0, text[-3000:])
        self.assertIn("mission completed: tasks 16/16", text)
        self.assert_safe()

    def assert_safe(self):
        self.fleet.processes["monitor"].send_signal(signal.SIGINT)
        code = self.fleet.wait_exit("monitor", 60)
        text = read(self.fleet.log("monitor"))
        self.assertIn("overlaps 0", text, text)
        self.assertEqual(code, 0, text)
        states = re.search(r"states (\d+)", text)
        self.assertTrue(states and int(states.group(1)) > 100, "the monitor heard almost nothing:\n" + text)

    def agents(self):
        for index, cell in enumerate(role_starts()):
            self.fleet.agent(f"robot{index}", cell)

    def test_mission_through_a_discovery_server(self):
        server = self.fleet.discovery_server()
        # A second server on the same state (a copied command line with only the port changed)
        # would overwrite the first one's: refused, and the first one goes on.
        port = int(self.fleet.server.rsplit(":", 1)[1])
        result = run([f"{BIN}/ctsfleet-discovery", "--domain", str(self.fleet.domain), "--listen",
                      f"127.0.0.1:{port - 1}", "--dds-config-dir", DDS_DIR,
                      "--state-dir", os.path.join(self.fleet.dir, "discovery-state")])
        self.assertEqual(result.returncode, 2, result.stdout + result.stderr)
        self.assertIn("in use by another ctsfleet-discovery", result.stderr)
        self.assertIsNone(server.poll(), read(self.fleet.log("discovery")))
        self.fleet.monitor()
        self.agents()
        self.fleet.coordinator()
        self.assert_completed_safely()
        # Everyone went through the server: 8 robots, the coordinator and the monitor joined it.
        joined = read(self.fleet.log("discovery")).count("participant joined")
        self.assertGreaterEqual(joined, 10, read(self.fleet.log("discovery")))

    def test_server_killed_and_restarted_while_a_robot_restarts(self):
        """The server dies mid-mission: matched robots keep working. A robot restarted meanwhile
        is found once the server is back, and the mission completes with no collision."""
        self.fleet.discovery_server()
        self.fleet.monitor()
        self.agents()
        self.fleet.coordinator()
        log = self.fleet.log("coordinator")
        wait_for(lambda: "plan epoch 1" in read(log), 120, "the first plan")
        wait_for(lambda: any(int(done) >= 2 for done in re.findall(r"tasks (\d+)/16", read(log))), 120,
                 "the mission under way (two tasks done)")
        server = self.fleet.processes["discovery"]
        server.send_signal(signal.SIGKILL)
        server.wait()
        done_at_kill = max(int(d) for d in re.findall(r"tasks (\d+)/16", read(log)))
        # Without a server the matched fleet goes on.
        wait_for(lambda: max(int(d) for d in re.findall(r"tasks (\d+)/16", read(log))) > done_at_kill, 60,
                 "progress with the discovery server dead")
        cell = self.fleet.kill_robot("robot3")
        self.fleet.agent("robot3", cell)  # no server to find the coordinator through, yet
        os.rename(self.fleet.log("discovery"), self.fleet.log("discovery-first"))
        self.fleet.discovery_server()
        wait_for(lambda: "replanning: robot robot3 joined" in read(log), 60,
                 "the restarted robot found through the restarted server")
        self.assert_completed_safely()

    def test_a_server_that_crashes_starts_again_and_robots_find_it(self):
        """The server process aborts mid-mission (as Fast DDS 2.9.1's does on an assertion of its
        own) at the worst moment: while it rewrites its state file, which it does in place, and
        after the coordinator joined, which the last complete copy of the file does not hold. The
        file is cut short; ctsfleet-discovery puts its last complete copy back and starts the server
        again, which learns the coordinator again; a robot restarted afterwards is found through it,
        and the mission completes with no collision. Stopping ctsfleet-discovery leaves no server."""
        supervisor = self.fleet.discovery_server()
        self.fleet.monitor()
        self.agents()
        log, server_log = self.fleet.log("coordinator"), self.fleet.log("discovery")
        state_dir = os.path.join(self.fleet.dir, "discovery-state")
        wait_for(lambda: read(server_log).count("participant joined") >= 9, 60, "the robots and the monitor joined")
        state_file = [os.path.join(state_dir, name) for name in os.listdir(state_dir)
                      if name.startswith("server-") and name.endswith(".json") and "_queue" not in name]
        self.assertEqual(len(state_file), 1, os.listdir(state_dir))
        state_file = state_file[0]
        joined = read(server_log).count("participant joined")
        wait_for(lambda: participants_in(state_file + ".complete") >= joined, 30,
                 "a complete copy of the server's state with the robots and the monitor kept")
        # The copy is a second old at worst; here, much older: ctsfleet-discovery is stopped (its
        # server goes on) while the coordinator joins, so the copy the server restarts on lacks
        # the coordinator and every endpoint it made.
        os.kill(supervisor.pid, signal.SIGSTOP)
        try:  # continued whatever happens: stopped, it could not stop its server when the test ends
            copied = participants_in(state_file + ".complete")
            self.fleet.coordinator()
            wait_for(lambda: "plan epoch 1" in read(log), 120, "the first plan")
            self.assertEqual(participants_in(state_file + ".complete"), copied, "the copy should lack the coordinator")
            first_server = children_of(supervisor.pid)
            self.assertEqual(len(first_server), 1, f"one server process expected under ctsfleet-discovery: {first_server}")
            # Caught between truncating its state file and writing it again.
            os.kill(first_server[0], signal.SIGSTOP)
            size = os.path.getsize(state_file)
            os.truncate(state_file, size // 2)
            os.kill(first_server[0], signal.SIGABRT)
            os.kill(first_server[0], signal.SIGCONT)
        finally:
            os.kill(supervisor.pid, signal.SIGCONT)
        wait_for(lambda: read(server_log).count("listening on") == 2, 30, "the server started again")
        self.assertIn("the discovery server crashed (Aborted, signal 6): starting it again", read(server_log))
        self.assertIn("was cut short (the server died while writing it): its last complete copy is back", read(server_log))
        self.assertIsNone(supervisor.poll(), read(server_log))
        # A robot that (re)starts now has only the new server to find its coordinator through.
        cell = self.fleet.kill_robot("robot3")
        self.fleet.agent("robot3", cell)
        wait_for(lambda: "replanning: robot robot3 joined" in read(log), 60,
                 "the restarted robot found through the restarted server")
        self.assert_completed_safely()
        second_server = children_of(supervisor.pid)
        supervisor.send_signal(signal.SIGTERM)
        self.assertEqual(self.fleet.wait_exit("discovery", 30), 0, read(server_log))
        for pid in second_server:
            wait_for(lambda: not os.path.exists(f"/proc/{pid}"), 10, f"server process {pid} gone")

    def test_bad_discovery_options_are_refused_clearly(self):
        domain = str(self.fleet.domain)
        agent = [f"{BIN}/ctsfleet-agent", "--id", "robot0", "--start", "1,1", "--domain", domain,
                 "--dds-config-dir", DDS_DIR]
        for value in ("localhost", "127.0.0.1", "127.0.0.1:0", "127.0.0.1:70000", "300.1.1.1:11811", "a:b;c"):
            result = run([*agent, "--dds", "fastdds", "--discovery-server", value])
            self.assertEqual(result.returncode, 2, f"{value}: {result.stdout}{result.stderr}")
            self.assertIn("HOST:PORT", result.stderr, result.stderr)
        # Cyclone has no discovery server: said, not ignored.
        result = run([*agent, "--dds", "cyclone", "--discovery-server", self.fleet.server])
        self.assertEqual(result.returncode, 2, result.stdout + result.stderr)
        self.assertIn("Fast DDS option", result.stderr)
        # Fast DDS 2.9.1 cannot secure a discovery server: refused before the middleware aborts.
        self.fleet.secure(["robot0"])
        result = run([*agent, "--dds", "fastdds", "--discovery-server", self.fleet.server, "--security",
                      self.fleet.fleet_ca])
        self.assertEqual(result.returncode, 2, result.stdout + result.stderr)
        self.assertIn("Fast DDS 2.9.1", result.stderr)
        for args in (["--listen", "127.0.0.1"], ["--listen", "999.0.0.1:5"], ["--listen", "127.0.0.1:80000"],
                     ["--server-id", "256"], ["--max-crashes", "-1"], ["--max-crashes", "many"],
                     ["--listen", "192.0.2.1:65161"]):  # the last: not an address of this host
            workdir = os.path.join(self.fleet.dir, "bad-discovery-options", "_".join(args))
            os.makedirs(workdir, exist_ok=True)
            result = run([f"{BIN}/ctsfleet-discovery", "--domain", domain, "--dds-config-dir", DDS_DIR, *args],
                         cwd=workdir)
            if result.returncode == 2:  # a bad value is refused before a state directory is made
                self.assertEqual(os.listdir(workdir), [], f"{args}: left behind")
            self.assertIn(result.returncode, (1, 2), f"{args}: {result.stdout}{result.stderr}")
            self.assertTrue("--listen" in result.stderr or "server-id" in result.stderr or "max-crashes" in
                            result.stderr or "cannot start discovery server" in result.stderr, f"{args}: {result.stderr}")
            self.assertNotIn("crashed", result.stderr, f"{args}: {result.stderr}")
        sim = [f"{BIN}/ctsfleet-sim", "--robots", "2", "--domain", domain, "--log-dir",
               os.path.join(self.fleet.dir, "sim")]
        result = run([*sim, "--dds", "fastdds", "--agent-dds", "cyclone", "--discovery", "server"])
        self.assertEqual(result.returncode, 2, result.stdout + result.stderr)
        self.assertIn("Fast DDS feature", result.stderr)
        result = run([*sim, "--dds", "fastdds", "--secure", "--discovery", "server"], timeout=120)
        self.assertEqual(result.returncode, 2, result.stdout + result.stderr)
        self.assertIn("Fast DDS 2.9.1", result.stderr)
        bench = run([f"{BIN}/ctsfleet-fleetbench", "-n", "2", "--dds", "cyclone", "--discovery", "server"])
        self.assertEqual(bench.returncode, 2, bench.stdout + bench.stderr)
        # In a fleet config too: the line of the bad key is named.
        config = self.fleet.config_with()
        with open(config) as f:
            text = f.read()
        with open(config, "w") as f:
            f.write(text.replace("dds:\n", "dds:\n  discovery_servers: 127.0.0.1:1\n"))
        result = run([f"{BIN}/ctsfleet-coordinator", "--config", config])
        self.assertEqual(result.returncode, 2, result.stdout + result.stderr)
        self.assertIn("discovery_servers", result.stderr)

    def test_bad_network_options_are_refused_clearly(self):
        domain = str(self.fleet.domain)
        for dds in ("cyclone", "fastdds"):
            for args, says in ((["--iface", "nosuch0"], "no such interface"),
                               (["--peers", "127.0.0.1"], "need a network interface"),
                               (["--iface", "lo", "--peers", "1.2.3"], "not an IPv4 address"),
                               (["--iface", "lo", "--peers", "127.0.0.1,"], "not an IPv4 address")):
                for program in ([f"{BIN}/ctsfleet-agent", "--id", "robot0", "--start", "1,1"],
                                [f"{BIN}/ctsfleet-monitor"],
                                [f"{BIN}/ctsfleet-coordinator", "--config", CONFIG]):
                    result = run([*program, "--dds", dds, "--domain", domain, *args])
                    self.assertEqual(result.returncode, 2, f"{program[0]} {args}: {result.stdout}{result.stderr}")
                    self.assertIn(says, result.stderr, f"{program[0]} {args}")
        config = self.fleet.config_with()
        with open(config) as f:
            text = f.read()
        with open(config, "w") as f:
            f.write(text.replace("dds:\n", "dds:\n  interface: nosuch0\n"))
        result = run([f"{BIN}/ctsfleet-coordinator", "--config", config])
        self.assertEqual(result.returncode, 2, result.stdout + result.stderr)
        self.assertIn("nosuch0", result.stderr)


if __name__ == "__main__":
    unittest.main()
