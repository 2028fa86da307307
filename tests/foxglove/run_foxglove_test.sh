#!/bin/sh
# Runs foxglove_test.mjs under a time limit; fails, saying why, without `npm ci` in tests/foxglove
# (scripts/dev runs it).
# usage: run_foxglove_test.sh NODE RIGIDD RIGID_VIEW RIGIDCTL SCENE
here=$(dirname "$0")
node=$1
shift
if [ ! -d "$here/node_modules/@foxglove/ws-protocol" ]; then
  echo "foxglove_client_test: FAILED: @foxglove/ws-protocol is missing (npm ci --prefix $here)"
  exit 1
fi
exec timeout -k 5 120 "$node" "$here/foxglove_test.mjs" "$@"
