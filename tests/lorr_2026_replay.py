#!/usr/bin/env python3
"""An independent replay of a League of Robot Runners 2026 output file (docs/FORMATS.md, "League
of Robot Runners output, 2026").

Usage: lorr_2026_replay.py RUN.json MAP

Expands each robot's segments "[(tick,row,col,heading,counter):(A d,...)]" into one action per
tick and replays them with the league's counter: an action (F forward, R clockwise, C counter-
clockwise) ends on its agentMaxCounter-th tick of that letter; W leaves the counter as it is (a
delayed robot stands mid-move). Checks: every segment's snapshot is where the replay stands; no
move into a wall or off the map; no cell held by two robots at a tick (a robot moving forward
holds its cell and the one ahead); no robot moves while delayed (delayIntervals); every errand
event happens with its robot on the errand's cell; the finished tasks' count. Exits non-zero with
the first fault.
"""
import json
import re
import sys

from lorr_replay import free_cells

AHEAD = [(0, 1), (1, 0), (0, -1), (-1, 0)]  # east, south, west, north
SEGMENT = re.compile(r"\[\((\d+),(\d+),(\d+),(\d+),(\d+)\):\(([^)]*)\)\]")


def main():
    run = json.load(open(sys.argv[1]))
    free_cell = free_cells(sys.argv[2])

    def free(cell):
        return free_cell(*cell)

    assert run["actionModel"] == "MAPF_T" and run["version"] == "2026 LoRR", run["actionModel"]
    assert run["numPlannerErrors"] == 0 and run["errors"] == [], run["errors"][:3]
    team, ticks, counter_max = run["teamSize"], run["makespan"], run["agentMaxCounter"]
    at = [(r, c) for r, c, _ in run["start"]]
    facing = ["ESWN".index(h) for _, _, h in run["start"]]
    counter = [0] * team
    doing = ["W"] * team  # the action under way
    actions = []
    snapshots = []
    for robot, path in enumerate(run["actualPaths"]):
        letters = []
        for match in SEGMENT.finditer(path):
            tick, row, col, heading, count, body = match.groups()
            assert int(tick) == len(letters), f"robot {robot}: segment at tick {tick} after {len(letters)} ticks"
            snapshots.append((int(tick), robot, (int(row), int(col)), int(heading), int(count)))
            for item in filter(None, body.split(",")):
                letter, times = item.split(" ")
                assert letter in "FRCW", f"robot {robot}: action {letter}"
                letters += [letter] * int(times)
        assert len(letters) == ticks, f"robot {robot}: {len(letters)} ticks of actions, makespan {ticks}"
        actions.append(letters)
    snapshots_at = {}
    for tick, robot, cell, heading, count in snapshots:
        snapshots_at.setdefault(tick, []).append((robot, cell, heading, count))
    delayed = [set() for _ in range(team)]
    for robot, intervals in enumerate(run["delayIntervals"]):
        for first, last in intervals:
            delayed[robot].update(range(first, last + 1))
    tasks = {t[0]: t[2] for t in run["tasks"]}
    events = {}
    for tick, robot, task, done in run["events"]:
        events.setdefault(tick, []).append((robot, task, done))
    finished = moves = 0
    for tick in range(ticks):
        for robot, cell, heading, count in snapshots_at.get(tick, []):
            assert (at[robot], facing[robot], counter[robot]) == (cell, heading, count), \
                f"robot {robot}: segment at tick {tick} says {cell, heading, count}, replay {at[robot], facing[robot], counter[robot]}"
        held = {}
        for robot in range(team):
            letter = actions[robot][tick]
            cells = [at[robot]]
            if letter != "W":
                assert tick not in delayed[robot], f"robot {robot} acts at tick {tick}, delayed"
                assert counter[robot] == 0 or doing[robot] == letter, f"robot {robot} changes action mid-way at tick {tick}"
                doing[robot] = letter
                counter[robot] += 1
                ahead = (at[robot][0] + AHEAD[facing[robot]][0], at[robot][1] + AHEAD[facing[robot]][1])
                if letter == "F":
                    assert free(ahead), f"robot {robot} moves into a wall or off the map at tick {tick}"
                    if counter[robot] < counter_max:
                        cells.append(ahead)
                if counter[robot] == counter_max:
                    counter[robot] = 0
                    moves += 1
                    if letter == "F":
                        at[robot] = ahead
                        cells = [ahead]
                    else:
                        facing[robot] = (facing[robot] + (1 if letter == "R" else 3)) % 4
            elif counter[robot] > 0 and doing[robot] == "F":  # stopped mid-move: it holds both cells
                cells.append((at[robot][0] + AHEAD[facing[robot]][0], at[robot][1] + AHEAD[facing[robot]][1]))
            for cell in cells:
                assert cell not in held, f"robots {held.get(cell)} and {robot} hold cell {cell} at tick {tick}"
                held[cell] = robot
        for robot, task, done in events.get(tick + 1, []):
            errands = tasks[task]
            cell = (errands[2 * (done - 1)], errands[2 * (done - 1) + 1])
            assert at[robot] == cell, f"robot {robot} finished errand {done} of task {task} away from it at tick {tick}"
            if done == len(errands) // 2:
                finished += 1
    assert finished == run["numTaskFinished"], (finished, run["numTaskFinished"])
    print(f"replayed {ticks} ticks of {team} robots: {moves} actions, {finished} tasks finished")


if __name__ == "__main__":
    main()
