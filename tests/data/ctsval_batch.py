#!/usr/bin/env python3
"""Runs ctsval.check on many (instance, solution) pairs: argv[1] = ctsval.py, stdin = lines
'INSTANCE<TAB>SOLUTION'; prints 'feasible flowtime makespan lower_bound' per pair."""
import importlib.util
import sys

spec = importlib.util.spec_from_file_location("ctsval", sys.argv[1])
ctsval = importlib.util.module_from_spec(spec)
spec.loader.exec_module(ctsval)
for line in sys.stdin:
    inst, sol = line.rstrip("\n").split("\t")
    r = ctsval.check(inst, sol)
    print(int(r["feasible"]), r.get("flowtime", -1), r.get("makespan", -1), r.get("lower_bound", -1), flush=True)
