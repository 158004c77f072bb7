#!/usr/bin/env bash
# ctsfleet-plot draws the four charts from a small CSV (quoted fields included) and refuses bad
# input with exit 2. Usage: plot_test.sh PLOTTER DATA_DIR
set -euo pipefail
plot="$1"; data="$2"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
"$plot" success "$data/small-bench.csv" -o "$work/success.svg" >/dev/null
"$plot" ratio "$data/small-bench.csv" -o "$work/ratio.png" >/dev/null
printf 'solver,time_s,flowtime\ncts-pll-v3,0.1,900\ncts-pll-v3,2.5,850\ncts-pibt-anytime,0.05,950\n' >"$work/anytime.csv"
"$plot" anytime "$work/anytime.csv" -o "$work/anytime.svg" >/dev/null
printf 'problem,step,errands\nrandom_20,0,0\nrandom_20,1,2\nrandom_20,2,1\nsortation_large_10000,0,5\nsortation_large_10000,1,7\n' >"$work/steps.csv"
"$plot" lifelong "$work/steps.csv" -o "$work/lifelong.svg" >/dev/null
grep -q "sortation_large_10000" "$work/lifelong.svg"
grep -q "<svg" "$work/success.svg"
grep -q "cts-pll-v3" "$work/success.svg"   # the legend names the solvers
[ "$(head -c 4 "$work/ratio.png" | tail -c 3)" = "PNG" ]
grep -q "<svg" "$work/anytime.svg"
for bad in "success /nonexistent.csv -o $work/x.svg" "success $data/small-bench.csv -o $work/x.txt" \
           "ratio $work/anytime.csv -o $work/x.svg" "lifelong $work/anytime.csv -o $work/x.svg" "nosuchchart $data/small-bench.csv -o $work/x.svg"; do
  set +e
  "$plot" $bad >/dev/null 2>"$work/err"
  code=$?
  set -e
  [ "$code" -eq 2 ] || { echo "ctsfleet-plot $bad: expected exit 2, got $code"; cat "$work/err"; exit 1; }
  ! grep -q Traceback "$work/err"
done
echo "plot test: passed"
