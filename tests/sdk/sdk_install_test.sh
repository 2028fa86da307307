#!/usr/bin/env bash
# The SDK as a user gets it: `cmake --install` of this build into a temporary prefix, then the
# minimal client of docs/sdk.md built out of tree against it, once with CMake (find_package(rigid),
# rigid::client) and once with `pkg-config --cflags --libs rigid`; both binaries must start
# (--help). Also checks that the install holds every program, scene and the DDS config, and that
# the systemd unit names the prefix installed to.
# Usage: sdk_install_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1
source=$2
work=$(mktemp -d "${TMPDIR:-/tmp}/rigid-sdk-test.XXXXXX")
view_pid=
# A failing check exits at once: the rigid-view it started must not outlive the test.
trap '[[ -n $view_pid ]] && kill "$view_pid" 2>/dev/null; rm -rf "$work"' EXIT
prefix=$work/prefix
fail() { echo "FAIL: $*" >&2; exit 1; }

cmake --install "$build" --prefix "$prefix" >"$work/install.log" || {
  cat "$work/install.log" >&2
  fail "cmake --install $build --prefix $prefix"
}
for p in rigidd rigid-sim rigidctl rigid-record rigid-attitude rigid-view rigid-keys; do
  [[ -x $prefix/bin/$p ]] || fail "$prefix/bin/$p not installed"
done
for scene in "$source"/config/scenes/*.pbtxt; do
  [[ -f $prefix/share/rigid/scenes/$(basename "$scene") ]] || fail "scene $(basename "$scene") not installed"
done
[[ -f $prefix/share/rigid/cyclonedds.xml ]] || fail "share/rigid/cyclonedds.xml not installed"
[[ -f $prefix/share/rigid/cyclonedds-ros.xml ]] || fail "share/rigid/cyclonedds-ros.xml not installed"
unit=$prefix/lib/systemd/system/rigidd.service
[[ -f $unit ]] || fail "$unit not installed"
grep -q "^ExecStart=$prefix/bin/rigidd --scene $prefix/share/rigid/scenes/default.pbtxt$" "$unit" ||
  fail "$unit does not name the prefix $prefix: $(grep ExecStart= "$unit")"
grep -q "@" "$unit" && fail "$unit has unconfigured variables"
"$prefix/bin/rigidctl" --help >/dev/null || fail "installed rigidctl --help"

# The installed rigid-view finds its page in share/rigid/web (no build tree beside it): it serves
# index.html and three.js. Bounded: 10 s, stopped by PID.
[[ -f $prefix/share/rigid/web/index.html ]] || fail "share/rigid/web/index.html not installed"
"$prefix/bin/rigid-view" --listen 127.0.0.1:0 --transport lcm >"$work/view.out" 2>"$work/view.err" &
view_pid=$!
url=
for _ in $(seq 100); do
  url=$(grep -ho 'http://127.0.0.1:[0-9]*/' "$work/view.out" "$work/view.err" 2>/dev/null | head -1) || true
  [[ -n $url ]] && break
  sleep 0.1
done
[[ -n $url ]] || fail "installed rigid-view printed no URL: $(cat "$work/view.err")"
get() {  # URL: the body, or nothing
  /usr/bin/python3 -c 'import sys, urllib.request
print(urllib.request.urlopen(sys.argv[1], timeout=5).read().decode())' "$1" 2>/dev/null || true
}
page=$(get "$url")
module=$(get "${url}three/three.module.js")
kill "$view_pid"
wait "$view_pid" || true
view_pid=
[[ $page == *"<html"* ]] || fail "installed rigid-view at $url did not serve its page"
[[ $module == *"REVISION"* ]] || fail "installed rigid-view did not serve three.module.js"

# CMake: find_package(rigid) + rigid::client.
cmake -S "$source/tests/sdk/consumer" -B "$work/cmake-build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" -DRIGID_MINIMAL_CLIENT="$source/clients/examples/minimal_client.cpp" \
  >"$work/configure.log" 2>&1 || { cat "$work/configure.log" >&2; fail "configuring the consumer"; }
cmake --build "$work/cmake-build" >"$work/build.log" 2>&1 || {
  cat "$work/build.log" >&2
  fail "building the minimal client against rigid::client"
}
"$work/cmake-build/minimal_client" --help | grep -q "usage: rigid_minimal_client" ||
  fail "the CMake-built minimal client does not start"

# pkg-config.
pc=$(dirname "$(find "$prefix" -name rigid.pc | head -n 1)")
[[ -f $pc/rigid.pc ]] || fail "rigid.pc not installed"
flags=$(PKG_CONFIG_PATH=$pc pkg-config --cflags --libs rigid) || fail "pkg-config --cflags --libs rigid"
# shellcheck disable=SC2086  # the flags are words
c++ "$source/clients/examples/minimal_client.cpp" -o "$work/minimal_pc" $flags ||
  fail "c++ minimal_client.cpp \$(pkg-config --cflags --libs rigid)"
"$work/minimal_pc" --help | grep -q "usage: rigid_minimal_client" ||
  fail "the pkg-config-built minimal client does not start"
echo "ok: installed to $prefix; the minimal client builds with CMake and with pkg-config and starts"
