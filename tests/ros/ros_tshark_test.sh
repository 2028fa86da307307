#!/usr/bin/env bash
# The wire, as tshark (Wireshark's RTPS dissector) reads a capture of loopback while rigidd --ros
# serves the test scene to a Fast DDS peer reading /tf and /clock (ros_fastdds_peer listen), in a
# network namespace of its own (in_netns.sh): each ROS topic announced with its DDS name and ROS
# type name, keyless (entity kinds 0x03/0x04: writer/reader without key), in the default partition;
# /tf and /clock samples in plain CDR, little endian (XCDR1: encapsulation CDR_LE 0x0001).
#
#   ros_tshark_test.sh RIGIDD ROS_FASTDDS_PEER SOURCE_DIR
set -euo pipefail
rigidd=$1
peer=$2
src=$3
here=$(cd "$(dirname "$0")" && pwd)
if [[ ${RIGID_IN_NETNS:-} != 1 ]]; then exec "$here/in_netns.sh" "$0" "$@"; fi
fail() { echo "ros_tshark_test: FAILED: $*"; exit 1; }
command -v dumpcap > /dev/null && command -v tshark > /dev/null ||
  fail "tshark is not installed (apt-get install tshark; scripts/dev setup installs it)"

dir=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2> /dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2> /dev/null || true; done
  rm -rf "$dir"
}
trap cleanup EXIT
export CYCLONEDDS_URI=file://$src/config/cyclonedds-ros.xml

dumpcap -q -i lo -w "$dir/cap.pcapng" > "$dir/dumpcap.log" 2>&1 &
capture=$!
pids+=($capture)
# dumpcap says nothing on stdout once it captures; its file appears when it has started.
for _ in $(seq 100); do [[ -s $dir/cap.pcapng ]] && break; sleep 0.05; done
[[ -s $dir/cap.pcapng ]] || fail "dumpcap did not start: $(cat "$dir/dumpcap.log")"
"$rigidd" --scene "$here/scenes/ros_shapes.pbtxt" --transport dds --ros > "$dir/rigidd.log" 2>&1 &
server=$!
pids+=($server)
timeout 30 "$peer" 0 listen || { cat "$dir/rigidd.log"; fail "the Fast DDS listener failed"; }
kill "$server"
wait "$server" || true
sleep 0.2
kill "$capture"
wait "$capture" || true

# What the capture carries (rtps_capture.py: one line per endpoint announced and per sample).
tshark -r "$dir/cap.pcapng" -Y rtps -T pdml 2> /dev/null | python3 "$here/rtps_capture.py" | sort > "$dir/lines"
grep '^endpoint|' "$dir/lines" | cut -d'|' -f2- | sort -u > "$dir/endpoints"
grep '^sample|' "$dir/lines" | cut -d'|' -f2- > "$dir/samples"
status=0
expect() {  # TOPIC TYPE KIND: announced by someone with that kind, in the default partition
  grep -qxF "$1|$2|$3|" "$dir/endpoints" || { echo "ros_tshark_test: FAILED: no $1 ($2, kind $3) in discovery"; status=1; }
}
m() { echo "$1::msg::dds_::$2_"; }
expect rt/tf "$(m tf2_msgs TFMessage)" 0x03
expect rt/tf_static "$(m tf2_msgs TFMessage)" 0x03
expect rt/clock "$(m rosgraph_msgs Clock)" 0x03
expect rt/rigid/markers "$(m visualization_msgs MarkerArray)" 0x03
expect ros_discovery_info "$(m rmw_dds_common ParticipantEntitiesInfo)" 0x03
for body in ball twin spinner arm/link_1 pill egg dot; do
  expect "rt/rigid/$body/wrench" "$(m geometry_msgs WrenchStamped)" 0x04
done
for s in get_simulator_features:GetSimulatorFeatures get_simulation_state:GetSimulationState \
  set_simulation_state:SetSimulationState step_simulation:StepSimulation \
  reset_simulation:ResetSimulation get_entity_state:GetEntityState \
  set_entity_state:SetEntityState get_entities:GetEntities; do
  expect "rq/rigidd/${s%%:*}Request" "simulation_interfaces::srv::dds_::${s#*:}_Request_" 0x04
  expect "rr/rigidd/${s%%:*}Reply" "simulation_interfaces::srv::dds_::${s#*:}_Response_" 0x03
done
# Every ROS endpoint on the wire keyless, in the default partition.
while IFS='|' read -r topic type kind parts; do
  [[ $topic =~ ^(rt|rq|rr)/ || $topic == ros_discovery_info ]] || continue
  [[ $kind == 0x03 || $kind == 0x04 ]] || { echo "ros_tshark_test: FAILED: $topic has entity kind $kind (keyed?)"; status=1; }
  [[ -z $parts ]] || { echo "ros_tshark_test: FAILED: $topic in partition(s) $parts"; status=1; }
done < "$dir/endpoints"
grep -q '^rt/rigid/my.box/' "$dir/endpoints" && { echo "ros_tshark_test: FAILED: a wrench topic for my.box"; status=1; }

# /tf and /clock samples in plain CDR, little endian (CDR_LE, 0x0001), and in nothing else.
for topic in rt/tf rt/clock; do
  n=$(grep -c "^$topic|0x0001$" "$dir/samples" || true)
  ((n >= 5)) || { echo "ros_tshark_test: FAILED: $n $topic samples in CDR_LE (0x0001)"; status=1; }
  other=$(grep "^$topic|" "$dir/samples" | grep -vc '|0x0001$' || true)
  ((other == 0)) || { echo "ros_tshark_test: FAILED: $other $topic samples in another encapsulation"; status=1; }
done
if [[ $status != 0 ]]; then
  echo "--- endpoints"; cat "$dir/endpoints"
  echo "--- samples"; sort "$dir/samples" | uniq -c
  exit 1
fi
echo "ros_tshark_test: ok ($(wc -l < "$dir/endpoints") endpoints, $(wc -l < "$dir/samples") samples)"
