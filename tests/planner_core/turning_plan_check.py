#!/usr/bin/env python3
"""Independent check of a CTS-MAPF plan in the rotation model (written apart from the C++ validator).

usage: turning_plan_check.py CTSVAL INSTANCE.yaml SOLUTION.txt

Checks the rotation model's rules: every cell of every timestep carries a heading letter (E S W N),
the headings at t=0 are the instance's (`heading:` per agent, E when absent), and each step of each
agent is a move to the cell ahead keeping its heading, a quarter turn in place, or a wait. The cells
alone (headings stripped) then go to the independent checker CTSVAL (ctsval.py) for every other
rule: starts, conflicts, tasks, goals. Exit 0 only when both accept the plan; prints the flowtime.
"""
import os
import re
import subprocess
import sys
import tempfile

import yaml

STEP = {"E": (1, 0), "S": (0, 1), "W": (-1, 0), "N": (0, -1)}
CLOCKWISE = "ESWN"


def fail(message):
    print("REJECTED: " + message)
    sys.exit(1)


def main():
    if len(sys.argv) != 4:
        print(__doc__)
        sys.exit(2)
    ctsval, instance_path, solution_path = sys.argv[1:]
    with open(instance_path) as f:
        instance = yaml.safe_load(f)
    start_headings = [agent.get("heading", "E") for agent in instance["agents"]]
    timesteps = []
    header = []
    with open(solution_path) as f:
        lines = f.read().splitlines()
    body = lines.index("solution=")
    header = lines[: body + 1]
    for line in lines[body + 1:]:
        if not line:
            continue
        t, rest = line.split(":", 1)
        poses = re.findall(r"\((-?\d+),(-?\d+),?([A-Z]?)\)", rest)
        if any(h == "" for _, _, h in poses):
            fail(f"t={t}: a cell without a heading")
        timesteps.append([(int(x), int(y), h) for x, y, h in poses])
    if not timesteps:
        fail("no timesteps")
    for a, heading in enumerate(start_headings):
        if timesteps[0][a][2] != heading:
            fail(f"agent {a} starts facing {timesteps[0][a][2]}, not {heading}")
    for t in range(1, len(timesteps)):
        for a, ((x0, y0, h0), (x1, y1, h1)) in enumerate(zip(timesteps[t - 1], timesteps[t])):
            if (x0, y0) == (x1, y1):
                turn = (CLOCKWISE.index(h1) - CLOCKWISE.index(h0)) % 4
                if turn == 2:
                    fail(f"t={t}: agent {a} turns half round")
            elif (x1 - x0, y1 - y0) != STEP[h0] or h1 != h0:
                fail(f"t={t}: agent {a} moves ({x0},{y0})->({x1},{y1}) facing {h0}, then {h1}")
    with tempfile.NamedTemporaryFile("w", suffix=".txt", delete=False) as cells_only:
        cells_only.write("\n".join(header) + "\n")
        for t, poses in enumerate(timesteps):
            cells_only.write(f"{t}:" + "".join(f"({x},{y})," for x, y, _ in poses) + "\n")
    try:
        checked = subprocess.run([sys.executable, ctsval, instance_path, cells_only.name], capture_output=True, text=True)
    finally:
        os.unlink(cells_only.name)
    print(checked.stdout.strip())
    if checked.returncode != 0:
        fail("ctsval.py rejects the cells")
    print(f"accepted: {len(timesteps[0])} agents, {len(timesteps)} timesteps, every step forward, a quarter turn or a wait")


if __name__ == "__main__":
    main()
