#!/bin/sh
# Runs playback_test.mjs (see there); fails without Debian's chromium or `npm ci` in tests/view (scripts/dev installs both).
# usage: playback_test.sh NODE RIGIDD RIGID_RECORD RIGID_VIEW SCENE OUTDIR RIGIDCTL
here=$(dirname "$0")
node=$1
shift
if [ ! -x /usr/bin/chromium ]; then
  echo "view_playback_browser_test: FAILED: /usr/bin/chromium is missing (apt-get install chromium)"
  exit 1
fi
if [ ! -d "$here/node_modules/playwright-core" ]; then
  echo "view_playback_browser_test: FAILED: playwright-core is missing (npm ci --prefix $here)"
  exit 1
fi
exec timeout -k 5 85 "$node" "$here/playback_test.mjs" "$@"
