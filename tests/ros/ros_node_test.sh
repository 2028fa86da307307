#!/usr/bin/env bash
# rigidd --ros read by an independent ROS 2 peer in node (node/ros_node_test.mjs: @foxglove/rtps
# and ROS 2's message definitions, pinned in node/package-lock.json), in a network namespace of
# its own with multicast on loopback (in_netns.sh). Two servers at once: domain 0 plain (ROS 2
# Iron and later), domain 1 with --ros-namespace lab --ros-distro humble.
#
#   ros_node_test.sh RIGIDD SOURCE_DIR
set -euo pipefail
rigidd=$1
src=$2
here=$(cd "$(dirname "$0")" && pwd)
if [[ ${RIGID_IN_NETNS:-} != 1 ]]; then exec "$here/in_netns.sh" "$0" "$@"; fi

fail() { echo "ros_node_test: FAILED: $*" >&2; exit 1; }
command -v node > /dev/null || fail "node is not installed (apt-get install nodejs npm)"
if [[ ! -f $here/node/node_modules/@foxglove/rtps/package.json ]]; then
  # --ignore-scripts: nothing from the registry runs at install.
  (cd "$here/node" && timeout 300 npm ci --ignore-scripts --no-audit --no-fund > /dev/null) ||
    fail "tests/ros/node/node_modules missing and npm ci failed (offline?)"
fi

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
"$rigidd" --scene "$scene" --transport dds --ros --dds-domain 1 --ros-namespace lab \
  --ros-distro humble > "$dir/b.log" 2>&1 &
pids+=($!)

status=0
timeout 60 node "$here/node/ros_node_test.mjs" 0 "" jazzy > "$dir/a.out" 2>&1 &
a=$!
timeout 60 node "$here/node/ros_node_test.mjs" 1 /lab humble > "$dir/b.out" 2>&1 &
b=$!
wait "$a" || status=1
wait "$b" || status=1
cat "$dir/a.out" "$dir/b.out"
grep -q "no ROS wrench topic" "$dir/a.log" || { echo "rigidd did not say which body has no wrench topic:"; status=1; }
if [[ $status != 0 ]]; then
  echo "--- rigidd (domain 0)"; cat "$dir/a.log"
  echo "--- rigidd (domain 1)"; cat "$dir/b.log"
  exit 1
fi
echo "ros_node_test: ok"
