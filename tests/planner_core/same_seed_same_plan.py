#!/usr/bin/env python3
"""Same input, same seed, same plan: every solver run twice at once (each run loads the machine
for the other) on a dense, a scale and a warehouse instance; the solution files must agree byte for
byte apart from the times. The first-plan solvers run on the clock alone (their first plan must not
depend on it); the anytime ones with --iterations (their final plan must not either).

usage: same_seed_same_plan.py BIN_DIR BENCHMARKS_DIR [SOLVER...]
"""
import concurrent.futures
import os
import subprocess
import sys
import tempfile

# Header keys that are times: the only lines allowed to differ.
TIME_KEYS = ("comp_time", "comp_time_ms", "comp_time_first_ms", "comp_time_preprocessing_ms")

CTS_INSTANCES = ("dense/maze-32-32-2-N50-M120-30.yaml", "scale/random-64-64-20-N400-M800-00.yaml",
                 "scale/warehouse-10-20-10-2-1-N400-M800-00.yaml")
MAPF_INSTANCES = ("mapf/maze-32-32-2-N50-0.yaml", "mapf/random-64-64-20-N600-0.yaml",
                  "mapf/warehouse-10-20-10-2-1-N300-0.yaml")
FIRST_PLAN_SOLVERS = ("cts-pibt", "cts-pll-v1", "cts-pll-v2", "lacam")
ANYTIME_SOLVERS = ("cts-pibt-anytime", "cts-pll-v3", "cts-lacam", "lacam-star")
ITERATIONS = "2000"  # about 2 s of search each on the reference machine
SAFETY_LIMIT_S = "120"  # only a stop for a broken solver: the budgets end every run long before


def body(path):
    with open(path, encoding="utf-8") as f:
        return [line for line in f if line.split("=", 1)[0] not in TIME_KEYS]


def header_value(lines, key):
    for line in lines:
        if line.startswith(key + "="):
            return line.split("=", 1)[1].strip()
    return None


def solve(bin_dir, instance, solver, out):
    command = [os.path.join(bin_dir, "ctsfleet-solve"), "-i", instance, "--solver", solver, "--seed", "7",
               "-t", SAFETY_LIMIT_S, "-o", out]
    if solver in ANYTIME_SOLVERS:
        command += ["--iterations", ITERATIONS]
    run = subprocess.run(command, capture_output=True, text=True, timeout=600)
    return command, run


def check(bin_dir, benchmarks, solver, instance_name, work):
    instance = os.path.join(benchmarks, instance_name)
    outs = [os.path.join(work, f"{solver}-{os.path.basename(instance_name)}-{k}.txt") for k in (0, 1)]
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        runs = list(pool.map(lambda out: solve(bin_dir, instance, solver, out), outs))
    problems = []
    for command, run in runs:
        if run.returncode != 0:
            problems.append(f"{' '.join(command)} exited {run.returncode}: {run.stderr.strip()[-400:]}")
        if "warning: the time limit" in run.stderr:
            problems.append(f"{' '.join(command)}: the safety limit ended the run, not its budget")
    if problems:
        return problems
    first, second = body(outs[0]), body(outs[1])
    if header_value(first, "seed") != "7" or not header_value(first, "solver_version"):
        problems.append(f"{solver} {instance_name}: the solution file does not name the seed and solver version")
    if first != second:
        diff = next(i for i, (a, b) in enumerate(zip(first + [""], second + [""])) if a != b)
        problems.append(f"{solver} {instance_name}: two runs differ from line {diff + 1}: "
                        f"{first[diff].strip()[:120] if diff < len(first) else '(end)'} | "
                        f"{second[diff].strip()[:120] if diff < len(second) else '(end)'}")
    elif not problems:
        print(f"ok {solver} {instance_name}: flowtime {header_value(first, 'flowtime')}, identical over two runs")
    return problems


def main():
    bin_dir, benchmarks = sys.argv[1], sys.argv[2]
    solvers = sys.argv[3:] or FIRST_PLAN_SOLVERS + ANYTIME_SOLVERS
    problems = []
    with tempfile.TemporaryDirectory() as work:
        for solver in solvers:
            instances = MAPF_INSTANCES if solver in ("lacam", "lacam-star") else CTS_INSTANCES
            for instance in instances:
                problems += check(bin_dir, benchmarks, solver, instance, work)
    for problem in problems:
        print("FAIL " + problem)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
