#!/usr/bin/env python3
"""DDS Security, tried as an attacker on the same network would: real coordinators, agents, monitor
and attack tools over loopback, a fleet CA made by ctsfleet-ca for each test. Every wait is on a
condition with a generous deadline."""
import os
import re
import shutil
import subprocess
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
from test_fleet import BIN, CONFIG, DDS_DIR, ROOT, Fleet, failed, read, role_starts, wait_for  # noqa: E402

TESTS = [
    "test_cyclone_fleet_keeps_out_every_attack",
    "test_fastdds_fleet_keeps_out_every_attack",
    "test_bad_identities_are_refused_before_and_by_the_middleware",
    "test_real_robot_configs_require_security",
    "test_fleet_ca_refuses_bad_requests",
    "test_sim_secure_runs_and_refuses_mixed_vendors",
]
TOIO_CONFIG = os.path.join(ROOT, "config/toio/fleet.yaml")


def run(args, timeout=120):
    return subprocess.run(args, capture_output=True, text=True, timeout=timeout)


class SecurityTest(unittest.TestCase):
    def setUp(self):
        self.fleet = Fleet(self._testMethodName, domain=140 + 2 * TESTS.index(self._testMethodName))

    def tearDown(self):
        self.fleet.close(keep_logs=failed(self))

    def tool(self, name, dds, *args):
        """Runs an attack tool on the test's domain; returns its CompletedProcess."""
        return run([f"{BIN}/{name}", "--dds", dds, "--domain", str(self.fleet.domain), "--dds-config-dir", DDS_DIR,
                    *args])

    def attacks_during_a_mission(self, dds):
        fleet = self.fleet
        fleet.secure([f"robot{i}" for i in range(8)], coordinators=("coordinator", "rogue"))
        # Intruders: robot8 has no certificate; robot9 has one from another fleet's CA.
        foreign = os.path.join(fleet.dir, "foreign-ca")
        run([f"{BIN}/ctsfleet-ca", "init", foreign])
        fleet.enrol("robot", "robot9", fleet_ca=foreign)
        fleet.monitor(dds)
        fleet.agents(dds)
        fleet.start("robot8", [f"{BIN}/ctsfleet-agent", "--id", "robot8", "--start", "1,1", "--dds", dds,
                               "--domain", str(fleet.domain), "--dds-config-dir", DDS_DIR])
        fleet.start("robot9", [f"{BIN}/ctsfleet-agent", "--id", "robot9", "--start", "2,1", "--dds", dds,
                               "--domain", str(fleet.domain), "--dds-config-dir", DDS_DIR, "--security", foreign])
        # Slow steps, so that the attacks land while the robots move.
        fleet.coordinator(dds, config=fleet.config_with(step_s=0.1))
        log = fleet.log("coordinator")
        wait_for(lambda: "plan epoch 1" in read(log), 120, "the first plan")
        wait_for(lambda: any(int(d) >= 1 for d in re.findall(r"tasks (\d+)/16", read(log))), 120, "a task done")
        ca = fleet.fleet_ca
        goal = role_starts()[2]
        # An enrolled robot's identity drives another robot, at a far-future epoch: it may not even
        # read robot states or write commands, so the tool cannot start.
        drive = self.tool("ctsfleet-test-drive", dds, "--security", ca, "--identity", "robot1", "--robot", "robot2",
                          "--epoch", "1000000", "--path", f"{goal[0]},{goal[1]+1}", "--timeout", "5")
        self.assertEqual(drive.returncode, 4, drive.stdout + drive.stderr)
        self.assertIn("refused", drive.stderr)
        # An observer reads states (the monitor does, below) but its command writer is refused.
        observe = self.tool("ctsfleet-test-drive", dds, "--security", ca, "--identity", "monitor", "--robot", "robot2",
                            "--epoch", "1000000", "--path", f"{goal[0]},{goal[1]+1}", "--timeout", "5")
        self.assertEqual(observe.returncode, 4, observe.stdout + observe.stderr)
        self.assertRegex(observe.stderr, r"command writer (of|for) robot2")
        # robot1's identity writing robot6's state in robot6's partition: refused by access control.
        claim = self.tool("ctsfleet-test-inject", dds, "--security", ca, "--identity", "robot1", "--claim", "robot6",
                          "--rounds", "5")
        self.assertEqual(claim.returncode, 4, claim.stdout + claim.stderr)
        # The same from robot1's own partition (as a modified program could): the coordinator drops
        # it, because the id is not the partition's, and says so.
        own = self.tool("ctsfleet-test-inject", dds, "--security", ca, "--identity", "robot1", "--claim", "robot6",
                        "--in-partition-of", "robot1", "--at", "1", "--at-y", "1", "--rounds", "40")
        self.assertEqual(own.returncode, 0, own.stdout + own.stderr)
        wait_for(lambda: "refused: a message about robot 'robot6' written in partition 'robot/robot1'" in read(log), 60,
                 "the coordinator's refusal of the impostor")
        # An enrolled coordinator the robots do not follow sends far-future epochs and commands in its
        # own name past DDS ownership: the robot obeys only the coordinator it follows (defence in
        # depth behind access control).
        rogue = self.tool("ctsfleet-test-inject", dds, "--security", ca, "--identity", "rogue", "--victim", "robot2")
        self.assertEqual(rogue.returncode, 0, rogue.stdout + rogue.stderr)
        wait_for(lambda: "this robot follows" in read(fleet.log("robot2")), 60, "robot2 refusing the rogue's commands")
        code = fleet.wait_exit("coordinator", 240)
        text = read(log)
        self.assertEqual(code, 0, text[-3000:])
        self.assertIn("mission completed: tasks 16/16", text)
        self.assertNotIn("robot robot8", text)
        self.assertNotIn("robot robot9", text)
        self.assertNotIn("robot robot6 taken out", text)
        self.assertIn("robots lost 0 joined 0", text)
        code, verdict = fleet.monitor_verdict()
        self.assertIn("overlaps 0", verdict, verdict)
        self.assertEqual(code, 0, verdict)
        states = re.search(r"states (\d+)", verdict)
        self.assertTrue(states and int(states.group(1)) > 100, "the observer read almost nothing:\n" + verdict)
        self.assertIn("robots 8, processes 8,", verdict)  # the intruders' states never reached the observer
        return text

    def test_cyclone_fleet_keeps_out_every_attack(self):
        text = self.attacks_during_a_mission("cyclone")
        # Cyclone names the refused certificate in the coordinator's log, once a minute at most.
        self.assertRegex(text, r"Cyclone DDS: .*certificate signature failure; subject: /O=ctsfleet/CN=robot9")
        self.assertLess(text.count("CN=robot9"), 10, "the refusal floods the log")

    def test_fastdds_fleet_keeps_out_every_attack(self):
        text = self.attacks_during_a_mission("fastdds")
        self.assertIn("failed authentication", text)

    def test_bad_identities_are_refused_before_and_by_the_middleware(self):
        fleet = self.fleet
        fleet.secure(["robot1", "robot2"])
        ca = fleet.fleet_ca
        # Expired: a certificate of the fleet's CA whose validity ended in 2020.
        work = os.path.join(fleet.dir, "expired")
        os.makedirs(work)
        with open(os.path.join(work, "ca.cnf"), "w") as f:
            f.write(f"[ca]\ndefault_ca = old\n[old]\ndatabase = {work}/index.txt\nnew_certs_dir = {work}\n"
                    f"certificate = {ca}/ca/identity_ca.pem\nprivate_key = {ca}/ca/identity_ca.key\n"
                    f"default_md = sha256\npolicy = any\nserial = {work}/serial\n[any]\ncommonName = supplied\n")
        open(os.path.join(work, "index.txt"), "w").close()
        with open(os.path.join(work, "serial"), "w") as f:
            f.write("01\n")
        fleet.enrol("robot", "old")
        old = os.path.join(ca, "participants/old")
        subprocess.run(["openssl", "req", "-new", "-key", f"{old}/key.pem", "-subj", "/O=ctsfleet/CN=old",
                        "-out", f"{work}/old.csr"], check=True, capture_output=True)
        subprocess.run(["openssl", "ca", "-batch", "-config", f"{work}/ca.cnf", "-startdate", "20200101000000Z",
                        "-enddate", "20200102000000Z", "-in", f"{work}/old.csr", "-out", f"{old}/cert.pem"],
                       check=True, capture_output=True)
        # Tampered: one byte of robot1's signed permissions changed (robot/robot1 -> robot/robot2).
        tampered = os.path.join(fleet.dir, "tampered-ca")
        shutil.copytree(ca, tampered)
        path = os.path.join(tampered, "participants/robot1/permissions.p7s")
        with open(path, "rb") as f:
            data = bytearray(f.read())
        at = data.index(b"<partition>robot/robot1") + len(b"<partition>robot/robot")
        data[at] = ord("2")
        with open(path, "wb") as f:
            f.write(bytes(data))
        # Revoked: robot2's folder is kept aside before ctsfleet-ca revokes it, as a thief would.
        stolen = os.path.join(fleet.dir, "stolen")
        shutil.copytree(os.path.join(ca, "participants/robot2"), stolen)
        self.assertEqual(run([f"{BIN}/ctsfleet-ca", "revoke", ca, "robot2"]).returncode, 0)
        shutil.copytree(stolen, os.path.join(ca, "participants/robot2"))

        cases = [(ca, "old", "certificate has expired"),
                 (tampered, "robot1", "signature does not verify"),
                 (ca, "robot2", "certificate revoked")]
        for dds in ("cyclone", "fastdds"):
            for fleet_dir, name, reason in cases:
                # The fleet's own programs check the files first and say what is wrong.
                agent = run([f"{BIN}/ctsfleet-agent", "--id", name, "--dds", dds, "--domain", str(fleet.domain),
                             "--dds-config-dir", DDS_DIR, "--security", fleet_dir], timeout=60)
                self.assertEqual(agent.returncode, 2, f"{dds} {name}: {agent.stdout}{agent.stderr}")
                self.assertIn(reason, agent.stderr)
                # A program without those checks is refused by the security plugins themselves,
                # except a revoked identity on Fast DDS 2.9, which reads no revocation list.
                raw = self.tool("ctsfleet-test-inject", dds, "--security", fleet_dir, "--identity", name,
                                "--claim", name, "--rounds", "2")
                if dds == "fastdds" and name == "robot2":
                    self.assertEqual(raw.returncode, 0, raw.stderr)
                    continue
                self.assertEqual(raw.returncode, 4, f"{dds} {name}: {raw.stdout}{raw.stderr}")
                self.assertIn("refused", raw.stderr)
        # The revoked identity is refused on Cyclone by the coordinator's side too: it never joins.
        fleet.coordinator("cyclone")
        fleet.start("thief", [f"{BIN}/ctsfleet-test-inject", "--domain", str(fleet.domain), "--dds-config-dir", DDS_DIR,
                              "--security", ca, "--identity", "robot1", "--claim", "robot1", "--rounds", "60"])
        wait_for(lambda: "robot robot1 announced" in read(fleet.log("coordinator")), 60, "an enrolled robot heard")
        self.assertNotIn("robot robot2", read(fleet.log("coordinator")))

    def test_real_robot_configs_require_security(self):
        fleet = self.fleet
        result = run([f"{BIN}/ctsfleet-coordinator", "--config", TOIO_CONFIG, "--domain", str(fleet.domain)], 60)
        self.assertEqual(result.returncode, 2, result.stdout + result.stderr)
        self.assertIn("security.required", result.stderr)
        self.assertIn("ctsfleet-ca init", result.stderr)
        agent = run([f"{BIN}/ctsfleet-agent", "--id", "robot0", "--backend", "toio", "--cube", "toio-0", "--mat",
                     os.path.join(ROOT, "config/mats/toio-collection-ring.yaml"), "--domain", str(fleet.domain)], 60)
        self.assertEqual(agent.returncode, 2, agent.stdout + agent.stderr)
        self.assertIn("requires --security", agent.stderr)
        fleet.secure(["robot0"])
        cases = [
            (["--security", os.path.join(fleet.dir, "nowhere")], "does not exist"),
            (["--security", fleet.fleet_ca, "--identity", "stranger"], "ctsfleet-ca add-robot"),
            (["--security", fleet.fleet_ca, "--identity", "robot0"], None),  # a robot's identity may not coordinate
        ]
        for extra, expected in cases:
            result = run([f"{BIN}/ctsfleet-coordinator", "--config", TOIO_CONFIG, "--domain", str(fleet.domain),
                          *extra], 60)
            self.assertNotEqual(result.returncode, 0, f"{extra}: {result.stdout}{result.stderr}")
            self.assertNotIn("Segmentation", result.stderr)
            if expected:
                self.assertEqual(result.returncode, 2, result.stderr)
                self.assertIn(expected, result.stderr)
            else:
                self.assertIn("Not Allowed By Security", result.stderr)
        # An open (loopback) simulation warns once that anyone on the domain can join.
        fleet.fleet_ca = None
        fleet.coordinator(config=fleet.config_with(mission_timeout_s=5))
        wait_for(lambda: "DDS Security is off" in read(fleet.log("coordinator")), 60, "the warning")

    def test_fleet_ca_refuses_bad_requests(self):
        ca = os.path.join(self.fleet.dir, "ca")
        tool = f"{BIN}/ctsfleet-ca"
        self.assertEqual(run([tool, "init", ca]).returncode, 0)
        refusals = [
            ([tool, "init", ca], "already holds a fleet CA"),
            ([tool, "add-robot", ca, "robot 1"], "not a valid name"),
            ([tool, "add-robot", ca, "../etc"], "not a valid name"),
            ([tool, "add-robot", ca, "r" * 33], "not a valid name"),
            ([tool, "add-robot", os.path.join(self.fleet.dir, "none"), "robot1"], "not a fleet directory"),
            ([tool, "add-robot", ca, "robot1", "--days", "0"], "--days"),
            ([tool, "add-robot", ca, "robot1", "--days", "abc"], "--days"),
            ([tool, "revoke", ca, "ghost"], "not enrolled"),
            ([tool, "frobnicate"], "unknown command"),
            ([tool, "init", os.path.join(self.fleet.dir, "x"), "--domains", "5-300"], "--domains"),
        ]
        for args, expected in refusals:
            result = run(args)
            self.assertEqual(result.returncode, 2, f"{args}: {result.stdout}{result.stderr}")
            self.assertIn(expected, result.stderr, args)
            # Named as the user typed it: a bare "fleet-ca" in the advice is a command not found.
            self.assertRegex(result.stderr, r"^ctsfleet-ca: error: ", args)
            self.assertNotRegex(result.stderr, r"(^|[^-\w])fleet-ca ", args)
        self.assertEqual(run([tool, "add-robot", ca, "robot1"]).returncode, 0)
        again = run([tool, "add-robot", ca, "robot1"])
        self.assertEqual(again.returncode, 2)
        self.assertIn("already enrolled", again.stderr)
        listing = run([tool, "list", ca])
        self.assertRegex(listing.stdout, r"robot1 +robot +until")
        key_mode = os.stat(os.path.join(ca, "ca/identity_ca.key")).st_mode & 0o777
        self.assertEqual(key_mode, 0o600)

    def test_sim_secure_runs_and_refuses_mixed_vendors(self):
        fleet = self.fleet
        mixed = run([f"{BIN}/ctsfleet-sim", "--secure", "--dds", "cyclone", "--agent-dds", "fastdds", "--domain",
                     str(fleet.domain), "--log-dir", os.path.join(fleet.dir, "mixed")], 60)
        self.assertEqual(mixed.returncode, 2, mixed.stdout + mixed.stderr)
        self.assertIn("does not work across the two vendors", mixed.stderr)
        fleet.start("sim", [f"{BIN}/ctsfleet-sim", "--secure", "--robots", "8", "--config", CONFIG, "--domain",
                            str(fleet.domain), "--step", "0.05", "--log-dir", os.path.join(fleet.dir, "sim")])
        code = fleet.wait_exit("sim", 240)
        text = read(fleet.log("sim"))
        self.assertEqual(code, 0, text[-3000:])
        self.assertIn("DDS Security on: throw-away fleet CA", text)
        self.assertIn("mission completed: tasks 16/16", text)


if __name__ == "__main__":
    unittest.main()
