#!/usr/bin/env bash
# rigid-record on a real stream, side by side: rigidd runs BODIES bodies at 1 kHz, a state every 10
# ticks (100 states/s) on DDS, and three recorders record the same stream at once for DURATION s:
# uncompressed (--compress none), zstd chunks (the default) and zstd keeping one state in ten
# (--every 10). Each recorder's CPU time (user + system, from /proc, read just before it is
# stopped) and its file's size are printed; then recording_levels rewrites the uncompressed file
# at several zstd levels (the level rigid-record uses is chosen from that table).
#
# Two scenes: "spinning", every body tumbling (each value of each state changes: the hard case),
# and "resting", every body at rest (each state repeats the last: the easy case). Real scenes lie
# between.
#
#   bench/transport/recording_bench.sh [--build DIR] [--bodies N] [--duration S] [--scene spinning|resting]
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$here/build
bodies=1000
duration=20
scenes="spinning resting"
while (($#)); do
  case $1 in
    --build) build=$2; shift 2 ;;
    --bodies) bodies=$2; shift 2 ;;
    --duration) duration=$2; shift 2 ;;
    --scene) scenes=$2; shift 2 ;;
    *) echo "recording_bench: unknown option $1" >&2; exit 2 ;;
  esac
done
export CYCLONEDDS_URI=${CYCLONEDDS_URI:-file://$here/config/cyclonedds.xml}
work=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT

# CPU seconds (user + system) of process $1 so far.
cpu_of() {
  local fields
  if ! read -ra fields 2> /dev/null < "/proc/$1/stat"; then
    echo "recording_bench: recorder $1 stopped early:" >&2
    cat "$work"/*.err >&2
    exit 1
  fi
  # Fields 14 and 15 (utime, stime), in clock ticks; the command name (field 2) has no spaces here.
  echo "scale=3; (${fields[13]} + ${fields[14]}) / $(getconf CLK_TCK)" | bc
}

for scene in $scenes; do
  file=$work/$scene.pbtxt
  {
    echo "world { rate_hz: 1000 substeps: 1 publish_every: 10 gravity { z: 0 } }"
    for ((i = 0; i < bodies; ++i)); do
      if [[ $scene == spinning ]]; then
        printf 'body { name: "b%d" mass: 1 inertia { x: 1 y: 2 z: 3 } use_gravity: false velocity { x: 0.%03d } angular_velocity { x: 0.%03d y: 5 z: 0.001 } }\n' "$i" "$((i % 1000))" "$((i % 997))"
      else
        printf 'body { name: "b%d" mass: 1 inertia { x: 1 y: 2 z: 3 } use_gravity: false position { x: %d } }\n' "$i" "$i"
      fi
    done
  } > "$file"
  prefix=recbench$$$scene
  "$build/server/rigidd/rigidd" --scene "$file" --transport dds --prefix "$prefix" \
    2> "$work/rigidd.err" &
  rigidd=$!
  pids+=("$rigidd")
  for ((t = 0; t < 100; ++t)); do
    grep -q "ready" "$work/rigidd.err" && break
    sleep 0.1
  done
  declare -A rec=()
  for kind in none zstd every10; do
    args=(--compress zstd)
    [[ $kind == none ]] && args=(--compress none)
    [[ $kind == every10 ]] && args=(--every 10)
    "$build/clients/rigid-record" record "$work/$scene-$kind.rlog" "${args[@]}" --transport dds \
      --prefix "$prefix" 2> "$work/$scene-$kind.err" &
    rec[$kind]=$!
    pids+=("${rec[$kind]}")
  done
  sleep "$duration"
  declare -A cpu=()
  for kind in none zstd every10; do
    cpu[$kind]=$(cpu_of "${rec[$kind]}")
    kill -INT "${rec[$kind]}"
  done
  for kind in none zstd every10; do wait "${rec[$kind]}" || true; done
  kill "$rigidd"; wait "$rigidd" || true
  echo "== $scene: $bodies bodies, 100 states/s, $duration s recorded by three recorders at once"
  printf '%-8s %10s %10s %12s %10s %14s\n' recorder states MB "bytes/state" ratio "CPU s (% core)"
  plain=$(stat -c %s "$work/$scene-none.rlog")
  for kind in none zstd every10; do
    size=$(stat -c %s "$work/$scene-$kind.rlog")
    states=$("$build/clients/rigid-record" info "$work/$scene-$kind.rlog" |
      sed -n 's/^records: \([0-9]*\) states.*/\1/p')
    printf '%-8s %10d %10.1f %12d %10.2f %8.2f (%4.1f%%)\n' "$kind" "$states" \
      "$(echo "$size / 1000000" | bc -l)" "$((size / (states > 0 ? states : 1)))" \
      "$(echo "$plain / $size" | bc -l)" "${cpu[$kind]}" \
      "$(echo "100 * ${cpu[$kind]} / $duration" | bc -l)"
  done
  "$build/bench/recording_levels" "$work/$scene-none.rlog" --levels 1,3,6,9 --repeats 3
done
