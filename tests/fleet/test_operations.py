#!/usr/bin/env python3
"""Operating a running fleet with real processes over loopback: tasks added with ctsfleet-task in
mid-mission, a lifelong mission given tasks in waves, and ctsfleet-dashboard opened in a real
browser (Debian's chromium, headless, driven by chromedriver through Selenium). The safety monitor
watches every fleet. Every wait is on a condition with a generous deadline."""
import json
import os
import socket
import sqlite3
import statistics
import threading
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest
import urllib.error
import urllib.request

import yaml

sys.path.insert(0, os.path.dirname(__file__))
from test_fleet import BIN, CONFIG, DDS_DIR, MISSION, ROOT, Fleet, failed, read, wait_for  # noqa: E402

TESTS = [
    "test_tasks_added_mid_mission_are_done_and_bad_ones_refused",
    "test_lifelong_mission_takes_tasks_in_three_waves",
    "test_dashboard_in_a_real_browser",
    "test_a_task_added_survives_a_failover",
    "test_fastdds_fleet_takes_tasks_and_its_dashboard_sees_them",
    "test_hostile_ids_and_texts_run_no_script_in_the_dashboard",
    "test_the_dashboard_answers_with_idle_streams_and_slow_sockets_open",
    "test_a_lifelong_stream_grows_the_plan_and_outlives_a_restarted_robot",
    "test_a_lifelong_pool_outlives_its_coordinator_killed_and_restarted_with_its_journal",
    "test_the_league_scenario_runs_a_problem_beside_its_lockstep_run_and_refuses_what_it_cannot",
]

# Markup an attacker may put in a robot id, an event kind or an event text: each would set
# window.pwned if the page ever parsed it as HTML.
HOSTILE = [
    '<img src=x onerror="window.pwned=(window.pwned||0)+1">',
    '"><script>window.pwned=(window.pwned||0)+1</script>',
    "<svg onload=window.pwned=(window.pwned||0)+1>",
]


def mission():
    with open(MISSION) as f:
        return yaml.safe_load(f)


def free_cells_away_from_the_mission():
    """Free cells of the mission map that are no task, start or goal (a task there is new work)."""
    m = mission()
    with open(os.path.join(os.path.dirname(MISSION), m["map"])) as f:
        rows = f.read().split("map\n", 1)[1].split()
    taken = {tuple(t["at"]) for t in m["tasks"]}
    taken |= {tuple(a["start"]) for a in m["agents"]} | {tuple(a["goal"]) for a in m["agents"]}
    return [(x, y) for y, row in enumerate(rows) for x, c in enumerate(row) if c == "." and (x, y) not in taken]


def summary_of(text):
    return json.loads(next(line for line in reversed(text.splitlines()) if line.startswith("{")))


class OperationsTest(unittest.TestCase):
    def setUp(self):
        # Domains 84-98, then 200 and up: 100-198 are other files' tests'.
        index = TESTS.index(self._testMethodName)
        self.fleet = Fleet(self._testMethodName, domain=84 + 2 * index if index < 8 else 200 + 2 * (index - 8))

    def tearDown(self):
        self.fleet.close(keep_logs=failed(self))

    def config(self, lifelong):
        with open(CONFIG) as f:
            config = yaml.safe_load(f)
        config["mission"] = os.path.abspath(MISSION)
        config["dds"]["config_dir"] = os.path.abspath(DDS_DIR)
        config["lifelong"] = lifelong
        path = os.path.join(self.fleet.dir, "fleet.yaml")
        with open(path, "w") as f:
            yaml.safe_dump(config, f)
        return path

    def task(self, *args, timeout=60, dds="cyclone"):
        """Runs ctsfleet-task; returns (exit code, stdout + stderr)."""
        done = subprocess.run([f"{BIN}/ctsfleet-task", "--domain", str(self.fleet.domain), "--dds-config-dir", DDS_DIR,
                               "--dds", dds, "--timeout", "30", *args], capture_output=True, text=True, timeout=timeout)
        return done.returncode, done.stdout + done.stderr

    def listing(self):
        code, text = self.task("list")
        self.assertEqual(code, 0, text)
        return {int(m.group(1)): m.group(2) for m in re.finditer(r"^task (\d+) at \(\d+,\d+\): (\w+)", text, re.M)}

    def start_fleet(self, lifelong, dds="cyclone"):
        self.fleet.monitor(dds)
        self.fleet.agents(dds)
        self.fleet.coordinator(dds=dds, config=self.config(lifelong), extra=["--json"])
        wait_for(lambda: "plan epoch" in read(self.fleet.log("coordinator")), 120, "the first plan")

    def assert_safe(self):
        code, text = self.fleet.monitor_verdict()
        self.assertIn("overlaps 0", text, text)
        self.assertEqual(code, 0, text)

    def test_tasks_added_mid_mission_are_done_and_bad_ones_refused(self):
        self.start_fleet(lifelong=False)
        cells = free_cells_away_from_the_mission()
        added = []
        for args in (["--any"], ["--robot", "robot3"], ["--any"]):
            x, y = cells[len(added) * 37 % len(cells)]
            code, text = self.task("add", "--at", f"{x},{y}", *args)
            self.assertEqual(code, 0, text)
            match = re.search(r"task (\d+) at \((\d+),(\d+)\) given to robot (\w+)", text)
            self.assertTrue(match, text)
            if args[0] == "--robot":
                self.assertEqual(match.group(4), "robot3")
            added.append(int(match.group(1)))
        self.assertEqual(added, [16, 17, 18])
        # Clumsy operators: each refused with its reason, and nothing changes.
        for args, reason in ((["add", "--at", "0,0", "--any"], "(0,0) is a wall"),
                             (["add", "--at", "999,3", "--any"], "off the map"),
                             (["add", "--at", "1,1", "--robot", "robot99"], "unknown robot 'robot99'"),
                             (["cancel", "99"], "no task 99")):
            code, text = self.task(*args)
            self.assertEqual(code, 1, text)
            self.assertIn(reason, text)
        code, text = self.task("add", "--at", "1;1", "--any")
        self.assertEqual(code, 2, text)
        self.assertIn("--at '1;1': expected X,Y", text)
        code = self.fleet.wait_exit("coordinator", 240)
        text = read(self.fleet.log("coordinator"))
        self.assertEqual(code, 0, text[-3000:])
        summary = summary_of(text)
        self.assertTrue(summary["completed"], summary)
        self.assertEqual(summary["tasks_total"], 19)
        self.assertEqual(summary["tasks_done"], 19)
        self.assert_safe()

    def test_lifelong_mission_takes_tasks_in_three_waves(self):
        self.start_fleet(lifelong=True)
        log = self.fleet.log("coordinator")
        cells = free_cells_away_from_the_mission()
        next_task = 16
        for wave, size in enumerate((2, 3, 2)):
            wait_for(lambda: read(log).count("every task done: the robots park") == wave, 240,
                     f"the fleet idle before wave {wave}")
            for i in range(size):
                x, y = cells[(wave * 7 + i) * 29 % len(cells)]
                code, text = self.task("add", "--at", f"{x},{y}", "--any")
                self.assertEqual(code, 0, text)
                self.assertIn(f"task {next_task} at ({x},{y})", text)
                next_task += 1
        wait_for(lambda: read(log).count("every task done: the robots park") == 3, 240, "the last wave done")
        states = self.listing()
        self.assertEqual(len(states), 23)
        self.assertTrue(all(state == "done" for state in states.values()), states)
        time.sleep(2)  # lifelong: nothing ends it but the operator
        self.assertIsNone(self.fleet.processes["coordinator"].poll(), read(log)[-2000:])
        self.fleet.processes["coordinator"].send_signal(signal.SIGINT)
        self.fleet.wait_exit("coordinator", 60)
        self.assert_safe()

    def test_a_lifelong_stream_grows_the_plan_and_outlives_a_restarted_robot(self):
        # Tasks arrive one after the other while the robots move: the plan grows by windows, the
        # fleet never stops to replan for a task. Mid-stream a robot is SIGKILLed: the plan is cut
        # round it and the others go on (no replan); the robot, started again where it stood, takes
        # its place in the plan and a role back, again without a replan.
        self.start_fleet(lifelong=True)
        log = self.fleet.log("coordinator")
        cells = free_cells_away_from_the_mission()
        for k in range(14):
            if k == 7:  # robot2's process dies mid-stream and is started again where it stood
                self.fleet.processes["robot2"].kill()
                wait_for(lambda: re.search(r"robot robot2 taken out: .*\(last at \((\d+),(\d+)\)\)", read(log)), 60,
                         "robot2 taken out")
                last = re.search(r"robot robot2 taken out: .*\(last at \((\d+),(\d+)\)\)", read(log))
                self.fleet.processes["robot2"].wait()
                self.fleet.agent("robot2", (int(last.group(1)), int(last.group(2))))
            x, y = cells[k * 31 % len(cells)]
            code, text = self.task("add", "--at", f"{x},{y}", "--any")
            self.assertEqual(code, 0, text)
            self.assertIn("it gets there in about", text)  # lifelong: the robot that gets there soonest
        wait_for(lambda: re.search(r"robot robot2 takes role \d", read(log).split("robot robot2 taken out")[-1]), 120,
                 "robot2 back with a role")
        wait_for(lambda: all(state == "done" for state in self.listing().values()), 240, "every task done")
        self.fleet.processes["coordinator"].send_signal(signal.SIGINT)
        self.fleet.wait_exit("coordinator", 60)
        text = read(log)
        summary = summary_of(text)
        self.assertEqual(summary["tasks_done"], summary["tasks_total"])
        self.assertEqual(summary["tasks_total"], 16 + 14)
        self.assertGreater(summary["windows"], 10, summary)
        self.assertIn("lifelong: the plan takes task", text)
        # Neither the loss, nor robot2's return, nor the fourteen tasks replanned the fleet.
        self.assertIn("lifelong: the plan goes on around robot robot2", text)
        self.assertIn("lifelong: robot robot2 is back at", text)
        self.assertEqual(summary["robots_planned_around"], 1, summary)
        self.assertEqual(summary["robots_taken_back"], 1, summary)
        self.assertEqual(summary["replans"], 0, summary)
        self.assertNotIn("replanning:", text)
        self.assert_safe()

    def test_a_lifelong_pool_outlives_its_coordinator_killed_and_restarted_with_its_journal(self):
        # Eighteen tasks at once, two of them for robot3: queues form, and robots that run out of
        # tasks take queued ones (the pool), each move journaled first. The coordinator is SIGKILLed
        # once a task has moved, and started again with its journal: every task is done once, by
        # the role the journal holds it for; robot3's two by robot3; nobody collides.
        journal = os.path.join(self.fleet.dir, "lifelong.journal")
        config = self.config(lifelong=True)

        def coordinator(name):
            self.fleet.start(name, [f"{BIN}/ctsfleet-coordinator", "--config", config, "--dds", "cyclone", "--domain",
                                    str(self.fleet.domain), "--json", "--journal", journal])
            return self.fleet.log(name)

        self.fleet.monitor()
        self.fleet.agents()
        first_log = coordinator("first")
        wait_for(lambda: "plan epoch" in read(first_log), 120, "the first plan")
        cells = free_cells_away_from_the_mission()
        named = []
        for k in range(18):
            x, y = cells[k * 29 % len(cells)]
            code, text = self.task("add", "--at", f"{x},{y}", *(["--robot", "robot3"] if k in (5, 11) else ["--any"]))
            self.assertEqual(code, 0, text)
            if k in (5, 11):
                named.append(int(re.search(r"task (\d+) at", text).group(1)))
        wait_for(lambda: "lifelong pool: task" in read(first_log), 180, "a queued task moved to a robot out of tasks")
        first = self.fleet.processes["first"]
        first.send_signal(signal.SIGKILL)
        first.wait()
        log = coordinator("restarted")
        wait_for(lambda: "resuming run 1" in read(log), 60, "the restarted coordinator resuming from its journal")
        wait_for(lambda: (lambda tasks: len(tasks) == 16 + 18 and all(s == "done" for s in tasks.values()))(self.listing()),
                 300, "every task done")
        self.fleet.processes["restarted"].send_signal(signal.SIGINT)
        self.fleet.wait_exit("restarted", 60)
        db = sqlite3.connect(journal)
        try:
            role_of = dict(db.execute("SELECT task, role FROM tasks_added"))
            visits = db.execute("SELECT task, role, robot FROM visits WHERE task >= 16").fetchall()
            pinned = [task for (task,) in db.execute("SELECT task FROM tasks_pinned ORDER BY task")]
        finally:
            db.close()
        self.assertEqual(sorted(task for task, _, _ in visits), sorted(role_of))  # each once
        for task, role, robot in visits:
            self.assertEqual(role, role_of[task], f"task {task} visited by role {role}, journaled for {role_of[task]}")
            if task in named:
                self.assertEqual(robot, "robot3", f"task {task} was named for robot3")
        self.assertEqual(pinned, sorted(named))
        self.assert_safe()

    def test_the_league_scenario_runs_a_problem_beside_its_lockstep_run_and_refuses_what_it_cannot(self):
        problem = os.path.join(ROOT, "benchmarks/lorr-2023/warehouse.domain/warehouse_small_10.json")
        room = os.path.join(ROOT, "benchmarks/lorr-2026/room.domain/room-example_150.json")  # 2 errands a task
        bad_delays = os.path.join(self.fleet.dir, "bad-delays.json")
        with open(bad_delays, "w") as f:
            json.dump({"seed": 0, "minDelay": -3, "maxDelay": 5, "eventModel": "bernoulli", "pDelay": 0.1,
                       "durationModel": "uniform"}, f)
        work = os.path.join(self.fleet.dir, "work")  # the bench's TMPDIR: where its work folder goes
        os.makedirs(work)
        env = dict(os.environ, TMPDIR=work)
        bench = [f"{BIN}/ctsfleet-fleetbench", "--scenario", "league", "--domain", str(self.fleet.domain)]
        for args, says in ((["--problem", room, "-n", "4"], "task 0 has 2 errands"),
                           (["--problem", problem, "-n", "11"], "has a team of 10"),
                           (["--problem", problem, "-n", "4", "--delays", "on"], "has no delayConfig"),
                           (["--problem", problem, "-n", "4", "--delay-config", bad_delays], "minDelay"),
                           (["--problem", problem, "-n", "4", "--actions", "move4", "--turn", "1"], "plans turns"),
                           (["-n", "4"], "give the problem")):
            result = subprocess.run(bench + args, capture_output=True, text=True, timeout=60, env=env)
            self.assertEqual(result.returncode, 2, f"{args}: {result.stdout}{result.stderr}")
            self.assertIn(says, result.stderr, args)
            self.assertEqual(os.listdir(work), [], f"{args}: left a partial run")
        # 4 robot processes on the 2023 warehouse problem, delayed as the 2026 room problem draws.
        result = subprocess.run(bench + ["--problem", problem, "-n", "4", "--measure", "25", "--step", "0.2",
                                         "--delay-config", room, "--json"],
                                capture_output=True, text=True, timeout=900, env=env)
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        row = summary_of(result.stdout)
        self.assertEqual(row["delays"], "on")
        self.assertEqual(row["collisions"], "0", row)
        self.assertGreater(row["fleet"]["tasks_done"], 0, row)
        self.assertGreater(row["steps"], 0, row)
        self.assertTrue(row["lockstep"]["ran"], read(os.path.join(row["logs"], "league-lockstep-4.log")))
        self.assertEqual(row["lockstep"]["ticks"], row["steps"], "the 2023 problem's action is a tick")
        self.assertGreater(row["lockstep"]["tasks"], 0, row)
        self.assertEqual(row["lockstep"]["faults"], 0, row)
        self.assertGreater(row["lockstep"]["delayed_share"], 0, row)
        self.assertAlmostEqual(row["ratio"], row["fleet"]["tasks_done"] / row["lockstep"]["tasks"], places=6)
        with open(os.path.join(row["logs"], "league-problem-4.json")) as f:
            cut = json.load(f)
        with open(room) as f:
            self.assertEqual(cut["delayConfig"], json.load(f)["delayConfig"])
        self.assertEqual(cut["teamSize"], 4)
        robot_logs = "".join(read(os.path.join(row["logs"], f"league-robot{r}.log")) for r in range(4))
        self.assertIn("this move delayed", robot_logs, "no sim robot was delayed")
        # Both runs as the league's output files. The fleet's, replayed on its ticks by the
        # independent checker: no cell held by two robots at a tick, every task done with its robot
        # on it, as many tasks as the fleet counted (give or take those done as the count ended).
        self.assertTrue(os.path.exists(os.path.join(row["logs"], "league-lockstep-4", "league-problem-4.lorr.json")))
        output = row["fleet_output"]
        replay = subprocess.run(["python3", os.path.join(ROOT, "tests", "lorr_2026_replay.py"), output["file"],
                                 cut["mapFile"]], capture_output=True, text=True, timeout=120)
        self.assertEqual(replay.returncode, 0, replay.stdout + replay.stderr)
        self.assertEqual(output["jumps"], 0, output)
        self.assertLessEqual(abs(output["tasks"] - row["fleet"]["tasks_done"]), 3, row)
        with open(output["file"]) as f:
            written = json.load(f)
        self.assertEqual((written["teamSize"], written["delaysOn"]), (4, True))
        self.assertGreater(sum(path.count("F") for path in written["actualPaths"]), 0)

    def test_hostile_ids_and_texts_run_no_script_in_the_dashboard(self):
        # Whatever reaches the dashboard (a forged state, an event) is shown as text: a replayed
        # history carries markup in robot ids, an event's kind, robot and text.
        browser = chromium_driver(self)
        if browser is None:
            return
        history = os.path.join(self.fleet.dir, "hostile.jsonl")
        with open(history, "w") as f:
            f.write(json.dumps({"format": "ctsfleet-history-1"}) + "\n")
            for k, markup in enumerate(HOSTILE):
                state = {"robot_id": markup, "cell_x": k, "cell_y": 0, "pose_x": k, "pose_y": 0, "pose_theta": 0,
                         "plan_epoch": 1, "action_index": 0, "status": "idle", "battery_percent": 50,
                         "seq_number": 1, "stamp_ms": 1000, "incarnation": 7 + k, "coordinator": 0}
                f.write(json.dumps({"t": 100 + k, "type": "state", "msg": state}) + "\n")
                event = {"coordinator": 1, "stamp_ms": 1000, "kind": markup, "robot_id": markup, "text": markup,
                         "value": 0}
                f.write(json.dumps({"t": 200 + k, "type": "event", "msg": event}) + "\n")
        dashboard = self.fleet.start("dashboard", [f"{BIN}/ctsfleet-dashboard", "--replay", history, "--port", "0",
                                                   "--speed", "1"])
        log = self.fleet.log("dashboard")
        wait_for(lambda: "dashboard: http://" in read(log), 60, "the dashboard's address")
        url = re.search(r"dashboard: (http://\S+)", read(log)).group(1)
        browser.get(url)
        events = lambda: browser.find_element("id", "events").text
        robots = lambda: browser.find_element("css selector", "#robots tbody").text
        wait_for(lambda: all(markup in events() for markup in HOSTILE), 60, "the hostile events shown as text")
        wait_for(lambda: all(markup in robots() for markup in HOSTILE), 60, "the hostile ids shown as text")
        self.assertIsNone(browser.execute_script("return window.pwned"), "a script from the data ran in the page")
        self.assertEqual(browser.execute_script("return document.querySelectorAll('#events img, #events script, "
                                                "#events svg, #robots img, #robots script, #robots svg').length"), 0)
        dashboard.send_signal(signal.SIGINT)
        self.fleet.wait_exit("dashboard", 30)

    def test_the_dashboard_answers_with_idle_streams_and_slow_sockets_open(self):
        # 100 event streams that are never read (from 127.0.0.2) and 100 sockets sending their
        # request a byte at a time (from 127.0.0.3): the page, asked from 127.0.0.1, still answers.
        instance = os.path.join(os.path.dirname(__file__), "..", "data", "instances", "random-32-32-20-N10-M30-00.yaml")
        plan = os.path.join(self.fleet.dir, "plan.txt")
        solved = subprocess.run([f"{BIN}/ctsfleet-solve", "-i", instance, "-o", plan, "-t", "5"], capture_output=True,
                                text=True, timeout=120)
        self.assertEqual(solved.returncode, 0, solved.stderr)
        dashboard = self.fleet.start("dashboard", [f"{BIN}/ctsfleet-dashboard", "--plan", plan, "--instance", instance,
                                                   "--port", "0"])
        log = self.fleet.log("dashboard")
        wait_for(lambda: "dashboard: http://" in read(log), 60, "the dashboard's address")
        port = int(re.search(r"dashboard: http://127\.0\.0\.1:(\d+)/", read(log)).group(1))

        def connect(source):
            s = socket.socket()
            self.addCleanup(s.close)
            s.bind((source, 0))
            s.settimeout(30)
            s.connect(("127.0.0.1", port))
            return s

        streams = [connect("127.0.0.2") for _ in range(100)]
        for s in streams:
            s.sendall(b"GET /api/stream HTTP/1.1\r\nHost: x\r\n\r\n")
        slow = [connect("127.0.0.3") for _ in range(100)]
        stop_dripping = threading.Event()
        self.addCleanup(stop_dripping.set)

        def drip():
            while not stop_dripping.wait(0.5):
                for s in slow:
                    try:
                        s.sendall(b"X")
                    except OSError:
                        pass
        for s in slow:
            s.sendall(b"GET / HTTP/1.1\r\nX-Slow: ")
        threading.Thread(target=drip, daemon=True).start()

        times = []
        for _ in range(5):
            for path in ["", "api/frame", "api/plan"]:
                started = time.monotonic()
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/{path}", timeout=30) as reply:
                    self.assertEqual(reply.status, 200)
                    reply.read()
                times.append(time.monotonic() - started)
        print(f"page answers under load: median {statistics.median(times) * 1000:.0f} ms, "
              f"slowest {max(times) * 1000:.0f} ms of {len(times)}")
        self.assertLess(statistics.median(times), 1.0, times)

        # Streams over the per-address cap were refused at once: 503 (or closed, when the server
        # refused the connection before the request reached it).
        def answer_start(s, wait=10):
            """The first bytes the server sent (b"" when it closed), None when it sent nothing in time."""
            s.settimeout(wait)
            try:
                return s.recv(64)
            except socket.timeout:
                return None
            except OSError:
                return b""
        answers = [answer_start(s) for s in streams]
        served = sum(1 for a in answers if a is not None and a.startswith(b"HTTP/1.1 200"))
        refused = sum(1 for a in answers if a is not None and (a == b"" or a.startswith(b"HTTP/1.1 503")))
        self.assertLessEqual(served, 8, answers)
        self.assertEqual(served + refused, 100, answers)
        # A socket still sending its request after the deadline (10 s) is cut off.
        wait_for(lambda: all(answer_start(s, 0.1) == b"" for s in slow), 60, "the slow sockets cut")

        # A body past the limit is refused without being read; a body that is not UTF-8 gets 400.
        big = connect("127.0.0.1")
        big.sendall(b"POST /api/replay HTTP/1.1\r\nHost: x\r\nContent-Length: 300000000\r\n\r\n")
        self.assertTrue(answer_start(big).startswith(b"HTTP/1.1 413"))
        for body in [b'{"speed": "\xff\xfe"}', b"\xc3\x28"]:
            request = urllib.request.Request(f"http://127.0.0.1:{port}/api/replay", data=body, method="POST")
            with self.assertRaises(urllib.error.HTTPError) as refused_body:
                urllib.request.urlopen(request, timeout=30)
            self.assertEqual(refused_body.exception.code, 400)
            json.loads(refused_body.exception.read())  # a JSON reason, whatever bytes came in

        # Ctrl-C ends it promptly, slow sockets and all.
        stop_dripping.set()
        started = time.monotonic()
        dashboard.send_signal(signal.SIGINT)
        self.assertEqual(self.fleet.wait_exit("dashboard", 30), 130)
        print(f"stopped {time.monotonic() - started:.2f} s after SIGINT")

    def test_dashboard_in_a_real_browser(self):
        browser = chromium_driver(self)
        if browser is None:
            return
        self.start_fleet(lifelong=True)
        dashboard = self.fleet.start("dashboard", [f"{BIN}/ctsfleet-dashboard", "--domain", str(self.fleet.domain),
                                                   "--dds-config-dir", DDS_DIR, "--port", "0"])
        log = self.fleet.log("dashboard")
        wait_for(lambda: "dashboard: http://" in read(log), 60, "the dashboard's address")
        url = re.search(r"dashboard: (http://\S+)", read(log)).group(1)
        browser.get(url)
        drawn = lambda: browser.execute_script("return window.ctsfleet.drawn()")
        wait_for(lambda: len(drawn()) == 8, 60, "eight robots drawn")
        # The robots move on the page: over 2 s at least one is drawn a cell away from where it was.
        before = drawn()
        time.sleep(2)
        after = drawn()
        moved = [r for r in before if abs(before[r]["x"] - after[r]["x"]) + abs(before[r]["y"] - after[r]["y"]) >= 1]
        self.assertTrue(moved, f"no robot moved on the page in 2 s: {before} -> {after}")
        # What the page has is what robots report on the wire: a robot state the page holds (same
        # sequence number) has the pose the dashboard heard (/api/frame), and each robot is drawn
        # where its state puts it, give or take the glide (100 ms behind a robot doing 20 cells/s).
        matched = []

        def page_matches_the_wire():
            page_frame = browser.execute_script("return window.ctsfleet.view.frame")
            page_drawn = drawn()
            wire = {r["id"]: r for r in json.load(urllib.request.urlopen(url + "api/frame", timeout=10))["robots"]}
            for robot in page_frame["robots"]:
                at = page_drawn[robot["id"]]
                self.assertLessEqual(abs(at["x"] - robot["pose_x"]) + abs(at["y"] - robot["pose_y"]), 4.0,
                                     f"{robot['id']} drawn at {at}, its state at {robot['pose_x']},{robot['pose_y']}")
                heard = wire[robot["id"]]
                if heard["seq"] == robot["seq"]:
                    self.assertEqual((heard["pose_x"], heard["pose_y"], heard["x"], heard["y"]),
                                     (robot["pose_x"], robot["pose_y"], robot["x"], robot["y"]), robot["id"])
                    matched.append(robot["id"])
            return len(matched) >= 8

        wait_for(page_matches_the_wire, 60, "robot states on the page that match the wire's")
        # Every task done, the robots park on their goals: drawn exactly there.
        wait_for(lambda: "every task done: the robots park" in read(self.fleet.log("coordinator")), 240,
                 "the mission's tasks done")
        goals = {f"robot{j}": tuple(a["goal"]) for j, a in enumerate(mission()["agents"])}
        wait_for(lambda: all(abs(drawn()[r]["x"] - g[0]) < 0.05 and abs(drawn()[r]["y"] - g[1]) < 0.05
                             for r, g in goals.items()), 30, f"robots drawn on their goals {goals}")
        # A click on a free cell gives the fleet a task there, and a robot reaches it.
        x, y = free_cells_away_from_the_mission()[40]
        canvas = browser.find_element("id", "map")
        offset = browser.execute_script(f"return window.ctsfleet.cellOffset({x}, {y})")
        from selenium.webdriver.common.action_chains import ActionChains
        ActionChains(browser).move_to_element_with_offset(
            canvas, offset[0] - canvas.size["width"] / 2, offset[1] - canvas.size["height"] / 2).click().perform()
        result = lambda: browser.find_element("id", "task-result").text
        wait_for(lambda: "given to robot" in result() or "refused" in result(), 60, "the coordinator's answer")
        self.assertIn(f"task 16 at ({x},{y}) given to robot", result())
        robot = re.search(r"given to robot (\w+)", result()).group(1)
        frame_now = lambda: browser.execute_script("return window.ctsfleet.view.frame")
        wait_for(lambda: len(frame_now()["tasks"]) == 17 and frame_now()["tasks"][16] == "done", 120,
                 "the clicked task done on the page")
        events = [e["kind"] for e in frame_now()["events"]]
        self.assertIn("task_added", events)
        # The schedule panel: every task done, none waits; the fleet's typical move is measured.
        schedule = lambda: browser.find_element("id", "schedule").text
        wait_for(lambda: "tasks waiting in the pool 0" in schedule() and re.search(r"typical move \d+ ms", schedule()),
                 30, "the schedule panel with a typical move")
        self.assertIn("tasks in robots' plans 0", schedule())
        # A robot that dies turns "lost" on the page.
        victim = "robot5" if robot != "robot5" else "robot6"
        self.fleet.processes[victim].send_signal(signal.SIGKILL)
        wait_for(lambda: drawn().get(victim, {}).get("status") == "lost", 30, f"{victim} shown lost")
        screenshot = os.path.join(os.getcwd(), "dashboard-browser-test.png")
        browser.save_screenshot(screenshot)
        print(f"screenshot: {screenshot}; page latency p50/p99 "
              f"{percentile(browser.execute_script('return window.ctsfleet.latencies()'), 0.5)}/"
              f"{percentile(browser.execute_script('return window.ctsfleet.latencies()'), 0.99)} ms")
        self.assertIsNone(dashboard.poll())
        self.assert_safe()

    def test_a_task_added_survives_a_failover(self):
        self.fleet.monitor()
        self.fleet.agents()
        config = self.config(lifelong=False)
        self.fleet.start("active", [f"{BIN}/ctsfleet-coordinator", "--config", config, "--domain",
                                    str(self.fleet.domain)])
        wait_for(lambda: "plan epoch" in read(self.fleet.log("active")), 120, "the first plan")
        self.fleet.start("standby", [f"{BIN}/ctsfleet-coordinator", "--config", config, "--domain",
                                     str(self.fleet.domain), "--standby", "--json"])
        wait_for(lambda: "standby: follows coordinator" in read(self.fleet.log("standby")), 60, "the standby following")
        x, y = free_cells_away_from_the_mission()[100]
        code, text = self.task("add", "--at", f"{x},{y}", "--robot", "robot4")
        self.assertEqual(code, 0, text)
        self.assertIn("task 16", text)
        wait_for(lambda: "standby: mirrors task 16" in read(self.fleet.log("standby")), 60, "the standby mirroring it")
        self.fleet.processes["active"].send_signal(signal.SIGKILL)
        code = self.fleet.wait_exit("standby", 240)
        text = read(self.fleet.log("standby"))
        self.assertEqual(code, 0, text[-3000:])
        summary = summary_of(text)
        self.assertTrue(summary["took_over"], summary)
        self.assertTrue(summary["completed"], summary)
        self.assertEqual(summary["tasks_total"], 17)
        self.assertEqual(summary["tasks_done"], 17)
        self.assert_safe()

    def test_fastdds_fleet_takes_tasks_and_its_dashboard_sees_them(self):
        self.start_fleet(lifelong=True, dds="fastdds")
        self.fleet.start("dashboard", [f"{BIN}/ctsfleet-dashboard", "--dds", "fastdds", "--domain",
                                       str(self.fleet.domain), "--dds-config-dir", DDS_DIR, "--port", "0",
                                       "--record", os.path.join(self.fleet.dir, "history.jsonl")])
        log = self.fleet.log("dashboard")
        wait_for(lambda: "dashboard: http://" in read(log), 60, "the dashboard's address")
        url = re.search(r"dashboard: (http://\S+)", read(log)).group(1)
        x, y = free_cells_away_from_the_mission()[7]
        code, text = self.task("add", "--at", f"{x},{y}", "--any", dds="fastdds")
        self.assertEqual(code, 0, text)
        frame = lambda: json.load(urllib.request.urlopen(url + "api/frame", timeout=10))
        wait_for(lambda: len(frame()["tasks"]) == 17 and all(t == "done" for t in frame()["tasks"]), 240,
                 "every task, the added one too, done as the dashboard sees it")
        plan = json.load(urllib.request.urlopen(url + "api/plan", timeout=10))
        mission_seen = json.load(urllib.request.urlopen(url + "api/mission", timeout=10))
        self.assertEqual(len(plan["robots"]), 8)
        self.assertEqual(mission_seen["tasks"][16]["x"], x)
        kinds = {e["kind"] for e in frame()["events"]}
        self.assertTrue({"task_added", "task_done", "replan"} <= kinds, kinds)
        # What it recorded replays: the same robots, the same tasks done.
        self.fleet.processes["dashboard"].send_signal(signal.SIGINT)
        self.fleet.wait_exit("dashboard", 30)
        replay = self.fleet.start("replay", [f"{BIN}/ctsfleet-dashboard", "--replay",
                                             os.path.join(self.fleet.dir, "history.jsonl"), "--speed", "1000",
                                             "--port", "0"])
        wait_for(lambda: "dashboard: http://" in read(self.fleet.log("replay")), 60, "the replay's address")
        replay_url = re.search(r"dashboard: (http://\S+)", read(self.fleet.log("replay"))).group(1)
        replayed = lambda: json.load(urllib.request.urlopen(replay_url + "api/frame", timeout=10))
        wait_for(lambda: len(replayed()["tasks"]) == 17 and all(t == "done" for t in replayed()["tasks"]), 60,
                 "the replay reaching the end")
        self.assertEqual(len(replayed()["robots"]), 8)
        self.assertTrue(replayed()["replay"])
        # ... and draws as a picture.
        picture = os.path.join(self.fleet.dir, "run.svg")
        drawn = subprocess.run([f"{BIN}/ctsfleet-dashboard", "--replay", os.path.join(self.fleet.dir, "history.jsonl"),
                                "--svg", picture], capture_output=True, text=True, timeout=60)
        self.assertEqual(drawn.returncode, 0, drawn.stderr)
        self.assertIn("picture of 8 robots", drawn.stdout)
        with open(picture) as f:
            self.assertIn("<svg", f.read(200))
        self.fleet.processes["coordinator"].send_signal(signal.SIGINT)
        self.fleet.wait_exit("coordinator", 60)
        self.assert_safe()


def percentile(values, p):
    values = sorted(values)
    return values[min(len(values) - 1, int(len(values) * p))] if values else None


def chromium_driver(test):
    """Debian's chromium, headless, through chromedriver, quit when `test` ends; None (after a loud
    message) when it cannot be had on this machine. Its temporary files (chromium leaves a folder
    with its singleton socket behind in TMPDIR) go into a folder of their own, removed after."""
    missing = [path for path in ("/usr/bin/chromium", "/usr/bin/chromedriver") if not os.path.exists(path)]
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        missing.append("python3-selenium")
    if missing:
        print("\n*** SKIPPED: the browser test needs " + ", ".join(missing) +
              " (scripts/setup installs chromium, chromium-driver, python3-selenium) ***\n", file=sys.stderr)
        return None
    options = webdriver.ChromeOptions()
    options.binary_location = "/usr/bin/chromium"
    for argument in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                     "--window-size=1400,1000"):
        options.add_argument(argument)
    scratch = tempfile.mkdtemp(prefix="ctsfleet-chromium-")
    test.addCleanup(shutil.rmtree, scratch, ignore_errors=True)
    service = Service("/usr/bin/chromedriver", env=dict(os.environ, TMPDIR=scratch))
    browser = webdriver.Chrome(service=service, options=options)
    test.addCleanup(browser.quit)  # cleanups run last first: the browser quits, then its folder goes
    return browser


if __name__ == "__main__":
    unittest.main()
