#!/usr/bin/env bash
# rigid-record export --mcap, checked by an independent reader (check_mcap.mjs: @mcap/core and
# protobufjs, pinned in package-lock.json). A deterministic recording is made without rigidd
# (tests/support/synthetic_recording: every shape kind, edge-case doubles), exported to CSV (the
# reference: 17 significant digits round-trip every double) and to MCAP, and the MCAP is read
# back: index, summary and every CRC valid, every state there, poses bit for bit, every message
# decoded from its embedded schema; its chunks zstd-compressed (fzstd decompresses them), and
# uncompressed with --compress none. Then the refusals: an existing OUT without --force, a journal.
#
#   mcap_export_test.sh RIGID_RECORD SYNTHETIC_RECORDING
#
# Needs node and tests/mcap/node_modules: installed here with `npm ci` if missing (the registry
# is then needed once; offline with node_modules already there). Exit 77 (skipped): no node, or
# node_modules missing and npm ci failed: a failure, not a skip (scripts/dev installs them).
set -euo pipefail
record=$1
synthetic=$2
here=$(cd "$(dirname "$0")" && pwd)

if ! command -v node > /dev/null; then
  echo "mcap_export_test: FAILED: node is not installed (apt-get install nodejs npm)"
  exit 1
fi
if [[ ! -f $here/node_modules/@mcap/core/package.json || ! -f $here/node_modules/protobufjs/package.json ||
      ! -f $here/node_modules/fzstd/package.json ]]; then
  # --ignore-scripts: nothing from the registry runs at install.
  if ! (cd "$here" && timeout 300 npm ci --ignore-scripts --no-audit --no-fund > /dev/null); then
    echo "mcap_export_test: FAILED: tests/mcap/node_modules missing and npm ci failed (offline?)"
    exit 1
  fi
fi

dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "mcap_export_test: FAILED: $*" >&2; exit 1; }

states=300
bodies=200   # 300 x 200 bodies: about 12 MB, several chunks
"$synthetic" "$dir/rec.rlog" "$states" "$bodies" > /dev/null
# The count of states as rigid-record info reports it.
info_states=$("$record" info "$dir/rec.rlog" | sed -n 's/^records: \([0-9]*\) states.*/\1/p')
[[ $info_states == "$states" ]] || fail "rigid-record info reports '$info_states' states, not $states"

"$record" export "$dir/rec.rlog" --csv "$dir/rec.csv" > /dev/null
out=$("$record" export "$dir/rec.rlog" --mcap "$dir/rec.mcap")
[[ $out == "$dir/rec.mcap: $states states from $dir/rec.rlog" ]] || fail "export said: $out"
timeout 120 node "$here/check_mcap.mjs" "$dir/rec.mcap" "$dir/rec.csv" "$info_states" "$bodies" zstd
# Uncompressed chunks on request, read the same.
"$record" export "$dir/rec.rlog" --mcap "$dir/plain.mcap" --compress none > /dev/null
timeout 120 node "$here/check_mcap.mjs" "$dir/plain.mcap" "$dir/rec.csv" "$info_states" "$bodies" none
(( $(stat -c %s "$dir/rec.mcap") < $(stat -c %s "$dir/plain.mcap") )) || fail "zstd chunks no smaller"

# An existing OUT is refused (exit 1, one line) and left as it was; --force replaces it.
before=$(cksum < "$dir/rec.mcap")
set +e
err=$("$record" export "$dir/rec.rlog" --mcap "$dir/rec.mcap" 2>&1 > /dev/null)
status=$?
set -e
[[ $status == 1 && $err == "rigid-record: $dir/rec.mcap already exists (--force overwrites it)" ]] ||
  fail "overwrite without --force: status $status, '$err'"
[[ $(cksum < "$dir/rec.mcap") == "$before" ]] || fail "the refused export changed OUT"
"$record" export "$dir/rec.rlog" --mcap "$dir/rec.mcap" --force > /dev/null
[[ ! -e $dir/rec.mcap.tmp ]] || fail "OUT.tmp left behind"

# A journal holds no states: one line, exit 1, no OUT and no OUT.tmp.
"$synthetic" "$dir/run.journal" 5 3 journal > /dev/null
set +e
err=$("$record" export "$dir/run.journal" --mcap "$dir/journal.mcap" 2>&1 > /dev/null)
status=$?
set -e
[[ $status == 1 && $err == *"is a journal (rigidd --journal)"* && $(wc -l <<< "$err") == 1 ]] ||
  fail "journal: status $status, '$err'"
[[ ! -e $dir/journal.mcap && ! -e $dir/journal.mcap.tmp ]] || fail "a journal's export left a file"

# A file that is no log at all: one line, exit 1.
echo "not a log" > "$dir/junk"
set +e
err=$("$record" export "$dir/junk" --mcap "$dir/junk.mcap" 2>&1 > /dev/null)
status=$?
set -e
[[ $status == 1 && $(wc -l <<< "$err") == 1 && ! -e $dir/junk.mcap ]] || fail "junk: status $status, '$err'"
echo "mcap_export_test: ok"
