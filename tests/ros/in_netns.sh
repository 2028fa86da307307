#!/usr/bin/env bash
# Runs COMMAND... in a network namespace of its own, whose loopback carries multicast as ROS 2's
# discovery needs (SPDP on 239.255.0.1): the ROS tests' DDS processes find each other there and
# nothing of the host's (other tests, other people's processes), and the host's lo is left as it
# is. Needs root, or unprivileged user namespaces (then it maps the caller to root inside).
#
#   in_netns.sh COMMAND [ARG...]
set -euo pipefail
if [[ ${RIGID_IN_NETNS:-} != 1 ]]; then
  self=$(readlink -f "$0")
  if [[ $(id -u) -eq 0 ]]; then
    exec unshare --net env RIGID_IN_NETNS=1 "$self" "$@"
  fi
  exec unshare --map-root-user --net env RIGID_IN_NETNS=1 "$self" "$@"
fi
ip link set lo up multicast on
ip route add 224.0.0.0/4 dev lo
exec "$@"
