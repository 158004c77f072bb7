#!/usr/bin/env bash
# Installs the build into a temporary prefix and uses it as a user would, from a folder outside
# the source tree: --version and man pages, ctsfleet-solve on an installed instance, a short
# ctsfleet-sim mission with the installed configs (no CTSFLEET_DATA_DIR, no source tree), and a
# tiny CMake project built against the installed planner_core (find_package(ctsfleet)).
# Usage: install_test.sh BUILD_DIR WORK_DIR DDS_DOMAIN
set -euo pipefail
build="$1"; work="$2"; domain="$3"
rm -rf "$work"; mkdir -p "$work"
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"
fail() { echo "FAIL: $*" >&2; exit 1; }

cmake --install "$build" --prefix "$prefix" >"$work/install.log" || fail "cmake --install (see $work/install.log)"
for program in ctsfleet-solve ctsfleet-gen ctsfleet-bench ctsfleet-coordinator ctsfleet-sim ctsfleet-agent \
               ctsfleet-monitor ctsfleet-fleetbench ctsfleet-seqbench ctsfleet-toio-emulator ctsfleet-toio-calibrate \
               ctsfleet-dashboard ctsfleet-task ctsfleet-ca ctsfleet-plot; do
  [ -x "$prefix/bin/$program" ] || fail "$program not installed"
  "$prefix/bin/$program" --version | grep -q "^$program [0-9]" || fail "$program --version"
  if command -v help2man >/dev/null; then
    [ -f "$prefix/share/man/man1/$program.1.gz" ] || fail "no man page for $program"
  fi
done
for data in config/fleet.yaml config/dds/cyclonedds-loopback.xml benchmarks/dense benchmarks/maps/den520d.map; do
  [ -e "$prefix/share/ctsfleet/$data" ] || fail "share/ctsfleet/$data not installed"
done
[ -f "$prefix/share/doc/ctsfleet/FORMATS.md" ] || fail "docs not installed"

# From a folder that is neither the source tree nor the prefix, with nothing in the environment.
outside="$work/elsewhere"; mkdir -p "$outside"; cd "$outside"
unset CTSFLEET_DATA_DIR
"$prefix/bin/ctsfleet-solve" -i "$prefix/share/ctsfleet/benchmarks/dense/maze-32-32-2-N50-M60-00.yaml" -t 2 \
  --solver cts-pll-v2 -o solution.txt --json >summary.json || fail "ctsfleet-solve on an installed instance"
python3 -c 'import json,sys; s=json.load(open("summary.json")); sys.exit(0 if s["solved"] else 1)' || fail "not solved"
"$prefix/bin/ctsfleet-solve" -i "$prefix/share/ctsfleet/benchmarks/mapf/maze-32-32-2-N50-0.scen" -N 10 -t 1 \
  --map "$prefix/share/ctsfleet/benchmarks/maps" -o scen.txt >/dev/null || fail "ctsfleet-solve on an installed .scen"

"$prefix/bin/ctsfleet-sim" --robots 8 --step 0.02 --domain "$domain" --log-dir sim-logs --json >sim.json 2>sim.log ||
  { tail -20 sim.log >&2; fail "ctsfleet-sim with the installed configs"; }
python3 -c 'import json,sys; s=json.load(open("sim.json")); sys.exit(0 if s["completed"] else 1)' || fail "mission not completed"

# A consumer project of the installed planner_core.
mkdir -p "$work/consumer"
cat >"$work/consumer/CMakeLists.txt" <<'EOF'
cmake_minimum_required(VERSION 3.25)
project(consumer LANGUAGES CXX)
set(CMAKE_CXX_STANDARD 20)
find_package(ctsfleet 0.1 REQUIRED)
add_executable(consumer main.cpp)
target_link_libraries(consumer PRIVATE ctsfleet::planner_core)
EOF
cat >"$work/consumer/main.cpp" <<'EOF'
#include <cstdio>

#include "planner_core/solver.hpp"
#include "planner_core/validator.hpp"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const planner_core::Instance instance = planner_core::load_instance(argv[1]);
  planner_core::SolverConfig config;
  config.solver = "cts-pll-v2";
  planner_core::SolveOptions options{planner_core::Deadline::in_seconds(5), {}, planner_core::Clock::now()};
  const planner_core::SolveResult result = planner_core::make_solver(config)->solve(instance, options);
  const bool valid = result.solved && planner_core::validate(instance, result.solution).ok();
  std::printf("solved=%d valid=%d flowtime=%lld\n", result.solved ? 1 : 0, valid ? 1 : 0,
              static_cast<long long>(result.flowtime));
  return valid ? 0 : 1;
}
EOF
cmake -S "$work/consumer" -B "$work/consumer/build" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release \
  >"$work/consumer.log" 2>&1 || { cat "$work/consumer.log" >&2; fail "consumer configure"; }
cmake --build "$work/consumer/build" >>"$work/consumer.log" 2>&1 || { tail -30 "$work/consumer.log" >&2; fail "consumer build"; }
"$work/consumer/build/consumer" "$prefix/share/ctsfleet/config/default/instance.yaml" | grep -q "valid=1" ||
  fail "the consumer did not solve the instance"
echo "install test: passed"
