#!/usr/bin/env bash
# DDS Security against plain DDS, side by side in one run (issue 10's targets): wrench-to-state
# latency p50/p99 and tick lateness p99 at 1 kHz (loop_bench realtime) in two uses: sporadic pushes
# (one every ~20 ms, a state every 10 ticks, 1000 bodies: between messages the machine idles, and
# each secure message then runs the cryptography's code cold) and a controller (a push every ~2 ms,
# a state every tick, 10 and 1000 bodies: the path stays warm, as it does for a control loop); the
# states per second DDS carries from rigidd to one subscriber at 1000 bodies (loop_bench fast
# --publish-every 1), and the states per second it carries when every state must arrive (loop_bench
# paced: lockstep step requests, which hand over each state once the last was taken, so that the
# loop sleeps instead of spinning on a core of its own). Runs alternate plain, secure and secure
# with the state unencrypted, REPEATS times each.
#
#   bench/security/security_bench.sh [--build DIR] [--duration S] [--repeats N]
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$here/build
duration=20
repeats=2
while (($#)); do
  case $1 in
    --build) build=$2; shift 2 ;;
    --duration) duration=$2; shift 2 ;;
    --repeats) repeats=$2; shift 2 ;;
    *) echo "security_bench: unknown option $1" >&2; exit 2 ;;
  esac
done
export CYCLONEDDS_URI=${CYCLONEDDS_URI:-file://$here/config/cyclonedds.xml}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$here/scripts/rigid-keys" init "$work/ks" >/dev/null
"$here/scripts/rigid-keys" add "$work/ks" bench --may push --may control >/dev/null
# The same with the state unencrypted (rigid-keys init --state-protection none).
"$here/scripts/rigid-keys" init "$work/ks_none" --state-protection none >/dev/null
"$here/scripts/rigid-keys" add "$work/ks_none" bench --may push --may control >/dev/null
bench=$build/bench/loop_bench
for ((r = 1; r <= repeats; ++r)); do
  for kind in plain secure secure-state-none; do
    sec=()
    [[ $kind == secure ]] && sec=(--security "$work/ks")
    [[ $kind == secure-state-none ]] && sec=(--security "$work/ks_none")
    echo "== run $r: $kind: realtime, sporadic pushes, 1000 bodies, ${duration} s"
    "$bench" realtime --bodies 1000 --duration "$duration" --transport dds "${sec[@]}"
    for n in 10 1000; do
      echo "== run $r: $kind: realtime, controller, $n bodies, ${duration} s"
      "$bench" realtime --bodies "$n" --duration "$duration" --transport dds --publish-every 1 \
        --push-every-ms 2 "${sec[@]}"
    done
    echo "== run $r: $kind: fast, 1000 point masses, a state every tick, 10 s"
    "$bench" fast --bodies 1000 --duration 10 --transport dds --publish-every 1 --point-masses \
      "${sec[@]}"
    echo "== run $r: $kind: paced, 1000 point masses, every state, 10 s"
    "$bench" paced --bodies 1000 --duration 10 --transport dds --point-masses "${sec[@]}"
  done
done
