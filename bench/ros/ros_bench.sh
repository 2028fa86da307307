#!/usr/bin/env bash
# rigidd with and without --ros, side by side: N pairs of runs, alternating, each a fresh rigidd
# on a scene of BODIES free bodies at 1 kHz publishing 100 states/s, measured by ros_bench
# (ros_bench.cpp: a client of rigid's topics, and with --ros also of /tf and a ROS wrench topic).
# In a network namespace of its own (tests/ros/in_netns.sh: loopback with multicast, no other
# DDS traffic), with config/cyclonedds-ros.xml.
#
#   bench/ros/ros_bench.sh BUILD_DIR [BODIES=1000] [PAIRS=5] [SECONDS=20]
#
# Prints each run's RESULT lines, then per pair rigidd's CPU, the DDS publisher thread's CPU
# (rigid-pub-dds) and the wrench-to-state p50s, and the medians over the pairs.
set -euo pipefail
build=$(cd "$1" && pwd)
bodies=${2:-1000}
pairs=${3:-5}
seconds=${4:-20}
src=$(cd "$(dirname "$0")/../.." && pwd)
if [[ ${RIGID_IN_NETNS:-} != 1 ]]; then exec "$src/tests/ros/in_netns.sh" "$0" "$@"; fi
export CYCLONEDDS_URI=file://$src/config/cyclonedds-ros.xml

dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
# BODIES boxes of 1 kg (I = diag(1, 2, 3)/12 kg m^2 scaled), spinning, in zero gravity: b0 and b1
# at rest for the pushes.
{
  echo 'world { rate_hz: 1000 substeps: 1 publish_every: 10 gravity { } }'
  echo 'body { name: "b0" mass: 1 shape { box { x: 0.3 y: 0.2 z: 0.1 } } }'
  echo 'body { name: "b1" mass: 1 shape { box { x: 0.3 y: 0.2 z: 0.1 } } position { x: 1 } }'
  for ((i = 2; i < bodies; ++i)); do
    echo "body { name: \"b$i\" mass: 1 shape { box { x: 0.3 y: 0.2 z: 0.1 } } position { y: $i } angular_velocity { x: 0.001 y: 5 z: 0.001 } }"
  done
} > "$dir/scene.pbtxt"

run() {  # LABEL ROS(0|1)
  local label=$1 ros=$2 pid out
  "$build/server/rigidd/rigidd" --scene "$dir/scene.pbtxt" --transport dds \
    $([[ $ros == 1 ]] && echo --ros) > "$dir/rigidd.log" 2>&1 &
  pid=$!
  for _ in $(seq 100); do grep -q "ready:" "$dir/rigidd.log" && break; sleep 0.1; done
  out=$("$build/bench/ros_bench" --pid "$pid" --duration "$seconds" $([[ $ros == 1 ]] && echo --ros))
  kill "$pid"
  wait "$pid" || true
  echo "$out" | sed "s/^/$label /"
}

for ((p = 1; p <= pairs; ++p)); do
  run "plain $p" 0 | tee -a "$dir/results"
  run "ros $p" 1 | tee -a "$dir/results"
done

python3 - "$dir/results" <<'PY'
import re, statistics, sys
runs = {}
for line in open(sys.argv[1]):
    kind, pair, _, what, *rest = line.split()
    r = runs.setdefault((kind, int(pair)), {})
    if what == "process_cpu_percent":
        r["cpu"] = float(rest[0])
    elif what == "thread_cpu_percent":
        names = dict(zip(rest[0::2], rest[1::2]))
        r["pub"] = float(names.get("rigid-pub-dds", "nan"))
    elif what == "wrench_to_state_us":
        r["rigid_p50"] = float(rest[2])
        key = "ros" if "ros" in rest else "held"
        r[key + "_p50"] = float(rest[rest.index(key) + 2])
pairs = sorted({p for _, p in runs})
print("pair  cpu plain  cpu ros  ratio   pub plain  pub ros  ratio   p50 us: plain run (one-tick, held)  ros run (one-tick, ROS)  ROS - one-tick")
ratios, pub_ratios, deltas = [], [], []
for p in pairs:
    a, b = runs.get(("plain", p), {}), runs.get(("ros", p), {})
    if not a or not b: continue
    ratios.append(b["cpu"] / a["cpu"]); pub_ratios.append(b["pub"] / a["pub"])
    deltas.append(b["ros_p50"] - b["rigid_p50"])
    print(f"{p:4d}  {a['cpu']:9.1f}  {b['cpu']:7.1f}  {ratios[-1]:5.3f}   {a['pub']:9.1f}  {b['pub']:7.1f}  {pub_ratios[-1]:5.3f}   "
          f"        {a['rigid_p50']:8.1f} {a['held_p50']:8.1f}    {b['rigid_p50']:8.1f} {b['ros_p50']:8.1f}   {deltas[-1]:+8.1f}")
if ratios:
    print(f"median ratio of rigidd's CPU (ros / plain): {statistics.median(ratios):.3f}; "
          f"of rigid-pub-dds's: {statistics.median(pub_ratios):.3f}; "
          f"median ROS p50 - rigid p50 in the same run: {statistics.median(deltas):+.1f} us")
PY
