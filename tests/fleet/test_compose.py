#!/usr/bin/env python3
"""docker/compose.yaml, checked without docker (no daemon runs here): it parses, every service runs
a program of this build with options that program has, the robots stand on the roles' starts of
the mission the coordinator's config names, and every process shares one domain and network. The
topology itself runs in tests/fleet/test_hosts.py over network namespaces."""
import os
import re
import subprocess
import sys
import unittest

import yaml

sys.path.insert(0, os.path.dirname(__file__))
from test_fleet import BIN, ROOT  # noqa: E402

COMPOSE = os.path.join(ROOT, "docker/compose.yaml")
INSTALLED_DATA = "/usr/share/ctsfleet/"  # the package's data folder: config/ of this repository


def local(path):
    return os.path.join(ROOT, path[len(INSTALLED_DATA):]) if path.startswith(INSTALLED_DATA) else path


def option_value(command, option):
    return command[command.index(option) + 1] if option in command else None


class ComposeTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        with open(COMPOSE) as f:
            cls.compose = yaml.safe_load(f)
        cls.services = cls.compose["services"]

    def test_every_service_runs_a_program_with_options_it_has(self):
        helps = {}
        for name, service in self.services.items():
            self.assertEqual(service.get("image"), "ctsfleet", name)
            command = service["command"]
            self.assertIsInstance(command, list, name)
            program = os.path.join(BIN, command[0])
            self.assertTrue(os.access(program, os.X_OK), f"{name}: {command[0]} is not a program of this build")
            if program not in helps:
                helps[program] = subprocess.run([program, "--help"], capture_output=True, text=True, timeout=30).stdout
            for option in (word for word in command[1:] if word.startswith("--")):
                self.assertRegex(helps[program], rf"(^|[\s,]){re.escape(option)}\b", f"{name}: {command[0]} has no {option}")
            for word in command:
                if word.startswith(INSTALLED_DATA):
                    self.assertTrue(os.path.exists(local(word)), f"{name}: {word} is not shipped")

    def test_robots_stand_on_the_missions_role_starts(self):
        config_path = local(option_value(self.services["coordinator"]["command"], "--config"))
        with open(config_path) as f:
            config = yaml.safe_load(f)
        with open(os.path.join(os.path.dirname(config_path), config["mission"])) as f:
            mission = yaml.safe_load(f)
        starts = [f"{a['start'][0]},{a['start'][1]}" for a in mission["agents"]]
        robots = {name: s["command"] for name, s in self.services.items()
                  if s["command"][0] == "ctsfleet-agent" and "toio" not in s.get("profiles", [])}
        self.assertEqual(sorted(option_value(c, "--start") for c in robots.values()), sorted(starts))
        ids = [option_value(c, "--id") for c in robots.values()]
        self.assertEqual(len(set(ids)), len(ids), "two robots with one id")
        self.assertEqual(set(self.services["coordinator"]["depends_on"]), set(robots) | {"monitor"})

    def test_the_dashboard_is_published_on_the_hosts_loopback_only(self):
        dashboard = self.services["dashboard"]
        command = dashboard["command"]
        self.assertEqual(command[0], "ctsfleet-dashboard")
        port = option_value(command, "--port")
        self.assertEqual(option_value(command, "--listen"), "0.0.0.0")  # inside its container
        self.assertEqual(dashboard["ports"], [f"127.0.0.1:{port}:{port}"])

    def test_one_domain_one_network_one_interface(self):
        for name, service in self.services.items():
            command = service["command"]
            self.assertEqual(option_value(command, "--domain"), "0", name)
            self.assertEqual(option_value(command, "--iface"), "eth0", name)
            self.assertEqual(service["networks"], ["fleet"], name)
        self.assertIn("fleet", self.compose["networks"])

    def test_the_toio_agent_gets_the_hosts_dbus_and_its_identity(self):
        toio = self.services["robot-toio"]
        self.assertIn("toio", toio["profiles"])
        self.assertIn("/run/dbus/system_bus_socket:/run/dbus/system_bus_socket", toio["volumes"])
        self.assertIsNotNone(option_value(toio["command"], "--security"))


if __name__ == "__main__":
    unittest.main()
