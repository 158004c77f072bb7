#!/usr/bin/env bash
# The rotation model from the command line: ctsfleet-solve --actions rotate plans for agents with
# start headings from the instance; the independent checker (turning_plan_check.py, with ctsval.py
# for the cells) accepts the plans of CTS-PIBT and LaCAM* (which plan with turns) and CTS-PLL (turns added)
# and rejects a wrong start heading and a plan without headings; a bad heading is refused by name.
# Usage: turning_plans_cli.sh BIN_DIR DATA_DIR PYTHON
set -euo pipefail
bin="$1"; data="$2"; python="$3"
here="$(cd "$(dirname "$0")" && pwd)"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
ctsval="$data/../../../shared/tools/ctsval.py"; [ -f "$ctsval" ] || ctsval="$data/ctsval.py"
check="$here/planner_core/turning_plan_check.py"

# The first two agents face north and west; the others east (no heading given).
sed -e "s|^map: ../maps/|map: $data/maps/|" \
    -e '0,/goal: \[25, 3\]}/s//goal: [25, 3], heading: N}/' \
    -e '0,/goal: \[20, 27\]}/s//goal: [20, 27], heading: W}/' \
    "$data/instances/random-32-32-20-N10-M30-00.yaml" > "$work/turning.yaml"
grep -q "heading: W" "$work/turning.yaml"
for solver in cts-pibt cts-pibt-anytime; do
  "$bin/ctsfleet-solve" -i "$work/turning.yaml" --solver $solver --actions rotate -t 3 --seed 4 -o "$work/$solver.txt" \
    | tee "$work/summary"
  grep -q "solved=1" "$work/summary"
  grep -q "^actions=rotate$" "$work/$solver.txt"
  grep -q "^0:(30,21,N),(0,4,W),(" "$work/$solver.txt"
  "$python" "$check" "$ctsval" "$work/turning.yaml" "$work/$solver.txt" | tee "$work/checked"
  # The same figures as the solver's, from the independent checker. (Its output is read from a
  # file: grep -q on a pipe stops reading at the first match, and the checker's next line met a
  # closed pipe.)
  flowtime="$(grep '^flowtime=' "$work/$solver.txt" | cut -d= -f2)"
  grep -q "flowtime=$flowtime " "$work/checked"
done

# The checker can fail: a wrong start heading.
sed -e '0,/^0:(30,21,N)/s//0:(30,21,E)/' "$work/cts-pibt.txt" > "$work/wrong-start.txt"
if "$python" "$check" "$ctsval" "$work/turning.yaml" "$work/wrong-start.txt" > "$work/out"; then
  echo "the checker accepted a wrong start heading"; exit 1
fi
grep -q "agent 0 starts facing E, not N" "$work/out"
# And the four-way plan of the same instance is rejected in the rotation model (no headings).
"$bin/ctsfleet-solve" -i "$work/turning.yaml" --solver cts-pibt -t 3 -o "$work/four-way.txt" > /dev/null
if "$python" "$check" "$ctsval" "$work/turning.yaml" "$work/four-way.txt" > "$work/out"; then
  echo "the checker accepted a plan without headings"; exit 1
fi

# CTS-PLL plans four-way moves; the turns are added: the checker accepts its plan as well.
"$bin/ctsfleet-solve" -i "$work/turning.yaml" --solver cts-pll-v3 --actions rotate -t 2 -o "$work/pll.txt" > "$work/summary"
grep -q "solved=1" "$work/summary"
"$python" "$check" "$ctsval" "$work/turning.yaml" "$work/pll.txt"
# LaCAM* over cell and heading (plain MAPF), its own plan alone: accepted by the checker too.
sed -e "s|^map: ../maps/|map: $data/maps/|" "$data/../../benchmarks/mapf/maze-32-32-2-N50-0.yaml" > "$work/plain.yaml"
"$bin/ctsfleet-solve" -i "$work/plain.yaml" --solver lacam-star --actions rotate --turns planned -t 2 \
  -o "$work/lacam.txt" > "$work/summary"
grep -q "solved=1" "$work/summary"
"$python" "$check" "$ctsval" "$work/plain.yaml" "$work/lacam.txt" > "$work/checked"
flowtime="$(grep '^flowtime=' "$work/lacam.txt" | cut -d= -f2)"
grep -q "flowtime=$flowtime " "$work/checked"
sed -e 's/heading: W/heading: west/' "$work/turning.yaml" > "$work/bad-heading.yaml"
set +e
"$bin/ctsfleet-solve" -i "$work/bad-heading.yaml" --actions rotate -o "$work/never.txt" 2> "$work/err"
code=$?
set -e
[ "$code" -eq 2 ] || { echo "bad heading: expected exit 2, got $code"; exit 1; }
grep -q "bad-heading.yaml:5: agents\[1\].heading: \"west\" is no heading (E, S, W or N)" "$work/err" || { cat "$work/err"; exit 1; }
echo "turning plans from the command line: ok"
