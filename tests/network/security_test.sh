#!/usr/bin/env bash
# DDS Security end to end, with the real robot_server and net_probe observers, inside a private
# network namespace (LAN profile with multicast on the namespace's loopback only).
#
# Usage: security_test.sh ROBOT_SERVER NET_PROBE SOURCE_DIR
#
# Checks:
#   1. a legitimate observer receives video and scans, and its cmd_vel writer is refused;
#   2. a participant without credentials receives nothing;
#   3. a participant whose certificates come from a foreign CA receives nothing;
#   4. a participant with a genuine identity but forged permissions (allowing cmd_vel, signed
#      by a permissions CA of its own) receives nothing;
#   5. a pilot whose certificate was revoked (revoke.sh) receives nothing, even with the CRL
#      removed from its own profile, and cannot start at all with it.
# Exit 77 (CTest: skipped) when network namespaces cannot be created.
set -euo pipefail
[ $# -eq 3 ] || { echo "usage: security_test.sh ROBOT_SERVER NET_PROBE SOURCE_DIR" >&2; exit 2; }
robot_server=$1; net_probe=$2; src=$3
here=$(cd "$(dirname "$0")" && pwd)
"$here/netns.sh" check || exit 77

ns="mostar_sec_$$"
work=$(mktemp -d /tmp/mostar_sec_XXXXXX)
robot_pid=""
cleanup() {
  [ -z "$robot_pid" ] || kill "$robot_pid" 2>/dev/null || true
  sleep 1
  pkill -9 -f "$work" 2>/dev/null || true
  [ -z "$robot_pid" ] || kill -9 "$robot_pid" 2>/dev/null || true
  [ -z "$robot_pid" ] || wait "$robot_pid" 2>/dev/null || true
  ip netns del "$ns" 2>/dev/null || true
  if [ "${KEEP_WORK:-0}" = 1 ]; then echo "work dir kept: $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT
trap "exit 1" INT TERM
ip netns add "$ns"
ip -n "$ns" link set lo up
ip -n "$ns" link set lo multicast on
ip -n "$ns" route add 224.0.0.0/4 dev lo
domain=$((100 + $$ % 100))
profile="$src/deploy/dds/lan.xml"
pki="$src/deploy/security/make_pki.sh"

# Genuine PKI: the robot, one observer, one pilot that gets revoked.
"$pki" "$work/pki" --profile "$profile" --observer watcher --pilot revoked_pilot >/dev/null
"$src/deploy/security/revoke.sh" "$work/pki" revoked_pilot >/dev/null
# Foreign PKI: same names, another CA.
"$pki" "$work/rogue" --profile "$profile" --observer watcher >/dev/null
# Forged permissions: the genuine watcher identity with permissions (incl. cmd_vel) signed by
# the foreign permissions CA.
mkdir "$work/forged"
cp "$work/pki/"{identity_ca.cert.pem,identity_ca.crl.pem,watcher.cert.pem,watcher.key.pem} "$work/forged/"
cp "$work/rogue/"{permissions_ca.cert.pem,governance.p7s} "$work/forged/"
sed -e 's|<topic>rt/mostar/estop</topic>|<topic>rt/mostar/estop</topic><topic>rt/mostar/cmd_vel</topic>|' \
  "$work/pki/watcher.permissions.xml" > "$work/forged/watcher.permissions.xml"
openssl smime -sign -text -in "$work/forged/watcher.permissions.xml" \
  -out "$work/forged/watcher.permissions.p7s" \
  -signer "$work/rogue/permissions_ca.cert.pem" -inkey "$work/rogue/permissions_ca.key.pem"
sed "s|$work/pki|$work/forged|g" "$work/pki/watcher.xml" > "$work/forged/watcher.xml"
# The revoked pilot's own participant refuses to start with the CRL in place; an attacker would
# drop the CRL from the profile, so test the robot's side with the CRL removed.
grep -v "identity_crl" "$work/pki/revoked_pilot.xml" > "$work/revoked_pilot_no_crl.xml"

ip netns exec "$ns" "$robot_server" --domain "$domain" --dds-profile "$work/pki/robot.xml" \
  --config "$src/deploy/config/server_sim.pbtxt" --source test_pattern \
  > "$work/robot.log" 2>&1 &
robot_pid=$!
sleep 1

probe() {  # name, profile, extra args...
  local name=$1 prof=$2; shift 2
  ip netns exec "$ns" "$net_probe" --domain "$domain" --dds-profile "$prof" --id "$name" \
    --duration-s 8 "$@" > "$work/$name.out" 2> "$work/$name.err" &
}
probe observer "$work/pki/watcher.xml" --try-command-writer
probe plain "$profile" --insecure
probe foreign "$work/rogue/watcher.xml"
probe forged "$work/forged/watcher.xml" --try-command-writer
probe revoked "$work/revoked_pilot_no_crl.xml"
probe revoked_local "$work/pki/revoked_pilot.xml"
wait $(jobs -p | grep -v "^$robot_pid$") 2>/dev/null || true
# `wait` above may also have waited for the robot if job control mixed them up: check it lives.
kill -0 "$robot_pid" 2>/dev/null || { cat "$work/robot.log"; echo "FAIL: robot_server died"; exit 1; }

failures=0
field() { sed -n "s/.* $2=\([^ ]*\).*/\1/p" "$work/$1.out"; }
expect() {  # description, condition
  if eval "$2"; then echo "ok: $1"; else echo "FAIL: $1 ($2)"; failures=$((failures + 1)); fi
}
for n in observer plain foreign forged revoked revoked_local; do
  echo "$n: $(cat "$work/$n.out" 2>/dev/null) $(grep -c . "$work/$n.err" 2>/dev/null || true) stderr lines"
done
expect "authenticated observer receives video" '[ "$(field observer left)" -ge 20 ]'
expect "authenticated observer receives scans" '[ "$(field observer scan)" -ge 5 ]'
expect "observer may not write cmd_vel" '[ "$(field observer command_writer)" = refused ]'
expect "no credentials: no data" '[ "$(field plain left)" = 0 ] && [ "$(field plain scan)" = 0 ]'
expect "foreign CA: no data" '[ "$(field foreign left)" = 0 ] && [ "$(field foreign scan)" = 0 ]'
expect "forged permissions: no data" '[ "$(field forged left)" = 0 ] && [ "$(field forged scan)" = 0 ]'
expect "revoked certificate: no data" '[ "$(field revoked left)" = 0 ] && [ "$(field revoked scan)" = 0 ]'
expect "revoked certificate: own participant refuses to start" '! grep -q "^probe:" "$work/revoked_local.out"'
# The robot's log says who came and went (the probes ended above; their farewell may take a
# moment to arrive).
for i in $(seq 50); do grep -q "(announcing 'watcher') left" "$work/robot.log" && break; sleep 0.1; done
expect "the robot logs the certificate the observer announces" \
  'grep -q "discovered, announcing the certificate of .watcher. (a claim" "$work/robot.log"'
expect "the robot logs the observer's authentication, the announced id as unproven" \
  'grep -q "authenticated by a certificate of the identity CA (announcing .watcher., unproven" "$work/robot.log"'
expect "the robot logs that the observer left" 'grep -q "(announcing .watcher.) left" "$work/robot.log"'
expect "the robot logs the failed authentications" \
  'grep -q "failed authentication" "$work/robot.log"'
[ "$failures" -eq 0 ] || { echo "robot log:"; tail -20 "$work/robot.log"; exit 1; }
echo "security_test: all checks passed"
