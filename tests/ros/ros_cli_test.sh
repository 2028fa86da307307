#!/usr/bin/env bash
# rigidd's --ros options: each bad one refused in one line naming the option and its value, exit
# status 2, before anything runs (a rigidd that runs instead is stopped after 20 s and fails the
# test); --check --ros names the bodies ROS cannot reach.
#
#   ros_cli_test.sh RIGIDD SCENE
set -uo pipefail
rigidd=$1
scene=$2
status=0
refused() {  # EXPECTED-PREFIX ARGS...
  local expected=$1 err code
  shift
  err=$(timeout 20 "$rigidd" --scene "$scene" "$@" 2>&1 > /dev/null)
  code=$?
  if [[ $code != 2 || $(wc -l <<< "$err") != 1 || $err != "rigidd: $expected"* ]]; then
    echo "ros_cli_test: FAILED: rigidd $*: status $code, '$err' (expected 'rigidd: $expected...')"
    status=1
  fi
}
refused "--ros-namespace: 'a-b' is not a ROS namespace: the character '-'" --ros --ros-namespace a-b
refused "--ros-namespace: 'lab//x' is not a ROS namespace: an empty token" --ros --ros-namespace lab//x
refused "--ros-namespace: '2lab' is not a ROS namespace: a token starting with the digit '2'" \
  --ros --ros-namespace 2lab
refused "--ros-distro: expected humble, iron, jazzy, kilted or rolling, got 'foxy'" --ros --ros-distro foxy
refused "--ros-namespace and --ros-distro apply to --ros" --ros-namespace lab
refused "--ros speaks on DDS, which --transport leaves out" --ros --transport lcm
err=$(timeout 20 "$rigidd" --check --ros --scene "$scene" 2>&1 > /dev/null)
[[ $? == 0 && $err == *"body 'my.box' has no ROS wrench topic"* ]] ||
  { echo "ros_cli_test: FAILED: --check --ros does not name my.box: '$err'"; status=1; }
[[ $status == 0 ]] && echo "ros_cli_test: ok"
exit $status
