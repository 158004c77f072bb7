#!/usr/bin/env python3
"""An independent replay of a League of Robot Runners output file (docs/FORMATS.md).

Usage: lorr_replay.py RUN.json MAP

Moves every agent by its actual actions, in either action model ("MAPF": U D L R W; "MAPF_T":
F R C W with headings E S W N), and checks what the league checks: no move into a wall or off the
map, no two agents on one cell, no two agents swapping cells, every finished task finished on its
cell, and the number of finished tasks. Exits non-zero with the first fault.
"""
import json
import sys

MOVES = {"U": (-1, 0), "D": (1, 0), "L": (0, -1), "R": (0, 1), "W": (0, 0)}
AHEAD = [(0, 1), (1, 0), (0, -1), (-1, 0)]  # east, south, west, north
HEADINGS = "ESWN"


def free_cells(map_path):
    """A MovingAI map's test for a free cell: free(row, column), False off the map."""
    lines = open(map_path).read().split("\n")
    height = int(lines[1].split()[1])
    width = int(lines[2].split()[1])
    rows = lines[4:4 + height]

    def free(r, c):
        return 0 <= r < height and 0 <= c < width and rows[r][c] in ".ES"
    return free


def main():
    run = json.load(open(sys.argv[1]))
    free = free_cells(sys.argv[2])

    rotate = run["actionModel"] == "MAPF_T"
    assert run["actionModel"] in ("MAPF", "MAPF_T"), run["actionModel"]
    assert run["AllValid"] == "Yes" and run["errors"] == [], run["errors"][:3]
    team = run["teamSize"]
    at = [(r, c) for r, c, _ in run["start"]]
    facing = [HEADINGS.index(h) for _, _, h in run["start"]] if rotate else None
    paths = [p.split(",") for p in run["actualPaths"]]
    steps = len(paths[0])
    cells = {t[0]: (t[1], t[2]) for t in run["tasks"]}
    finished = {(e[1], a): e[0] for a, events in enumerate(run["events"]) for e in events if e[2] == "finished"}
    checked = turns = moves = 0
    for step in range(steps):
        nxt = list(at)
        for a in range(team):
            action = paths[a][step]
            if rotate:
                assert action in "FRCW", f"agent {a} step {step}: {action}"
                if action == "F":
                    nxt[a] = (at[a][0] + AHEAD[facing[a]][0], at[a][1] + AHEAD[facing[a]][1])
                elif action in "RC":
                    facing[a] = (facing[a] + (1 if action == "R" else 3)) % 4
                    turns += 1
            else:
                assert action in MOVES, f"agent {a} step {step}: {action}"
                nxt[a] = (at[a][0] + MOVES[action][0], at[a][1] + MOVES[action][1])
            if nxt[a] != at[a]:
                assert free(*nxt[a]), f"agent {a} moves into a wall or off the map at step {step}"
                moves += 1
        assert len(set(nxt)) == len(nxt), f"two agents on a cell at step {step}"
        standing = {cell: a for a, cell in enumerate(at)}
        for a in range(team):
            b = standing.get(nxt[a])
            assert b is None or b == a or nxt[b] != at[a], f"agents {a} and {b} swap at step {step}"
        at = nxt
        for a in range(team):
            if (step + 1, a) in finished:
                assert cells[finished[(step + 1, a)]] == at[a], f"agent {a} finished away from its task"
                checked += 1
    assert checked == run["numTaskFinished"] > 0, (checked, run["numTaskFinished"])
    assert moves > 0 and (not rotate or turns > 0), (moves, turns)
    print(f"replayed {steps} steps of {team} agents: {moves} moves, {turns} turns, {checked} tasks finished")


if __name__ == "__main__":
    main()
