#!/usr/bin/env bash
# rigidd's benchmark set, in one run so the figures compare (the machines' timings drift between
# runs minutes apart):
#   1. the machine's own timer (a bare SCHED_FIFO thread sleeping to 1 ms deadlines): the floor
#      under rigidd's tick lateness and overruns here;
#   2. realtime: 1 kHz, 1000 general bodies, a state every 10 ticks on DDS and LCM, a subscriber
#      and a controller on each bus: overruns, tick lateness, command-to-state latency per bus;
#   3. the physics alone (step_bench, same 10^4-body case) and fast mode (the whole loop with both
#      buses publishing at 100 Hz of simulated time): cost per body-step and their ratio.
#
#   bench/loop/loop_bench.sh [--build DIR] [--duration S] [--fast-duration S]
#       defaults: build/, 60 s, 20 s. Run as root (scripts/net-setup adds LCM's route on lo).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build="$here/build"
duration=60
fast_duration=20
while (($#)); do
  case "$1" in
    --build) build=$(cd "$2" && pwd); shift 2 ;;
    --duration) duration=$2; shift 2 ;;
    --fast-duration) fast_duration=$2; shift 2 ;;
    *) echo "usage: $0 [--build DIR] [--duration S] [--fast-duration S]" >&2; exit 2 ;;
  esac
done
for exe in bench/loop_bench bench/step_bench server/rigidd/rigidd; do
  [[ -x "$build/$exe" ]] || { echo "missing $build/$exe: build first" >&2; exit 1; }
done
export "$("$here/scripts/net-setup")"

echo "== machine: $(nproc) CPUs, $(uname -r), $(date -u +%Y-%m-%dT%H:%MZ)"
echo "== 1. timer floor ($duration s each)"
"$build/bench/loop_bench" timer --duration "$duration" | grep RESULT
echo "== 2. realtime, 1000 bodies, $duration s"
"$build/bench/loop_bench" realtime --bodies 1000 --duration "$duration"
echo "== 3. cost per body-step, 10^4 bodies"
step=$("$build/bench/step_bench" --benchmark_filter='racket/exact_rotor4/10000$' \
  --benchmark_repetitions=5 --benchmark_report_aggregates_only=true 2>/dev/null | grep _median)
echo "step_bench: $step"
# Wall time per body-step, like the loop's figure (the counter step_bench prints is CPU time).
step_ns=$(awk '{ for (i = 1; i <= NF; ++i) if ($i == "us") { print $(i - 1) * 1000 / 10000; exit } }' \
  <<<"$step")
fast=$("$build/bench/loop_bench" fast --bodies 10000 --duration "$fast_duration")
echo "$fast"
loop_ns=$(awk '/RESULT fast_ns_per_body_step_median_second/ { print $3 }' <<<"$fast")
awk -v s="$step_ns" -v l="$loop_ns" 'BEGIN {
  printf "RESULT fast/step_bench: %.2f / %.2f ns per body-step = %.3fx (target <= 1.3x)\n", l, s, l / s }'
