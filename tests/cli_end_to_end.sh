#!/usr/bin/env bash
# End-to-end: ctsfleet-gen makes an instance, ctsfleet-solve solves it (the independent checker
# accepts the plan), ctsfleet-bench runs a folder, and bad input gives a clear error and exit 2.
set -euo pipefail
bin="$1"; data="$2"; python="${3:-python3}"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
ctsval="$data/../../../shared/tools/ctsval.py"; [ -f "$ctsval" ] || ctsval="$data/ctsval.py"

# expect_input_error NAMED COMMAND...: COMMAND exits 2 and its error names NAMED (an option).
expect_input_error() {
  local named="$1" code=0
  shift
  "$@" > /dev/null 2> "$work/err" || code=$?
  [ "$code" -eq 2 ] || { echo "$*: expected exit 2, got $code"; exit 1; }
  grep -q -- "$named" "$work/err"
}

"$bin/ctsfleet-gen" --map "$data/maps/random-32-32-20.map" -N 8 -M 16 --seed 5 -o "$work/gen.yaml"
"$bin/ctsfleet-solve" -i "$work/gen.yaml" -t 5 -o "$work/sol.txt" --svg "$work/sol.svg" | tee "$work/summary"
grep -q "solved=1" "$work/summary"
grep -q "^order_0=" "$work/sol.txt"
grep -q "^comp_time_first_ms=" "$work/sol.txt"
grep -q "^comp_time_preprocessing_ms=" "$work/sol.txt"
grep -q "preprocessing_ms=.* peak_memory_mb=" "$work/summary"
grep -q "stroke-opacity" "$work/sol.svg" && grep -q ">start</text>" "$work/sol.svg"
# mapf-visualizer reads the lines with ":(" as timesteps, each "(x,y)," a position; lacam's keys are there.
grep ":(" "$work/sol.txt" | grep -qvE '^[0-9]+:(\([0-9]+,[0-9]+\),)+$' && { echo "a timestep line mapf-visualizer would misread"; exit 1; }
[ "$(grep -c ':(' "$work/sol.txt")" -eq "$(( $(grep '^makespan=' "$work/sol.txt" | cut -d= -f2) + 1 ))" ]
grep -q '^soc=' "$work/sol.txt" && grep -q '^starts=(' "$work/sol.txt" && grep -q '^goals=(' "$work/sol.txt"
"$python" "$ctsval" "$work/gen.yaml" "$work/sol.txt"

mkdir "$work/suite"
for seed in 1 2 3; do
  "$bin/ctsfleet-gen" --map "$data/maps/maze-32-32-2.map" -N 5 -M 10 --seed $seed -o "$work/suite/maze-32-32-2-N5-M10-0$seed.yaml" >/dev/null
done
"$bin/ctsfleet-bench" "$work/suite" -t 2 --sample 2 --csv "$work/bench.csv" -j 2 | tee "$work/bench.out"
[ "$(wc -l < "$work/bench.csv")" -eq 3 ]   # header + 2 sampled instances
grep -q "| maze-32-32-2 | 5 | 10 | 2 |" "$work/bench.out"

printf 'map: nowhere.map\nagents: []\n' > "$work/bad.yaml"
set +e
"$bin/ctsfleet-solve" -i "$work/bad.yaml" -o "$work/never.txt" 2> "$work/err"
code=$?
set -e
[ "$code" -eq 2 ] || { echo "expected exit 2, got $code"; exit 1; }
grep -q "nowhere.map" "$work/err"
[ ! -e "$work/never.txt" ]
# A time limit that is not a positive, finite number of seconds is an input error.
for limit in 0 -1 nan inf 1e300; do
  set +e
  "$bin/ctsfleet-solve" -i "$work/gen.yaml" -t "$limit" -o "$work/never.txt" 2> "$work/err"
  code=$?
  set -e
  [ "$code" -eq 2 ] || { echo "-t $limit: expected exit 2, got $code"; exit 1; }
  grep -q -- "--time" "$work/err"
  [ ! -e "$work/never.txt" ]
done
# The same for ctsfleet-bench, and a bad option value is exit 2 too (not the parser's own code).
for args in "-t -1" "-t nan" "--experiment mapf-scale -t inf" "--solver bogus"; do
  set +e
  "$bin/ctsfleet-bench" $args "$work/suite" > /dev/null 2> "$work/err"
  code=$?
  set -e
  [ "$code" -eq 2 ] || { echo "ctsfleet-bench $args: expected exit 2, got $code"; exit 1; }
done
expect_input_error --lns-neighbourhood \
  "$bin/ctsfleet-solve" -i "$work/gen.yaml" --lns-neighbourhood 0 -o "$work/never.txt"

# The scale experiment on a one-instance suite (200 agents: far from optimal, so the solve runs
# to its 120 s limit unless stopped): SIGTERM while ctsfleet-solve runs stops both and
# exits 130 with the table so far.
mkdir "$work/scale"
"$bin/ctsfleet-gen" --map "$data/maps/random-32-32-20.map" -N 200 -M 0 --seed 1 -o "$work/scale/random-N200.yaml" >/dev/null
"$bin/ctsfleet-bench" --experiment mapf-scale --scale-suite "$work/scale" --out-dir "$work/scale-out" -t 120 \
  > "$work/scale.out" 2>&1 &
bench_pid=$!
for _ in $(seq 200); do   # until its ctsfleet-solve runs (20 s at most)
  pgrep -P "$bench_pid" > /dev/null && break
  sleep 0.1
done
pgrep -P "$bench_pid" > /dev/null || { echo "the experiment never started ctsfleet-solve"; exit 1; }
kill -TERM "$bench_pid"
set +e
wait "$bench_pid"
code=$?
set -e
[ "$code" -eq 130 ] || { echo "interrupted experiment: expected exit 130, got $code"; cat "$work/scale.out"; exit 1; }
grep -q "interrupted" "$work/scale.out"
# The lifelong experiment on a League of Robot Runners problem: the table, the chart's CSV and
# the league's output file, which an independent replay (positions from the actions) accepts.
lorr="$data/../../benchmarks/lorr-2023/random.domain/random_50.json"
"$bin/ctsfleet-bench" --experiment lifelong --problem "$lorr" --steps 120 --step-time 1 --league-output \
  --out-dir "$work/lifelong" > "$work/lifelong.out"
grep -q "^random_50 " "$work/lifelong.out"
grep -q "^random_50,50,120,1,pibt-lanes-r128," "$work/lifelong/lifelong.csv"
grep -q "^  rollouts of 3 steps (auto)" "$work/lifelong.out"
map="$data/../../benchmarks/lorr-2023/random.domain/maps/random-32-32-20.map"
"$python" "$(dirname "$0")/lorr_replay.py" "$work/lifelong/random_50.lorr.json" "$map"
# The same in the league's rotation model: an independent replay of forward, turns and waits.
"$bin/ctsfleet-bench" --experiment lifelong --problem "$lorr" --steps 120 --step-time 1 --league-output \
  --actions rotate --rollouts 1 --no-lns --out-dir "$work/lifelong-rotate" > "$work/lifelong-rotate.out"
grep -q "^random_50,50,120,1,pibt-rotate-lanes-r1-hold-half-keep," "$work/lifelong-rotate/lifelong.csv"
grep -q "^  plans held half (auto)" "$work/lifelong-rotate.out"
"$python" "$(dirname "$0")/lorr_replay.py" "$work/lifelong-rotate/random_50.lorr.json" "$map"
# Plans held until every agent stands on its cell, in every rollout: its steps replay as validly.
"$bin/ctsfleet-bench" --experiment lifelong --problem "$lorr" --steps 120 --step-time 1 --league-output \
  --actions rotate --no-lns --rollouts 4 --hold-plans always --park-dead-ends on --out-dir "$work/lifelong-hold" \
  > "$work/lifelong-hold.out"
grep -q "plans held always, targets kept" "$work/lifelong-hold.out"
# Parking asked for (auto parks only on maps more than 90% full: not in the run above).
grep -Eq "^  parked: [0-9]+ agents at the last step" "$work/lifelong-hold.out"
if grep -q "parked" "$work/lifelong.out"; then echo "50 agents on 819 cells parked under auto"; exit 1; fi
grep -q "^random_50,50,120,1,pibt-rotate-lanes-r4-hold-always-keep-park," "$work/lifelong-hold/lifelong.csv"
# Rollouts look 8 steps ahead only where plans are held always by auto (more than 90% full).
grep -q "^  rollouts of 3 steps (auto)" "$work/lifelong-hold.out"
"$bin/ctsfleet-bench" --experiment lifelong --problem "${lorr%/*}/random_800.json" --steps 12 --step-time 1 \
  --actions rotate --rollouts 4 --out-dir "$work/lifelong-crowded" > "$work/lifelong-crowded.out"
grep -q "^  rollouts of 8 steps (auto)" "$work/lifelong-crowded.out"
grep -q "^  plans held always (auto)" "$work/lifelong-crowded.out"
# More than 90% full: window LNS stays off by default (auto), even in the rotation model.
if grep -q "window LNS" "$work/lifelong-crowded.out"; then echo "LNS on at random_800 under auto"; exit 1; fi
grep -Eq "^random_800 +800 +[0-9]+ +[0-9.]+ +[0-9.]+ +[0-9.]+ +[0-9.]+ +[0-9]+ +0 " "$work/lifelong-crowded.out"  # no invalid step
"$python" "$(dirname "$0")/lorr_replay.py" "$work/lifelong-hold/random_50.lorr.json" "$map"
for bad in "--hold-plans sometimes" "--park-dead-ends yes" "--keep-window sometimes" \
  "--rollout-steps -1" "--traffic-costs sometimes" "--keep-equal-cost sometimes" "--neighbourhoods widest"; do
  # shellcheck disable=SC2086  # the option and its value are two words
  expect_input_error "${bad%% *}" "$bin/ctsfleet-bench" --experiment lifelong --problem "$lorr" --actions rotate $bad
done
# And with window LNS, the default in the rotation model (no --lns needed): its steps replay as
# validly. With 50 agents on 819 free cells the window (auto) is 16 steps, kept from step to step.
"$bin/ctsfleet-bench" --experiment lifelong --problem "$lorr" --steps 60 --step-time 0.2 --league-output \
  --actions rotate --out-dir "$work/lifelong-lns" > "$work/lifelong-lns.out"
grep -q "window LNS: [1-9]" "$work/lifelong-lns.out"
grep -q "^  windows of 16 steps (auto), kept from step to step (auto)" "$work/lifelong-lns.out"
grep -q "^  paths of equal cost kept (auto)" "$work/lifelong-lns.out"
grep -q "^  neighbourhoods adaptive (nearest, crossing, random) (auto)" "$work/lifelong-lns.out"
grep -Eq "^  last window carried on at [1-9][0-9]* of 60 steps" "$work/lifelong-lns.out"
# With LNS and 50 agents on 819 free cells, "auto" guidance (the default) takes shortest paths.
grep -q "guidance none (auto): shortest paths; a wait or turn costs 1" "$work/lifelong-lns.out"
expect_input_error --stay-cost "$bin/ctsfleet-bench" --experiment lifelong --problem "$lorr" --stay-cost 9
grep -q "^random_50,50,60,0.2,pibt-rotate-none-r128-lns-window-kept-equal-kept-adaptive-hold-half-keep," "$work/lifelong-lns/lifelong.csv"
"$python" "$(dirname "$0")/lorr_replay.py" "$work/lifelong-lns/random_50.lorr.json" "$map"
# The ring road (auto only when agents are more, asked for here): costs in tenths, waits at 3;
# its steps replay as validly.
"$bin/ctsfleet-bench" --experiment lifelong --problem "$lorr" --steps 40 --step-time 0.2 --league-output \
  --actions rotate --rollout-steps 8 --lns --keep-window off --guidance ring --neighbourhoods nearest \
  --out-dir "$work/lifelong-ring" > "$work/lifelong-ring.out"
grep -q "^  neighbourhoods nearest$" "$work/lifelong-ring.out"
grep -q "^  windows of 8 steps, planned afresh each step$" "$work/lifelong-ring.out"
grep -q "guidance ring: lanes turning every 1 rows and every 1 columns, and cheaper within 12 cells of the edge; a wait or turn costs 3" \
  "$work/lifelong-ring.out"
# With the ring road auto counts traffic costs (from 60% of the time taken: 50 agents on 819 cells).
grep -q "^  traffic costs (auto): cells taken more than 60% of the time cost up to 2 moves more" "$work/lifelong-ring.out"
grep -q "^random_50,50,40,0.2,pibt-rotate-ring-stay3-r128-lns-equal-kept-hold-half-keep-traffic," "$work/lifelong-ring/lifelong.csv"
"$python" "$(dirname "$0")/lorr_replay.py" "$work/lifelong-ring/random_50.lorr.json" "$map"
# Work counted instead of timed: two runs, one with a step far too short (every step late, taken
# all the same), move the agents alike, and replay validly.
for run in short ample; do
  step_time=0.000001
  [ "$run" = ample ] && step_time=5
  "$bin/ctsfleet-bench" --experiment lifelong --problem "$lorr" --steps 30 --step-time "$step_time" --league-output \
    --actions rotate --rollouts 8 --rollout-steps 8 --lns --lns-rounds 400 --keep-window on --out-dir "$work/lifelong-counted-$run" \
    > "$work/lifelong-counted-$run.out"
  grep -q "work counted, not timed: every step 8 rollouts and, with LNS, 400 LNS rounds" "$work/lifelong-counted-$run.out"
  grep -q "^random_50,50,30,.*,pibt-rotate-none-r8-lns-window-kept-equal-kept-adaptive-hold-half-keep," "$work/lifelong-counted-$run/lifelong.csv"
  "$python" "$(dirname "$0")/lorr_replay.py" "$work/lifelong-counted-$run/random_50.lorr.json" "$map"
done
"$python" - "$work/lifelong-counted-short/random_50.lorr.json" "$work/lifelong-counted-ample/random_50.lorr.json" <<'PY'
import json, sys
short, ample = (json.load(open(path)) for path in sys.argv[1:])
assert short["actualPaths"] == ample["actualPaths"], "the counted runs moved the agents differently"
assert short["numTaskFinished"] == ample["numTaskFinished"] > 0
PY
cmp "$work/lifelong-counted-short/lifelong_steps.csv" "$work/lifelong-counted-ample/lifelong_steps.csv"
expect_input_error --lns-rounds "$bin/ctsfleet-bench" --experiment lifelong --problem "$lorr" --lns-rounds 0
# The settings file (config/lifelong.yaml): read whole; a command-line option overrides its key;
# a bad value names the file, its line and the key, and nothing is written.
"$bin/ctsfleet-bench" --experiment lifelong --problem "$lorr" --steps 10 --step-time 0.2 --actions rotate \
  --lifelong-config "$(dirname "$0")/../config/lifelong.yaml" --out-dir "$work/lifelong-shipped" > "$work/lifelong-shipped.out"
grep -q "^random_50,50,10,0.2,pibt-rotate-none-r128-lns-window-kept-equal-kept-adaptive-hold-half-keep," \
  "$work/lifelong-shipped/lifelong.csv"
printf 'lns: off\nrollouts: 2\nguidance: lanes\n' > "$work/cheap.yaml"
"$bin/ctsfleet-bench" --experiment lifelong --problem "$lorr" --steps 10 --step-time 0.2 --actions rotate \
  --lifelong-config "$work/cheap.yaml" --rollouts 3 --out-dir "$work/lifelong-cheap" > "$work/lifelong-cheap.out"
grep -q "^random_50,50,10,0.2,pibt-rotate-lanes-r3-hold-half-keep," "$work/lifelong-cheap/lifelong.csv"
printf 'rollouts: 4\nhold_plans: sometimes\n' > "$work/bad-lifelong.yaml"
expect_input_error "bad-lifelong.yaml:2" "$bin/ctsfleet-bench" --experiment lifelong --problem "$lorr" \
  --lifelong-config "$work/bad-lifelong.yaml" --out-dir "$work/lifelong-bad"
grep -q "hold_plans" "$work/err"
[ ! -e "$work/lifelong-bad/lifelong.csv" ] || { echo "a bad settings file still wrote a table"; exit 1; }
# The league's 2026 problems (Start-Kit 3.x): read and run, their execution settings named as not
# simulated; a second problem with a bad delayConfig stops the run before anything is written.
lorr26="$data/../../benchmarks/lorr-2026/maze.domain"
"$bin/ctsfleet-bench" --experiment lifelong --problem "$lorr26/maze-example_40.json" --steps 10 --step-time 0.2 \
  --actions rotate --out-dir "$work/lifelong-2026" > "$work/lifelong-2026.out"
grep -q "^maze-example_40 " "$work/lifelong-2026.out"
grep -q "2026 LoRR: agentCounter [0-9]*, delayConfig read; not simulated here" "$work/lifelong-2026.out"
sed -e "s|\"maps/|\"$lorr26/maps/|; s|\"agents/|\"$lorr26/agents/|; s|\"tasks/|\"$lorr26/tasks/|" \
  -e 's|"pDelay": [0-9.]*|"pDelay": 1.5|' "$lorr26/maze-example_40.json" > "$work/bad-delays.json"
expect_input_error '"pDelay"' "$bin/ctsfleet-bench" --experiment lifelong --problem "$lorr26/maze-example_40.json" \
  --problem "$work/bad-delays.json" --steps 10 --out-dir "$work/lifelong-2026-bad"
[ ! -e "$work/lifelong-2026-bad/lifelong.csv" ] || { echo "a bad problem still wrote a table"; exit 1; }
# The same problems under the 2026 rules (--experiment league): ticks, agentCounter, delays, the
# Action Dependency Graph carrying plans out; the output file replayed independently, delays on
# and off; bad settings and a bad second problem stop the run before anything is written.
"$bin/ctsfleet-bench" --experiment league --problem "$lorr26/maze-example_40.json" --ticks 200 --rollouts 1 \
  --delays both --league-output --out-dir "$work/league" > "$work/league.out"
grep -Eq "^maze-example_40 +40 +on +[0-9]+ +[0-9]+ +[0-9.]+ +[0-9]+ +[0-9.]+ +[0-9.]+ +0 +0 +0 " "$work/league.out"
grep -Eq "^maze-example_40 +40 +off +[0-9]+ +[0-9]+ +0.0 " "$work/league.out"
grep -q "^maze-example_40,40,200,100,1000,on," "$work/league/league.csv"
grep -q "^maze-example_40,40,200,100,1000,off," "$work/league/league.csv"
grep -q "^maze-example_40 (no delays),199," "$work/league/league_ticks.csv"
"$python" "$(dirname "$0")/lorr_2026_replay.py" "$work/league/maze-example_40.lorr.json" "$lorr26/maps/maze-32-32-2.map"
"$python" "$(dirname "$0")/lorr_2026_replay.py" "$work/league/maze-example_40.no-delays.lorr.json" \
  "$lorr26/maps/maze-32-32-2.map"
expect_input_error '"pDelay"' "$bin/ctsfleet-bench" --experiment league --problem "$lorr26/maze-example_40.json" \
  --problem "$work/bad-delays.json" --ticks 10 --out-dir "$work/league-bad"
[ ! -e "$work/league-bad/league.csv" ] || { echo "a bad problem still wrote a league table"; exit 1; }
# iron_harvest (10,000 robots on 2.2 million cells): the planner's tables would not fit; refused
# before anything is written (354 GB needed; a CI machine has far less).
expect_input_error "GB of distance tables" "$bin/ctsfleet-bench" --experiment league --problem \
  "$lorr26/maze-example_40.json" --problem "$lorr26/../iron_harvest.domain/iron-example_10000.json" --ticks 10 \
  --out-dir "$work/league-iron"
[ ! -e "$work/league-iron/league.csv" ] || { echo "a problem too big still wrote a league table"; exit 1; }
expect_input_error --plan-period-ms "$bin/ctsfleet-bench" --experiment league --problem "$lorr26/maze-example_40.json" \
  --plan-period-ms 150
for bad in "--scheduler fastest" "--delays maybe" "--ticks 0" "--tick-ms -5"; do
  # shellcheck disable=SC2086  # the option and its value are two words
  expect_input_error "${bad%% *}" "$bin/ctsfleet-bench" --experiment league --problem "$lorr26/maze-example_40.json" $bad
done
expect_input_error --actions "$bin/ctsfleet-bench" --experiment lifelong --problem "$lorr" --actions diagonal
expect_input_error --guidance "$bin/ctsfleet-bench" --experiment lifelong --problem "$lorr" --guidance highway

echo "cli end-to-end: all checks passed"
