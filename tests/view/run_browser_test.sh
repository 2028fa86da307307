#!/bin/sh
# Runs one of tests/view's browser tests under a time limit; fails, saying why, without Debian's
# chromium or `npm ci` in tests/view (scripts/dev installs both).
# usage: run_browser_test.sh NAME SCRIPT.mjs SECONDS NODE ARGS...
here=$(dirname "$0")
name=$1
script=$2
seconds=$3
node=$4
shift 4
if [ ! -x /usr/bin/chromium ]; then
  echo "$name: FAILED: /usr/bin/chromium is missing (apt-get install chromium)"
  exit 1
fi
if [ ! -d "$here/node_modules/playwright-core" ]; then
  echo "$name: FAILED: playwright-core is missing (npm ci --prefix $here)"
  exit 1
fi
exec timeout -k 5 "$seconds" "$node" "$here/$script" "$@"
