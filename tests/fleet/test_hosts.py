#!/usr/bin/env python3
"""A fleet over three "hosts": network namespaces joined by a bridge (in a fourth namespace, so
nothing touches this machine's own network), with link-local addresses the test creates and
removes. The coordinator and the monitor run on one host, four robot agents on each of the two
others, all on the LAN interface (--iface) instead of loopback. Skipped, loudly, only where
namespaces cannot be made (no root, no iproute2). Domains 180-189."""
import os
import re
import subprocess
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(__file__))
from test_fleet import BIN, CONFIG, Fleet, failed, read, role_starts, wait_for  # noqa: E402

TESTS = [
    "test_cyclone_multicast_mission_over_three_hosts",
    "test_cyclone_unicast_peers_mission_over_three_hosts",
    "test_fastdds_discovery_server_mission_over_three_hosts",
    "test_host_cut_off_for_three_leases_heals",
    "test_host_that_never_comes_back",
    "test_split_at_the_standbys_host_then_at_the_active_ones",
]
HOSTS = ("c", "a", "b")  # coordinator host, then the two robot hosts


def sh(*args):
    return subprocess.run(list(args), capture_output=True, text=True, timeout=30)


class Lan:
    """Namespaces ctsf<domain><host>, each with interface `fleet0` on a bridge in ctsf<domain>sw."""

    def __init__(self, domain):
        self.prefix = f"ctsf{domain}"
        self.switch = self.prefix + "sw"
        self.address = {host: f"169.254.{domain}.{i + 1}" for i, host in enumerate(HOSTS)}
        self.namespaces = [self.switch] + [self.prefix + h for h in HOSTS]

    def up(self):
        self.down()
        steps = [["ip", "netns", "add", ns] for ns in self.namespaces]
        steps += [["ip", "-n", self.switch, "link", "add", "br0", "type", "bridge"],
                  ["ip", "-n", self.switch, "link", "set", "br0", "up"]]
        for host in HOSTS:
            ns = self.prefix + host
            steps += [["ip", "link", "add", "fleet0", "netns", ns, "type", "veth", "peer", "name", "port" + host,
                       "netns", self.switch],
                      ["ip", "-n", self.switch, "link", "set", "port" + host, "master", "br0"],
                      ["ip", "-n", self.switch, "link", "set", "port" + host, "up"],
                      ["ip", "-n", ns, "addr", "add", self.address[host] + "/24", "dev", "fleet0"],
                      ["ip", "-n", ns, "link", "set", "fleet0", "up", "multicast", "on"],
                      ["ip", "-n", ns, "link", "set", "lo", "up"],
                      ["ip", "-n", ns, "route", "add", "224.0.0.0/4", "dev", "fleet0"]]
        for step in steps:
            result = sh(*step)
            if result.returncode != 0:
                self.down()
                return f"{' '.join(step)}: {result.stderr.strip()}"
        return None

    def down(self):
        for ns in self.namespaces:
            sh("ip", "netns", "del", ns)

    def port(self, host, up):
        result = sh("ip", "-n", self.switch, "link", "set", "port" + host, "up" if up else "down")
        assert result.returncode == 0, result.stderr

    def run_in(self, host):
        return ["ip", "netns", "exec", self.prefix + host]


class HostsTest(unittest.TestCase):
    def setUp(self):
        domain = 180 + 2 * TESTS.index(self._testMethodName)
        self.lan = Lan(domain)
        problem = self.lan.up()
        if problem:
            print(f"\n*** SKIPPED: cannot make network namespaces here ({problem}) ***\n", file=sys.stderr)
            self.skipTest("network namespaces unavailable: " + problem)
        self.fleet = Fleet(self._testMethodName, domain=domain)

    def tearDown(self):
        if hasattr(self, "fleet"):
            self.fleet.close(keep_logs=failed(self))
        self.lan.down()

    def network(self, dds, host, peers=False, server=None):
        args = ["--dds", dds, "--iface", "fleet0"]
        if peers:
            args += ["--peers", ",".join(self.lan.address.values())]
        if server:
            args += ["--discovery-server", server]
        return args

    def start_fleet(self, dds="cyclone", peers=False, server=None, config=CONFIG, monitor_host="c", step="0.05",
                    coordinator_args=()):
        domain = str(self.fleet.domain)
        if server:
            self.fleet.start("discovery", [*self.lan.run_in("c"), f"{BIN}/ctsfleet-discovery", "--domain", domain,
                                           "--listen", server, "--state-dir",
                                           os.path.join(self.fleet.dir, "discovery-state")])
            wait_for(lambda: "listening on" in read(self.fleet.log("discovery")), 30, "the discovery server")
        self.fleet.start("monitor", [*self.lan.run_in(monitor_host), f"{BIN}/ctsfleet-monitor", "--domain", domain,
                                     *self.network(dds, monitor_host, peers, server)])
        started = time.time()
        for index, cell in enumerate(role_starts()):
            host = "a" if index < 4 else "b"
            robot = f"robot{index}"
            self.fleet.start(robot, [*self.lan.run_in(host), f"{BIN}/ctsfleet-agent", "--id", robot, "--start",
                                     f"{cell[0]},{cell[1]}", "--domain", domain, "--step", step,
                                     *self.network(dds, host, peers, server)])
        self.fleet.start("coordinator", [*self.lan.run_in("c"), f"{BIN}/ctsfleet-coordinator", "--config", config,
                                         "--domain", domain, *self.network(dds, "c", peers, server),
                                         *coordinator_args])
        log = self.fleet.log("coordinator")
        wait_for(lambda: "first command of term" in read(log), 120, "the first command")
        print(f"{dds}{' peers' if peers else ''}{' server' if server else ''}: first command "
              f"{time.time() - started:.2f} s after the agents started (8 agents on 2 hosts)")
        return log

    def finish(self):
        code = self.fleet.wait_exit("coordinator", 240)
        text = read(self.fleet.log("coordinator"))
        self.assertEqual(code, 0, text[-3000:])
        self.assertIn("mission completed: tasks 16/16", text)
        self.fleet.processes["monitor"].send_signal(2)
        code = self.fleet.wait_exit("monitor", 60)
        text = read(self.fleet.log("monitor"))
        self.assertIn("overlaps 0", text, text)
        self.assertEqual(code, 0, text)
        self.assertIn("robots 8", text, text)

    def test_cyclone_multicast_mission_over_three_hosts(self):
        self.start_fleet("cyclone")
        self.finish()

    def test_cyclone_unicast_peers_mission_over_three_hosts(self):
        self.start_fleet("cyclone", peers=True)
        self.finish()

    def test_fastdds_discovery_server_mission_over_three_hosts(self):
        self.start_fleet("fastdds", server=f"{self.lan.address['c']}:{65000 + self.fleet.domain}")
        self.finish()

    def test_host_cut_off_for_three_leases_heals(self):
        """Host b's bridge port goes down for 3 s (3 leases): its robots are taken out, come back when
        the link heals, rejoin, and the mission completes with no collision."""
        log = self.start_fleet("cyclone", config=self.fleet.config_with(replacement_timeout_s=30))
        wait_for(lambda: any(int(done) >= 2 for done in re.findall(r"tasks (\d+)/16", read(log))), 120,
                 "the mission under way (two tasks done)")
        self.lan.port("b", up=False)
        wait_for(lambda: len(re.findall(r"robot robot[4-7] taken out", read(log))) >= 1, 30, "the cut seen")
        time.sleep(3.0)  # the cut lasts three leases
        self.lan.port("b", up=True)
        wait_for(lambda: "joined" in read(log).split("taken out")[-1], 60, "host b's robots back")
        self.finish()

    def test_host_that_never_comes_back(self):
        """Host b's bridge port goes down for good mid-mission: its four robots are taken out, the
        robots of host a finish what they can around the cells b's robots were last on, and the
        coordinator ends the mission (replacement timeout) naming what is left, every line of it
        b's roles or blocked by b's robots; no collision among the robots the monitor hears."""
        log = self.start_fleet("cyclone", config=self.fleet.config_with(replacement_timeout_s=3))
        wait_for(lambda: any(int(done) >= 2 for done in re.findall(r"tasks (\d+)/16", read(log))), 120,
                 "the mission under way (two tasks done)")
        self.lan.port("b", up=False)
        wait_for(lambda: len(set(re.findall(r"robot (robot[4-7]) taken out", read(log)))) == 4, 30,
                 "all four robots of host b taken out")
        code = self.fleet.wait_exit("coordinator", 240)
        text = read(log)
        self.assertEqual(code, 3, text[-3000:])  # ended with tasks pending
        self.assertIn("no robot joined within timing.replacement_timeout_s", text)
        self.assertIsNone(re.search(r"replanning: robot robot[4-7] joined", text), text[-3000:])  # never back
        pending = [line for line in text.splitlines() if line.startswith("pending:")]
        self.assertTrue(pending, text[-3000:])
        for line in pending:
            task = re.search(r"task (\d+)", line)
            explained = (re.search(r"role [4-7] \(no robot\)", line) or "could not reach its goal (blocked)" in line
                         or (task and f"task {task.group(1)} unreachable" in text))
            self.assertTrue(explained, "unexplained: " + line)
        self.fleet.processes["monitor"].send_signal(2)
        self.fleet.wait_exit("monitor", 60)
        verdict = read(self.fleet.log("monitor"))
        self.assertIn("overlaps 0", verdict, verdict)

    def test_split_at_the_standbys_host_then_at_the_active_ones(self):
        """A standby on host a, with four of the robots. First host a is cut off for 3 s: the standby
        hears neither the active coordinator nor host b's robots, which that coordinator still
        drives, so it must not take over (a plan taking those robots for walls at their last cells
        would drive robots into them). Then the active coordinator's host c is cut off for good
        but for a moment: the standby hears every robot, takes over, and when c comes back the old
        coordinator stands down. The mission completes, and the monitor (host b) sees no overlap."""
        domain = str(self.fleet.domain)
        log = self.start_fleet("cyclone", monitor_host="b", step="0.05",
                               coordinator_args=["--journal", os.path.join(self.fleet.dir, "active.journal")])
        standby_log = self.fleet.log("standby")
        self.fleet.start("standby", [*self.lan.run_in("a"), f"{BIN}/ctsfleet-coordinator", "--config", CONFIG,
                                     "--domain", domain, *self.network("cyclone", "a"), "--standby"])
        wait_for(lambda: "standby: follows coordinator" in read(standby_log), 60, "the standby following")
        wait_for(lambda: any(int(done) >= 2 for done in re.findall(r"tasks (\d+)/16", read(log))), 120,
                 "the mission under way (two tasks done)")
        self.lan.port("a", up=False)
        wait_for(lambda: "may be cut off from part of the fleet" in read(standby_log), 30,
                 "the standby holding back")
        time.sleep(1.5)  # the cut lasts three leases in all
        self.lan.port("a", up=True)
        wait_for(lambda: "joined" in read(log).split("taken out")[-1], 60, "host a's robots back")
        self.assertNotIn("taking over as term", read(standby_log))
        self.assertNotIn("is not heard here", read(standby_log))  # robots back a moment after the active one
        self.assertEqual(self.fleet.processes["standby"].poll(), None, read(standby_log)[-3000:])
        self.lan.port("c", up=False)
        wait_for(lambda: "taking over as term 2" in read(standby_log), 30, "the standby taking over")
        print("standby took over with " + re.search(r"(\d+ of 16) tasks done", read(standby_log)).group(1) + " tasks done")
        self.lan.port("c", up=True)
        self.assertEqual(self.fleet.wait_exit("coordinator", 60), 5, read(log)[-3000:])  # stood down
        self.assertIn("higher term (2 > 1)", read(log))
        self.assertEqual(self.fleet.wait_exit("standby", 240), 0, read(standby_log)[-3000:])
        self.assertIn("mission completed: tasks 16/16", read(standby_log))
        self.fleet.processes["monitor"].send_signal(2)
        self.assertEqual(self.fleet.wait_exit("monitor", 60), 0, read(self.fleet.log("monitor")))
        verdict = read(self.fleet.log("monitor"))
        self.assertIn("overlaps 0", verdict, verdict)
        self.assertIn("robots 8", verdict, verdict)


if __name__ == "__main__":
    unittest.main()
