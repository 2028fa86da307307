#!/usr/bin/env bash
# rigidd --ros --security: the keystore of scripts/rigid-keys covers ROS 2's topics. In a network
# namespace of its own (in_netns.sh), with a Cyclone DDS peer built from ROS 2 message
# definitions alone (secure/ros_secure_peer.cpp) reading its identity by SROS2's file names:
#  - rigidd's serve identity may make every ROS topic (else it would not start);
#  - a read identity reads /tf; a push:ball identity moves ball through rt/rigid/ball/wrench;
#  - the push:ball identity may not write rt/rigid/twin/wrench, the read identity no wrench, and
#    a participant without identity reads nothing;
#  - the keystore has SROS2's layout: KEYSTORE/enclaves/NAME with SROS2's file names.
#
#   ros_security_test.sh RIGIDD ROS_SECURE_PEER SOURCE_DIR
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
status=0
fail() { echo "ros_security_test: FAILED: $*"; status=1; }

keys=$src/scripts/rigid-keys
ks=$dir/ks
"$keys" init "$ks" > /dev/null
"$keys" add "$ks" pilot --may push:ball > /dev/null
"$keys" add "$ks" viewer --may read > /dev/null
for f in cert.pem key.pem identity_ca.cert.pem permissions_ca.cert.pem governance.p7s permissions.p7s; do
  [[ -f $ks/enclaves/pilot/$f ]] || fail "no $f in $ks/enclaves/pilot (SROS2's layout)"
done

export CYCLONEDDS_URI=file://$src/config/cyclonedds-ros.xml
"$rigidd" --scene "$here/scenes/ros_shapes.pbtxt" --transport dds --ros \
  --security "$ks/identities/rigidd" > "$dir/rigidd.log" 2>&1 &
pids+=($!)

# The viewer reads /tf (ball at rest at x = -1).
x0=$("$peer" read --security "$ks/identities/viewer" ball) || fail "the read identity read no /tf (status $?)"
[[ $x0 == -1 ]] || fail "ball at x = '$x0' before any push, not -1"
# The pilot pushes ball along x through ROS; the viewer sees it move.
"$peer" write --security "$ks/identities/pilot" rt/rigid/ball/wrench 10 ||
  fail "push:ball could not write rt/rigid/ball/wrench (status $?)"
sleep 0.3
x1=$("$peer" read --security "$ks/identities/viewer" ball) || fail "no /tf after the push"
awk -v a="$x1" 'BEGIN { exit !(a > -1) }' || fail "ball did not move along x after the push (x = $x1)"
# Refusals: access control refuses the writer (status 3) or nothing matches it (1).
set +e
"$peer" write --security "$ks/identities/pilot" rt/rigid/twin/wrench 10
twin=$?
"$peer" write --security "$ks/identities/viewer" rt/rigid/ball/wrench 10
viewer=$?
"$peer" read ball > /dev/null
plain=$?
set -e
[[ $twin == 3 ]] || fail "push:ball wrote rt/rigid/twin/wrench (status $twin, not 3: refused)"
[[ $viewer == 3 ]] || fail "the read identity wrote a wrench (status $viewer, not 3: refused)"
[[ $plain != 0 ]] || fail "a participant without identity read /tf"
grep -q "not permitted\|DDS Security" "$dir/rigidd.log" || true
if [[ $status != 0 ]]; then
  echo "--- rigidd"; cat "$dir/rigidd.log"
  exit 1
fi
echo "ros_security_test: ok"
