#!/usr/bin/env bash
# Tests scripts/rigid-keys in a temporary directory: keystore layout and modes, no secret ever
# printed, signatures that verify, permissions partitions, usage errors, revocation and expiry.
#   bash tests/security/rigid_keys_test.sh [path/to/rigid-keys]
# Exits non-zero at the first failed assertion, naming it.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
tool=${1:-$here/../../scripts/rigid-keys}
[[ -r $tool ]] || { echo "FAIL: no rigid-keys at $tool" >&2; exit 1; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
ks=$work/ks
log=$work/all-output.txt  # everything the tool printed, searched for secrets at the end

fail() { echo "FAIL: $*" >&2; exit 1; }
pass() { echo "ok: $*"; }

# Runs the tool, keeping its stdout in $out, stderr in $err and exit status in $rc.
run() {
  rc=0
  bash "$tool" "$@" >"$work/out" 2>"$work/err" || rc=$?
  out=$(cat "$work/out")
  err=$(cat "$work/err")
  cat "$work/out" "$work/err" >>"$log"
}

expect_ok() {
  run "$@"
  [[ $rc -eq 0 ]] || fail "'$*' exited $rc: $err"
}

# Bad usage: exit 2 and a one-line message that names the offending value.
expect_usage() { # VALUE ARGS...
  local value=$1
  shift
  run "$@"
  [[ $rc -eq 2 ]] || fail "'$*' exited $rc, wanted 2 (stderr: $err)"
  [[ $(printf '%s\n' "$err" | wc -l) -eq 1 ]] || fail "'$*' printed more than one line: $err"
  [[ $err == *"$value"* ]] || fail "'$*' message does not name '$value': $err"
  pass "usage error for '$value'"
}

mode() { stat -c %a "$1"; }

# --- init and add -----------------------------------------------------------------------------
start=$(date -u +%s)
expect_ok init "$ks"
[[ $out == *rigidd* ]] || fail "init output does not mention rigidd: $out"
expect_ok add "$ks" alice --may push:craft,top
expect_ok add "$ks" bob --may push
expect_ok add "$ks" carol --may read
expect_ok add "$ks" dave --may control --may read
pass "init + add"

for f in ca/identity_ca.pem ca/identity_ca.key ca/permissions_ca.pem ca/permissions_ca.key \
  governance.xml governance.p7s; do
  [[ -s $ks/$f ]] || fail "missing $f"
done
for n in rigidd alice bob carol dave; do
  for f in identity_ca.pem permissions_ca.pem governance.p7s cert.pem key.pem permissions.xml \
    permissions.p7s crl.pem policy; do
    [[ -s $ks/identities/$n/$f ]] || fail "missing identities/$n/$f"
  done
done
pass "layout"

# --- list --------------------------------------------------------------------------------------
expect_ok list "$ks"
[[ $(printf '%s\n' "$out" | wc -l) -eq 5 ]] || fail "list wants 5 lines, got: $out"
line() { printf '%s\n' "$out" | awk -v n="$1" '$1 == n'; }
[[ $(line alice) =~ ^alice[[:space:]]+push:craft,top[[:space:]]+[0-9]{4}-[0-9]{2}-[0-9]{2}[[:space:]]+valid$ ]] ||
  fail "list line for alice: $(line alice)"
[[ $(line bob) =~ [[:space:]]push[[:space:]].*valid$ ]] || fail "list line for bob: $(line bob)"
[[ $(line carol) =~ [[:space:]]read[[:space:]].*valid$ ]] || fail "list line for carol: $(line carol)"
# read is implied by control, so the normalised policy drops it.
[[ $(line dave) =~ [[:space:]]control[[:space:]].*valid$ ]] || fail "list line for dave: $(line dave)"
[[ $(line rigidd) =~ [[:space:]]serve[[:space:]].*valid$ ]] || fail "list line for rigidd: $(line rigidd)"
# Default validity 365 days; either side of a midnight (UTC) that fell during this test.
end_a=$(date -u -d "@$((start + 365 * 86400))" +%F)
end_b=$(date -u -d '+365 days' +%F)
[[ $(line alice) == *"$end_a"* || $(line alice) == *"$end_b"* ]] ||
  fail "alice not valid until $end_a: $(line alice)"
[[ $(cat "$ks/identities/alice/policy") == 'push:craft,top' ]] || fail "alice policy file"
pass "list"

# --- modes: keys 0600, directories holding keys 0700 -------------------------------------------
for k in "$ks"/ca/*.key "$ks"/identities/*/key.pem; do
  [[ $(mode "$k") == 600 ]] || fail "$k has mode $(mode "$k")"
done
for d in "$ks" "$ks/ca" "$ks/identities" "$ks"/identities/*/; do
  [[ $(mode "$d") == 700 ]] || fail "$d has mode $(mode "$d")"
done
# Nothing in the keystore is readable by group or others (a symbolic link's own mode means
# nothing: what it points to is checked as itself).
leaky=$(find "$ks" ! -type l -perm /077 -print)
[[ -z $leaky ]] || fail "group/other-accessible files: $leaky"
pass "modes"

# --- signatures ---------------------------------------------------------------------------------
for n in alice rigidd; do
  d=$ks/identities/$n
  openssl smime -verify -in "$d/permissions.p7s" -CAfile "$d/permissions_ca.pem" \
    -out "$work/$n.verified.xml" 2>"$work/verify.err" ||
    fail "permissions.p7s of $n does not verify: $(cat "$work/verify.err")"
  # -text signing adds a Content-Type header; what was signed is the XML itself.
  grep -q "<subject_name>CN=$n</subject_name>" "$work/$n.verified.xml" ||
    fail "signed permissions of $n lack subject CN=$n"
done
openssl smime -verify -in "$ks/governance.p7s" -CAfile "$ks/ca/permissions_ca.pem" \
  -out /dev/null 2>"$work/verify.err" || fail "governance.p7s does not verify: $(cat "$work/verify.err")"
openssl verify -CAfile "$ks/ca/identity_ca.pem" "$ks/identities/alice/cert.pem" >/dev/null ||
  fail "alice's certificate does not verify against the identity CA"
subject=$(openssl x509 -in "$ks/identities/alice/cert.pem" -noout -subject -nameopt RFC2253)
[[ $subject == 'subject=CN=alice' ]] || fail "alice's subject: $subject"
openssl pkey -in "$ks/identities/alice/key.pem" -noout -text 2>/dev/null | grep -q 'prime256v1' ||
  fail "alice's key is not EC prime256v1"
pass "signatures, subject, key type"

# --- permissions partitions for push:craft,top ---------------------------------------------------
perm=$ks/identities/alice/permissions.xml
grep -q '<partition>push/alice/craft</partition>' "$perm" || fail "no push/alice/craft partition"
grep -q '<partition>push/alice/top</partition>' "$perm" || fail "no push/alice/top partition"
[[ $(grep -c '<partition>' "$perm") -eq 2 ]] || fail "alice has partitions other than her two bodies"
grep -q '<topic>\*rigid/wrench</topic>' "$perm" || fail "alice cannot publish *rigid/wrench"
grep -q '<default>DENY</default>' "$perm" || fail "alice's default is not DENY"
# The wrench criterion is a publish criterion with exactly those partitions.
awk '/<publish>/,/<\/publish>/' "$perm" | grep -q 'push/alice/top' || fail "push partitions not under <publish>"
grep -q '<partition>push/bob/\*</partition>' "$ks/identities/bob/permissions.xml" ||
  fail "bob (push, all bodies) lacks push/bob/*"
grep -q '<partition>control/dave</partition>' "$ks/identities/dave/permissions.xml" ||
  fail "dave lacks control/dave"
if grep -q 'rigid/wrench' "$ks/identities/carol/permissions.xml"; then fail "carol (read) may use wrench"; fi
grep -q '<partition>push/\*</partition>' "$ks/identities/rigidd/permissions.xml" ||
  fail "rigidd does not subscribe push/*"
pass "permissions partitions"

# --- usage errors --------------------------------------------------------------------------------
expect_usage 'bad name' add "$ks" 'bad name' --may read
expect_usage 'a/b' add "$ks" 'a/b' --may read
expect_usage 'cr*ft' add "$ks" eve --may 'push:cr*ft'
expect_usage 'x/y' add "$ks" eve --may 'push:ok,x/y'
expect_usage 'admin' add "$ks" eve --may admin
expect_usage 'DIR' add
expect_usage 'DIR' list
expect_usage 'DIR' init
expect_usage '2021-02-30' add "$ks" eve --may read --valid-from 2021-02-30 --valid-until 2021-03-01
expect_usage 'abc' add "$ks" eve --may read --days abc
[[ ! -e $ks/identities/eve ]] || fail "a refused add left identities/eve behind"

# Other failures: exit 1 with a reason.
run add "$ks" alice --may read
[[ $rc -eq 1 && $err == *alice* && $err == *--force* ]] || fail "re-adding alice: rc=$rc $err"
run init "$ks"
[[ $rc -eq 1 ]] || fail "init over an existing keystore exited $rc"
run list "$work/nowhere"
[[ $rc -eq 1 && $err == *nowhere* ]] || fail "list of a missing keystore: rc=$rc $err"
run
[[ $rc -eq 2 && $err == *usage* ]] || fail "no arguments: rc=$rc"
expect_ok --help
[[ $out == *'rigid-keys add DIR NAME'* ]] || fail "--help does not show usage"
pass "failures"

# --- revoke ---------------------------------------------------------------------------------------
serial=$(openssl x509 -in "$ks/identities/bob/cert.pem" -noout -serial | cut -d= -f2)
expect_ok revoke "$ks" bob
for n in alice bob rigidd; do
  openssl crl -in "$ks/identities/$n/crl.pem" -noout -text | grep -qi "Serial Number: *$serial" ||
    fail "bob's serial $serial not in identities/$n/crl.pem"
done
openssl crl -in "$ks/identities/alice/crl.pem" -noout -verify -CAfile "$ks/ca/identity_ca.pem" 2>/dev/null ||
  fail "CRL does not verify against the identity CA"
expect_ok list "$ks"
[[ $(line bob) =~ revoked$ ]] || fail "list does not say bob is revoked: $(line bob)"
[[ $(line alice) =~ valid$ ]] || fail "revoking bob changed alice: $(line alice)"
run revoke "$ks" bob
[[ $rc -eq 1 ]] || fail "revoking bob twice exited $rc"
pass "revoke"

# --- validity in the past ---------------------------------------------------------------------------
expect_ok add "$ks" old --may push:craft --valid-from 2020-01-01 --valid-until 2020-01-02
expect_ok list "$ks"
[[ $(line old) =~ [[:space:]]2020-01-02[[:space:]]+expired$ ]] || fail "old is not expired: $(line old)"
grep -q '<not_after>2020-01-02T23:59:59Z</not_after>' "$ks/identities/old/permissions.xml" ||
  fail "old's permissions validity does not follow its certificate"
pass "expired"

# --- --force replaces and revokes the old certificate --------------------------------------------
old_serial=$(openssl x509 -in "$ks/identities/carol/cert.pem" -noout -serial | cut -d= -f2)
expect_ok add "$ks" carol --may push:craft --force
[[ $(cat "$ks/identities/carol/policy") == push:craft ]] || fail "carol not replaced"
openssl crl -in "$ks/identities/carol/crl.pem" -noout -text | grep -qi "Serial Number: *$old_serial" ||
  fail "carol's replaced certificate is not revoked"
expect_ok list "$ks"
[[ $(line carol) =~ valid$ ]] || fail "carol's new certificate: $(line carol)"
pass "--force"

# --- show never shows the key ------------------------------------------------------------------------
expect_ok show "$ks" alice
[[ $out == *'CN=alice'* && $out == *'push:craft,top'* ]] || fail "show alice: $out"

# --- how rigid/state travels: encrypted by default, else as init --state-protection says ------------
state_protection() {  # GOVERNANCE.xml: the data_protection_kind of the *rigid/state rule
  awk '/\*rigid\/state</{f=1} f && /<data_protection_kind>/{print; exit}' "$1" |
    sed 's/.*<data_protection_kind>\([A-Z]*\)<.*/\1/'
}
[[ $(state_protection "$ks/governance.xml") == ENCRYPT ]] ||
  fail "state not encrypted by default: [$(state_protection "$ks/governance.xml")]"
expect_ok init "$work/ks_none" --state-protection none
[[ $(state_protection "$work/ks_none/governance.xml") == NONE ]] ||
  fail "--state-protection none: $(state_protection "$work/ks_none/governance.xml")"
grep -A8 '\*rigid/scene<' "$work/ks_none/governance.xml" | grep -q '<data_protection_kind>ENCRYPT<' ||
  fail "--state-protection none must leave the scene encrypted"
run init "$work/ks_bad" --state-protection maybe
[[ $rc == 2 && $err == *"'maybe'"* ]] || fail "bad --state-protection: rc $rc, $err"
pass "--state-protection"

# --- nothing secret was ever printed ------------------------------------------------------------------
if grep -q 'PRIVATE KEY' "$log"; then fail "a private key appeared on stdout/stderr"; fi
pass "no secret printed"

echo "rigid-keys: all assertions passed"
