#!/usr/bin/env python3
"""Command-line catalogue: every shipped program, every option its --help lists, run with the bad
values that fit the option's type, under a timeout. For each case:

  - the program ends by itself, or ends within 2 s of SIGTERM (no hang);
  - it is never killed by a signal (no abort, no segfault) and never exits 128+;
  - an exit 2 comes with a line "PROGRAM: error: ..." on stderr naming the option or file;
  - a value no option can mean (nan, inf, 1e300, a word for a number, a missing value, an integer
    beyond 64 bits) is refused with exit 2.

Then the named cases: the failures users met before (each must exit 2 with a message, or, for the
monitor on a silent domain, exit non-zero). Prints a summary line with the number of cases.

Usage: cli_catalogue.py BIN_DIR SOURCE_DIR WORK_DIR
"""
import concurrent.futures
import os
import re
import shutil
import signal
import subprocess
import sys
import time

BIN, ROOT, WORK = (os.path.abspath(arg) for arg in sys.argv[1:4])
os.makedirs(WORK, exist_ok=True)
DATA = os.path.join(ROOT, "tests/data")
INSTANCE = os.path.join(DATA, "instances/random-32-32-20-N10-M30-00.yaml")
MAP = os.path.join(DATA, "maps/random-32-32-20.map")
MAT = os.path.join(ROOT, "config/mats/toio-simple.yaml")
EMPTY_FILE = os.path.join(WORK, "empty.txt")
open(EMPTY_FILE, "w").close()
FIVE_CELL_MAP = os.path.join(WORK, "five-cells.map")
with open(FIVE_CELL_MAP, "w") as f:
    f.write("type octile\nheight 1\nwidth 5\nmap\n.....\n")
# A history whose mission's map rows are shorter than its width (it crashed --svg once).
SHORT_ROWS_HISTORY = os.path.join(WORK, "short-rows.jsonl")
with open(SHORT_ROWS_HISTORY, "w") as f:
    f.write('{"format": "ctsfleet-history-1"}\n')
    f.write('{"t": 1, "type": "mission", "msg": {"coordinator": 1, "mission_id": "m", "width": 40, "height": 3, '
            '"map_rows": "..\\n..\\n..", "goals": [{"x": 0, "y": 0}], "tasks": [], "lifelong": false}}\n')
    f.write('{"t": 2, "type": "state", "msg": {"robot_id": "a", "cell_x": 0, "cell_y": 0, "pose_x": 0, "pose_y": 0, '
            '"pose_theta": 0, "plan_epoch": 1, "action_index": 0, "status": "idle", "battery_percent": -1, '
            '"seq_number": 1, "stamp_ms": 1, "incarnation": 1, "coordinator": 1}}\n')
MARKUP_ID = '<img src=x onerror=alert(1)>'
# Special files given as input: each must be refused at once (a FIFO blocked its reader for ever).
FIFO = os.path.join(WORK, "input-fifo.yaml")  # named as an instance: past the extension check
if not os.path.exists(FIFO):
    os.mkfifo(FIFO)
ZERO_MAP_INSTANCE = os.path.join(WORK, "zero-map.yaml")
with open(INSTANCE) as f, open(ZERO_MAP_INSTANCE, "w") as out:
    out.write(re.sub(r"^map:.*$", "map: /dev/zero", f.read(), flags=re.M))
HUGE_MAP = os.path.join(WORK, "huge.map")
with open(HUGE_MAP, "w") as f:
    f.write("type octile\nheight 5000\nwidth 5000\nmap\n")
# A plan of INSTANCE, and two that do not fit it: another instance's starts (the agents' columns
# rotated) and a cell off the map. The dashboard drew both once.
PLAN = os.path.join(WORK, "plan.txt")
subprocess.run([os.path.join(BIN, "ctsfleet-solve"), "-i", INSTANCE, "--solver", "cts-pibt", "-o", PLAN, "-t", "10"],
               check=True, capture_output=True)
with open(PLAN) as f:
    head, steps = f.read().split("solution=\n", 1)
ROTATED_PLAN = os.path.join(WORK, "rotated-plan.txt")
with open(ROTATED_PLAN, "w") as f:
    rotate = lambda line: re.sub(r"^(\d+:)(\(\d+,\d+\),)(.*)$", r"\1\3\2", line)
    f.write(head + "solution=\n" + "\n".join(rotate(line) for line in steps.splitlines()) + "\n")
OFF_MAP_PLAN = os.path.join(WORK, "off-map-plan.txt")
with open(OFF_MAP_PLAN, "w") as f:
    f.write(head + "solution=\n" + re.sub(r"^(5:)\(\d+,\d+\)", r"\1(999,999)", steps, flags=re.M))
# An open 2000 x 2000 map with a few agents: reading it takes a while, and Ctrl-C must still end
# the solve at once (the reading did not look at the stop flag before).
BIG_MAP_INSTANCE = os.path.join(WORK, "big-open.yaml")
with open(os.path.join(WORK, "big-open.map"), "w") as f:
    f.write("type octile\nheight 2000\nwidth 2000\nmap\n" + ("." * 2000 + "\n") * 2000)
with open(BIG_MAP_INSTANCE, "w") as f:
    f.write("map: big-open.map\nagents:\n" +
            "".join(f"  - {{start: [{j}, 0], goal: [{1999 - j}, 1999]}}\n" for j in range(5)) +
            "tasks:\n" + "".join(f"  - {{at: [{100 * j + 7}, {1500 - 50 * j}], agents: [{j}]}}\n" for j in range(5)))
DOMAIN_BASE = 150  # catalogue runs use DDS domains 150..199, away from the other tests

# A valid command line per program: it either finishes quickly or runs until SIGTERM.
def base_args(program, domain):
    out = lambda name: os.path.join(WORK, f"{program}-{domain}-{name}")
    return {
        "ctsfleet-solve": ["-i", INSTANCE, "-t", "0.3", "-o", out("solution.txt")],
        "ctsfleet-gen": ["--map", MAP, "-N", "2", "-M", "2", "-o", out("gen.yaml")],
        "ctsfleet-bench": [INSTANCE, "-t", "0.2", "-j", "1", "--csv", out("bench.csv")],
        "ctsfleet-seqbench": ["--map", MAP, "-k", "3"],
        "ctsfleet-coordinator": ["-c", os.path.join(ROOT, "config/fleet.yaml"), "--domain", str(domain)],
        "ctsfleet-sim": ["--robots", "2", "--domain", str(domain), "--log-dir", out("sim-logs")],
        "ctsfleet-monitor": ["--duration", "0.3", "--domain", str(domain)],
        "ctsfleet-fleetbench": ["-n", "2", "--domain", str(domain), "--kill-after", "0", "--step", "0.05"],
        "ctsfleet-agent": ["--id", f"catalogue{domain}", "--domain", str(domain)],
        "ctsfleet-task": ["list", "--domain", str(domain), "--timeout", "0.5"],
        "ctsfleet-dashboard": ["--domain", str(domain), "--port", "0", "--duration", "0.5"],
        "ctsfleet-toio-emulator": ["--bus", "unix:path=" + out("no-bus"), "--cube", "a@200,200"],
        "ctsfleet-toio-calibrate": ["fit", "--mat", MAT, "-o", out("mat.yaml"), "--point", "0,0=125,175",
                                    "--point", "1,0=175,175", "--point", "0,1=125,225"],
    }[program]

PROGRAMS = ["ctsfleet-solve", "ctsfleet-gen", "ctsfleet-bench", "ctsfleet-seqbench", "ctsfleet-coordinator",
            "ctsfleet-sim", "ctsfleet-monitor", "ctsfleet-fleetbench", "ctsfleet-agent", "ctsfleet-toio-emulator",
            "ctsfleet-toio-calibrate", "ctsfleet-task", "ctsfleet-dashboard"]
# Programs that run until stopped when their input is good: give them this long, then SIGTERM.
# The dashboard and the monitor run until stopped with --duration 0, and toio-calibrate waits for a
# cube it is named (none answers here): 4 s shows they run, then SIGTERM must end them (20 s each
# took two minutes of the suite and caught nothing more).
LONG_RUNNING = {"ctsfleet-coordinator": 2.5, "ctsfleet-sim": 3.0, "ctsfleet-fleetbench": 3.0, "ctsfleet-agent": 2.0,
                "ctsfleet-dashboard": 4.0, "ctsfleet-monitor": 4.0, "ctsfleet-toio-calibrate": 4.0}

NUMBER_NONSENSE = ["nan", "inf", "-inf", "1e300", "abc", "99999999999999999999"]
NUMBER_EDGES = ["-1", "0", "-5", "1e10", "2147483648"]
TEXT_VALUES = ["", "no-such-word", "/proc/nonexistent/folder/file", WORK, EMPTY_FILE, "/proc/version",
               "/proc/no/such/file", "a,b;c \"d\""]

OPTION_LINE = re.compile(r"^\s+((?:-\w,)?--[\w-]+)(?:\s+(INT|UINT|FLOAT|TEXT|ENUM)\b(\S*))?")


def options_of(program, subcommand=None):
    """(names, type) for every option of `program`'s --help, but --help and --version."""
    args = [os.path.join(BIN, program)] + ([subcommand] if subcommand else []) + ["--help"]
    text = subprocess.run(args, capture_output=True, text=True, timeout=20).stdout
    found = []
    for line in text.splitlines():
        m = OPTION_LINE.match(line)
        if not m or m.group(1).endswith(("--help", "--version")):
            continue
        long_name = m.group(1).split(",")[-1]
        found.append((long_name, m.group(2)))  # type None: a flag
    return found


class Case:
    def __init__(self, program, args, name, must_refuse=False, expect=None, timeout=None, stderr_contains=None):
        self.program, self.args, self.name = program, args, name
        self.stderr_contains = stderr_contains  # a text the program must say on stderr
        self.must_refuse = must_refuse  # exit 2 required
        self.expect = expect            # a predicate on the exit code, for named cases
        self.timeout = timeout or LONG_RUNNING.get(program, 20.0)
        self.code = None                # the exit code seen


def run(case):
    """Returns a problem description, or None when the case holds."""
    started = time.monotonic()
    proc = subprocess.Popen([os.path.join(BIN, case.program)] + case.args, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True, cwd=WORK,
                            env=dict(os.environ, TMPDIR=WORK))  # what the programs leave stays in WORK
    terminated = False
    try:
        out, err = proc.communicate(timeout=case.timeout)
    except subprocess.TimeoutExpired:
        terminated = True
        proc.send_signal(signal.SIGTERM)
        try:
            out, err = proc.communicate(timeout=2.0 + (1.0 if case.program in LONG_RUNNING else 0))
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
            return f"hang: still running {2 + (1 if case.program in LONG_RUNNING else 0)} s after SIGTERM"
    finally:
        try:
            os.killpg(proc.pid, signal.SIGKILL)  # children left behind, if any
        except ProcessLookupError:
            pass
    code = proc.returncode
    case.code = code
    tail = (err.strip().splitlines() or [""])[-1][:200]
    if code < 0 and case.args[-2:-1] == ["--crash-at"] and -code == signal.SIGABRT:
        return None  # the agent's fault injection: it aborts on purpose
    if code < 0:
        return f"killed by signal {-code}: {tail}"
    if code >= 128 and not (terminated and code == 130):
        return f"exit {code}: {tail}"
    errors = [line for line in err.splitlines() if line.startswith(case.program + ": error: ")]
    if code == 2 and len(errors) != 1:
        return f"exit 2 without exactly one '{case.program}: error:' line: {err.strip()[:300]!r}"
    if case.must_refuse and code != 2:
        return f"accepted (exit {code}{', after SIGTERM' if terminated else ''}), expected exit 2; stderr: {tail}"
    if case.expect and not case.expect(code):
        return f"exit {code} not as expected; stderr: {tail}"
    if case.stderr_contains and case.stderr_contains not in err:
        return f"stderr does not say '{case.stderr_contains}': {err.strip()[-300:]!r}"
    del started, out
    return None


def catalogue_cases():
    cases = []
    index = 0
    for program in PROGRAMS:
        sub = "fit" if program == "ctsfleet-toio-calibrate" else None
        for option, kind in options_of(program, sub):
            if kind is None:  # a flag: given a value, or repeated
                continue
            values = []
            if kind in ("INT", "UINT", "FLOAT"):
                values = [(v, True) for v in NUMBER_NONSENSE] + [(v, False) for v in NUMBER_EDGES]
            else:
                values = [(v, False) for v in TEXT_VALUES]
            for value, must_refuse in values:
                domain = DOMAIN_BASE + index % 50
                index += 1
                args = replace_option(base_args(program, domain), option, value)
                cases.append(Case(program, args, f"{program} {option} {value!r}", must_refuse))
            # the option given with no value at all
            domain = DOMAIN_BASE + index % 50
            index += 1
            args = [a for a in replace_option(base_args(program, domain), option, None)] + [option]
            cases.append(Case(program, args, f"{program} {option} (no value)", True))
        cases.append(Case(program, ["--no-such-option"], f"{program} --no-such-option", True))
    return cases


def replace_option(args, option, value):
    """`args` with `option` set to `value` (dropped when None); the value replaces an existing one."""
    out, skip = [], False
    aliases = {option}
    for i, a in enumerate(args):
        if skip:
            skip = False
            continue
        if a in aliases or (option == "--robots" and a == "-n") or (option == "--output" and a == "-o") \
                or (option == "--out" and a == "-o") or (option == "--time" and a == "-t") \
                or (option == "--config" and a == "-c") or (option == "--instance" and a == "-i") \
                or (option == "--agents" and a == "-N") or (option == "--tasks" and a == "-M") \
                or (option == "--threads" and a == "-j") or (option == "--sequences" and a == "-k"):
            skip = True
            continue
        out.append(a)
    if value is not None:
        out += [option, value]
    return out


def fleet_config(name, **overrides):
    """config/fleet.yaml with some `section.key` values replaced, written into WORK."""
    text = open(os.path.join(ROOT, "config/fleet.yaml")).read()
    text = text.replace("mission: default/", f"mission: {ROOT}/config/default/")
    text = text.replace("config_dir: dds", f"config_dir: {ROOT}/config/dds")
    for key, value in overrides.items():
        text, count = re.subn(rf"^(\s*{key}:)[^#\n]*", rf"\g<1> {value}  ", text, flags=re.M)
        assert count == 1, key
    path = os.path.join(WORK, name)
    with open(path, "w") as f:
        f.write(text)
    return path


def second_timing_config():
    """config/fleet.yaml with a second `timing:` section after the first (the first won silently)."""
    path = fleet_config("second-timing.yaml")
    with open(path, "a") as f:
        f.write("timing:\n  step_s: -1\n")
    return path


def named_cases():
    refuse = lambda program, args, name: Case(program, args, name, must_refuse=True)
    return [
        refuse("ctsfleet-sim", ["--robots", "5000"], "sim: more robots than free cells"),
        refuse("ctsfleet-sim", ["--backend", "toio-emulated", "--robots", "70"], "sim: 70 toio cubes on an 8x8 mat"),
        refuse("ctsfleet-seqbench", ["--map", FIVE_CELL_MAP], "seqbench on a 5-cell map"),
        refuse("ctsfleet-seqbench", ["--map", "/proc/nonexistent.map"], "seqbench: missing map"),
        refuse("ctsfleet-fleetbench", ["--map", "/proc/nonexistent.map"], "fleetbench: missing map"),
        refuse("ctsfleet-fleetbench", ["-n", "0"], "fleetbench -n 0"),
        refuse("ctsfleet-monitor", ["--domain", "500"], "monitor --domain 500"),
        refuse("ctsfleet-monitor", ["--dds-config-dir", "/proc/nonexistent"], "monitor: missing DDS config folder"),
        Case("ctsfleet-monitor", ["--domain", "231", "--duration", "0.5"], "monitor hears nothing: non-zero",
             expect=lambda code: code not in (0, 2), stderr_contains="heard no robot on cyclone domain 231"),
        Case("ctsfleet-coordinator", ["-c", os.path.join(ROOT, "config/fleet.yaml"), "--domain", "230"],
             "coordinator hearing no robot says what an agent needs", timeout=8, expect=lambda code: code == 130,
             stderr_contains="no robot heard after 5 s on cyclone domain 230"),
        Case("ctsfleet-agent", ["--id", "lonely", "--domain", "229", "--iface", "lo"],
             "agent hearing no coordinator says where it listens", timeout=13, expect=lambda code: code == 0,
             stderr_contains="lonely: no coordinator heard after 10 s on cyclone domain 229 (interface lo, multicast "
                             "discovery): a coordinator must run with --dds cyclone --domain 229 --iface"),
        refuse("ctsfleet-bench", ["-j", "100000", INSTANCE], "bench -j 100000"),
        refuse("ctsfleet-bench", ["--experiment", "dense", "--out-dir", "/proc/no/such"], "bench: unwritable out-dir"),
        refuse("ctsfleet-bench", ["--experiment", "dense", "--out-dir", "/proc/1", "--sample", "1", "-t", "0.1"],
               "bench: existing folder nothing can be written into"),
        refuse("ctsfleet-bench", ["--experiment", "dense", "--benchmarks", "/proc/nonexistent"], "bench: missing suites"),
        refuse("ctsfleet-toio-calibrate", ["fit", "--mat", MAT, "-o", "/proc/no/such.yaml", "--point", "0,0=1,1"],
               "calibrate fit -o unwritable"),
        refuse("ctsfleet-solve", ["-i", INSTANCE, "-t", "inf"], "solve -t inf"),
        refuse("ctsfleet-solve", ["-i", INSTANCE, "-t", "1e10"], "solve -t 1e10"),
        refuse("ctsfleet-solve", ["-i", INSTANCE, "-t", "-5"], "solve -t -5"),
        refuse("ctsfleet-solve", ["-i", INSTANCE, "-t", "nan"], "solve -t nan"),
        refuse("ctsfleet-solve", ["-i", INSTANCE, "-t", "0"], "solve -t 0"),
        refuse("ctsfleet-solve", ["-i", os.path.join(ROOT, "benchmarks/mapf/den520d-N500-0.scen"), "-N", "-5"],
               "solve -N -5"),
        refuse("ctsfleet-solve", ["-i", os.path.join(ROOT, "benchmarks/mapf/den520d-N500-0.scen"), "-N", "501",
                                  "--map", os.path.join(ROOT, "benchmarks/maps")], "solve -N beyond the rows"),
        refuse("ctsfleet-solve", ["-i", os.path.join(ROOT, "benchmarks/mapf/den520d-N500-0.scen"), "-N", "5"],
               "solve .scen without its map"),
        refuse("ctsfleet-solve", ["-i", INSTANCE, "--map", MAP], "solve --map with a .yaml"),
        refuse("ctsfleet-gen", ["--map", MAP, "-N", "99999999999", "-M", "1", "-o", "x.yaml"], "gen -N 99999999999"),
        refuse("ctsfleet-gen", ["--map", MAP, "-N", "-5", "-M", "1", "-o", "x.yaml"], "gen -N -5"),
        refuse("ctsfleet-coordinator", ["-c", fleet_config("time-limit.yaml", time_limit_s="-1")],
               "config planner.time_limit_s: -1"),
        refuse("ctsfleet-coordinator", ["-c", fleet_config("domain.yaml", domain_id="500")], "config dds.domain_id: 500"),
        refuse("ctsfleet-coordinator", ["-c", fleet_config("lease.yaml", lease_s="-2")], "config dds.lease_s: -2"),
        refuse("ctsfleet-coordinator", ["-c", fleet_config("step.yaml", step_s=".nan")], "config timing.step_s: .nan"),
        refuse("ctsfleet-coordinator", ["-c", fleet_config("command-timeout.yaml", command_timeout_s="1")],
               "config timing.command_timeout_s: 1, below twice the resend interval"),
        refuse("ctsfleet-coordinator", ["-c", fleet_config("command-timeout-word.yaml", command_timeout_s="soon")],
               "config timing.command_timeout_s: soon"),
        refuse("ctsfleet-coordinator", ["-c", fleet_config("quorum.yaml", quorum="99999999999")],
               "config robots.quorum: 99999999999"),
        refuse("ctsfleet-coordinator", ["-c", fleet_config("twice.yaml", expected="[robot0, robot1, robot0]")],
               "config robots.expected with an id twice"),
        refuse("ctsfleet-coordinator", ["-c", EMPTY_FILE], "coordinator: empty config"),
        refuse("ctsfleet-coordinator", ["-c", WORK], "coordinator: a folder for the config"),
        refuse("ctsfleet-agent", ["--id", "r", "--lease", "-1"], "agent --lease -1"),
        refuse("ctsfleet-agent", ["--id", "r", "--domain", "-5"], "agent --domain -5"),
        refuse("ctsfleet-agent", ["--id", "r", "--step", "-1"], "agent --step -1"),
        refuse("ctsfleet-agent", ["--id", "r", "--start", "3"], "agent --start 3"),
        refuse("ctsfleet-agent", ["--id", "x" * 33], "agent: a 33-character id"),
        Case("ctsfleet-agent", ["--id", MARKUP_ID], "agent: markup as its id", must_refuse=True,
             stderr_contains="is not a robot id"),
        refuse("ctsfleet-coordinator", ["-c", fleet_config("no-robots.yaml", expected="[]")],
               "config robots.expected: [] (crashed the coordinator once)"),
        refuse("ctsfleet-coordinator", ["-c", fleet_config("markup-id.yaml", expected=f"['{MARKUP_ID}']")],
               "config robots.expected with markup as an id"),
        refuse("ctsfleet-coordinator", ["-c", fleet_config("seed.yaml", seed="-1")], "config planner.seed: -1"),
        Case("ctsfleet-coordinator", ["-c", second_timing_config()], "config with a second timing section",
             must_refuse=True, stderr_contains="key 'timing' given twice"),
        refuse("ctsfleet-coordinator", ["-c", fleet_config("seed-big.yaml", seed="4294967296")],
               "config planner.seed: 2^32"),
        refuse("ctsfleet-task", ["add", "--at", "1,1", "--robot", MARKUP_ID, "--domain", "228"],
               "task --robot with markup"),
        refuse("ctsfleet-solve", ["-i", INSTANCE, "--iterations", "-1"], "solve --iterations -1"),
        Case("ctsfleet-dashboard", ["--domain", "226", "--port", "0"], "dashboard stopped by SIGTERM: 130", timeout=3,
             expect=lambda code: code == 130),
        Case("ctsfleet-solve", ["-i", INSTANCE, "--solver", "cts-pll-v3", "-t", "60", "-o",
                                os.path.join(WORK, "stopped.txt")], "solve with a plan stopped by SIGTERM: 130",
             timeout=3, expect=lambda code: code == 130),
        Case("ctsfleet-solve", ["-i", INSTANCE, "--actions", "rotate", "--solver", "cts-pll-v3", "-t", "60", "-o",
                                os.path.join(WORK, "stopped-turning.txt")],
             "solve --actions rotate stopped by SIGTERM: 130", timeout=3, expect=lambda code: code == 130),
        # An anytime solver: each instance takes its 5 s (cts-pibt's first plans took the whole suite
        # under 3 s on an idle machine, and the bench ended before the signal).
        Case("ctsfleet-bench", [os.path.join(ROOT, "benchmarks/dense"), "--solver", "cts-pibt-anytime", "-t", "5",
                                "--csv", os.path.join(WORK, "b.csv")],
             "bench over a suite stopped by SIGTERM: 130, the instances left not run", timeout=3,
             expect=lambda code: code == 130),
        Case("ctsfleet-solve", ["-i", os.path.join(ROOT, "benchmarks/mapf-scale/warehouse-20-40-10-2-2-N10000.yaml"),
                                "--solver", "lacam", "-t", "60", "-o", os.path.join(WORK, "stopped-early.txt")],
             "solve stopped by SIGTERM before a plan: 130", timeout=1, expect=lambda code: code == 130),
        Case("ctsfleet-solve", ["-i", BIG_MAP_INSTANCE, "-t", "60", "-o", os.path.join(WORK, "big.txt")],
             "solve on a 2000x2000 map stopped by SIGTERM while reading it: 130", timeout=0.3,
             expect=lambda code: code == 130),
        Case("ctsfleet-solve", ["-i", FIFO], "solve -i a FIFO", must_refuse=True, timeout=5, stderr_contains="FIFO"),
        Case("ctsfleet-solve", ["-i", ZERO_MAP_INSTANCE], "solve: an instance whose map is /dev/zero",
             must_refuse=True, timeout=5, stderr_contains="a device"),
        Case("ctsfleet-solve", ["-i", os.path.join(ROOT, "benchmarks/mapf/maze-32-32-2-N50-0.scen"), "--map", FIFO],
             "solve --map a FIFO", must_refuse=True, timeout=5),
        Case("ctsfleet-gen", ["--map", HUGE_MAP, "-N", "1", "-M", "1", "-o", os.path.join(WORK, "g.yaml")],
             "gen: a 5000x5000 map header", must_refuse=True, timeout=5, stderr_contains="4096"),
        Case("ctsfleet-coordinator", ["-c", FIFO], "coordinator -c a FIFO", must_refuse=True, timeout=5),
        Case("ctsfleet-coordinator", ["-c", os.path.join(ROOT, "config/fleet.yaml"), "--journal", FIFO,
                                      "--domain", "227"], "coordinator --journal a FIFO", must_refuse=True, timeout=5),
        Case("ctsfleet-dashboard", ["--replay", FIFO, "--port", "0"], "dashboard --replay a FIFO", must_refuse=True,
             timeout=5),
        Case("ctsfleet-dashboard", ["--plan", FIFO, "--instance", INSTANCE, "--port", "0"],
             "dashboard --plan a FIFO", must_refuse=True, timeout=5),
        Case("ctsfleet-dashboard", ["--plan", ROTATED_PLAN, "--instance", INSTANCE, "--port", "0"],
             "dashboard --plan of another instance (the agents rotated)", must_refuse=True,
             stderr_contains="not a valid plan of"),
        refuse("ctsfleet-dashboard", ["--plan", OFF_MAP_PLAN, "--instance", INSTANCE, "--port", "0"],
               "dashboard --plan with a cell off the map"),
        refuse("ctsfleet-dashboard", ["--plan", ROTATED_PLAN, "--instance", INSTANCE, "--svg",
                                      os.path.join(WORK, "rotated.svg")], "dashboard --svg of another instance's plan"),
        refuse("ctsfleet-dashboard", ["--replay", SHORT_ROWS_HISTORY, "--svg", os.path.join(WORK, "short.svg")],
               "dashboard --svg of a history whose map rows are short (crashed once)"),
        refuse("ctsfleet-toio-calibrate", ["fit", "--mat", MAT, "-o", os.path.join(WORK, "fit.yaml"), "--point",
                                           "0,0=nan,175", "--point", "1,0=100,175", "--point", "0,1=50,200"],
               "toio-calibrate fit with a nan point (the fit ran once)"),
        refuse("ctsfleet-toio-calibrate", ["fit", "--mat", MAT, "-o", os.path.join(WORK, "fit.yaml"), "--point",
                                           "4294967296,0=100,175", "--point", "1,0=100,175", "--point", "0,1=50,200"],
               "toio-calibrate fit with a cell past int"),
        refuse("ctsfleet-sim", ["--domain", "-5"], "sim --domain -5"),
        refuse("ctsfleet-sim", ["--step", "-1"], "sim --step -1"),
        refuse("ctsfleet-toio-emulator", ["--bus", "unix:path=/x", "--mat", MAT, "--cube", "a@cell:99,99"],
               "emulator: a cube on cell 99,99 of a 6x4 grid"),
        refuse("ctsfleet-toio-emulator", ["--bus", "unix:path=/x", "--cube", "a@200,200", "--cube", "a@250,250"],
               "emulator: two cubes with one name"),
        refuse("ctsfleet-toio-emulator", ["--bus", "unix:path=/x", "--cube", "a@200,200", "--tick-ms", "-5"],
               "emulator --tick-ms -5"),
    ]


def script_cases():
    """Every script answers --help and --version at once with exit 0 and refuses an unknown option
    with exit 2."""
    problems, count = [], 0
    for script in sorted(os.listdir(os.path.join(ROOT, "scripts"))):
        path = os.path.join(ROOT, "scripts", script)
        checks = [(["--help"], 0), (["--version"], 0)]
        if script != "test":  # test passes its arguments on to ctest
            checks.append((["--no-such-option"], 2))
        for args, want in checks:
            count += 1
            try:
                done = subprocess.run([path] + args, capture_output=True, text=True, timeout=20, cwd=WORK)
            except subprocess.TimeoutExpired:
                problems.append(f"scripts/{script} {' '.join(args)}: hang")
                continue
            if done.returncode != want or "Traceback" in done.stderr:
                problems.append(f"scripts/{script} {' '.join(args)}: exit {done.returncode}, expected {want}: "
                                f"{done.stderr.strip()[-200:]!r}")
            elif args == ["--help"] and "usage" not in (done.stdout + done.stderr).lower():
                problems.append(f"scripts/{script} --help: no usage text")
            elif args == ["--version"] and not re.search(r"\d+\.\d+|unversioned", done.stdout):
                problems.append(f"scripts/{script} --version: no version: {done.stdout.strip()[:100]!r}")
    return count, problems


def exit_code_table_problems(cases):
    """The README's exit-code table, the constants of ctsfleet/program.hpp and the codes the cases
    exited with must agree: one table for every program."""
    with open(os.path.join(ROOT, "README.md")) as f:
        readme = f.read()
    block = re.search(r"<!-- exit-codes -->(.*?)<!-- /exit-codes -->", readme, re.S)
    if not block:
        return ["README.md has no exit-code table between <!-- exit-codes --> markers"]
    table = {int(m.group(1)) for m in re.finditer(r"^\| (\d+) \|", block.group(1), re.M)}
    with open(os.path.join(ROOT, "common/program/include/ctsfleet/program.hpp")) as f:
        header = {int(m.group(1)) for m in re.finditer(r"constexpr int kExit\w+ = (\d+);", f.read())}
    problems = []
    if table != header:
        problems.append(f"exit codes: README table {sorted(table)} but ctsfleet/program.hpp {sorted(header)}")
    for case in cases:
        if case.code is not None and case.code >= 0 and case.code not in table:
            problems.append(f"{case.name}: exit {case.code}, which the README's exit-code table does not list")
    return problems


def main():
    cases = catalogue_cases() + named_cases()
    failures = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=4) as pool:
        for case, problem in zip(cases, pool.map(run, cases)):
            if problem:
                failures.append(f"{case.name}: {problem}")
    failures += exit_code_table_problems(cases)
    script_count, script_problems = script_cases()
    failures += script_problems
    programs = len(PROGRAMS)
    print(f"cli catalogue: {programs} programs, {len(cases)} program cases ({len(named_cases())} named), "
          f"{script_count} script cases, {len(failures)} failures")
    for failure in failures:
        print("FAIL", failure)
    if not failures:
        shutil.rmtree(WORK, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
