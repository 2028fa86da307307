#!/usr/bin/env bash
# rigidd --ros driven by a Fast DDS peer (fastdds/ros_fastdds_peer.cpp), in a network namespace
# of its own with multicast on loopback (in_netns.sh): the services, wrenches through ROS against
# rigid's own, malformed samples (domain 0); the services with --controls off (domain 1).
#
#   ros_fastdds_test.sh RIGIDD ROS_FASTDDS_PEER SOURCE_DIR
set -euo pipefail
rigidd=$1
peer=$2
src=$3
here=$(cd "$(dirname "$0")" && pwd)
if [[ ${RIGID_IN_NETNS:-} != 1 ]]; then exec "$here/in_netns.sh" "$0" "$@"; fi

dir=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2> /dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2> /dev/null || true; done
  rm -rf "$dir"
}
trap cleanup EXIT
export CYCLONEDDS_URI=file://$src/config/cyclonedds-ros.xml
scene=$here/scenes/ros_shapes.pbtxt
"$rigidd" --scene "$scene" --transport dds --ros --dds-domain 0 > "$dir/a.log" 2>&1 &
pids+=($!)
"$rigidd" --scene "$scene" --transport dds --ros --dds-domain 1 --controls off > "$dir/b.log" 2>&1 &
pids+=($!)

status=0
timeout 90 "$peer" 0 full > "$dir/a.out" 2>&1 &
a=$!
timeout 60 "$peer" 1 controls-off > "$dir/b.out" 2>&1 &
b=$!
wait "$a" || status=1
wait "$b" || status=1
grep "^ros_fastdds_test" "$dir/a.out" "$dir/b.out" | sed 's/^[^:]*://'
if [[ $status != 0 ]]; then
  echo "--- peer (domain 0)"; cat "$dir/a.out"
  echo "--- rigidd (domain 0)"; cat "$dir/a.log"
  echo "--- rigidd (domain 1)"; cat "$dir/b.log"
  exit 1
fi
echo "ros_fastdds_test: ok"
