#!/usr/bin/env bash
# The shipped systemd units and udev rules: the units verify (systemd-analyze verify, with
# ExecStart pointed at an existing program: the real binaries are not installed here) and keep
# their hardening; the laser and motor-board nodes belong to the group mostar with mode 0660.
#
# Usage: deploy_units_test.sh SOURCE_DIR
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: deploy_units_test.sh SOURCE_DIR" >&2; exit 2; }
src=$1
work=$(mktemp -d /tmp/mostar_units_XXXXXX)
trap 'rm -rf "$work"' EXIT

failures=0
check() {  # description, condition
  if eval "$2"; then echo "ok: $1"; else echo "FAIL: $1 ($2)"; failures=$((failures + 1)); fi
}
has() { grep -qx "$2" "$src/deploy/$1"; }

robot=systemd/mostar-robot-server.service
relay=systemd/mostar-relay.service
for unit in "$robot" "$relay"; do
  for line in "ProtectProc=invisible" "ProcSubset=pid" "IPAddressDeny=any" \
      "IPAddressAllow=localhost 10.77.0.0/24|IPAddressAllow=10.77.0.0/24 localhost" \
      "User=mostar" "Group=mostar" "NoNewPrivileges=yes" "CapabilityBoundingSet="; do
    check "$unit has $line" 'grep -qxE "$line" "$src/deploy/$unit"'
  done
done
# The overlay's TCP fallback (docs/networking.md): no fixed user, no capability but the hub's
# low port, no devices.
tunnel=systemd/mostar-wg-tcp.service
tunnel_hub=systemd/mostar-wg-tcp-hub.service
for unit in "$tunnel" "$tunnel_hub"; do
  for line in "ProtectProc=invisible" "ProcSubset=pid" "DynamicUser=yes" "NoNewPrivileges=yes" \
      "PrivateDevices=yes" "Restart=always"; do
    check "$unit has $line" 'has "$unit" "$line"'
  done
done
check "the peer's tunnel has no capability" 'has "$tunnel" "CapabilityBoundingSet="'
check "the hub's tunnel may bind a low port and do nothing else privileged" \
  'has "$tunnel_hub" "CapabilityBoundingSet=CAP_NET_BIND_SERVICE"'
check "the robot's devices are closed but for its own" 'has "$robot" "DevicePolicy=closed"'
for device in /dev/lms200 /dev/mostar-drive; do
  check "the robot server may open $device" 'has "$robot" "DeviceAllow=$device rw"'
done
check "the robot server may open no serial port by class" \
  '! grep -qE "^DeviceAllow=char-tty" "$src/deploy/$robot"'
check "the relay has no devices" 'has "$relay" "PrivateDevices=yes"'
# The hub's endpoint keeper: reads WireGuard's state and writes the state folder, nothing else.
endpoints=systemd/mostar-hub-endpoints.service
endpoints_timer=systemd/mostar-hub-endpoints.timer
for line in "CapabilityBoundingSet=CAP_NET_ADMIN" "ProtectSystem=strict" \
    "ReadWritePaths=/var/lib/mostar" "IPAddressDeny=any" "NoNewPrivileges=yes"; do
  check "$endpoints has $line" 'has "$endpoints" "$line"'
done
check "the endpoints are saved every minute while the hub's overlay runs" \
  'has "$endpoints_timer" "OnUnitActiveSec=1min" && has "$endpoints_timer" "WantedBy=wg-quick@mostar-hub.service"'
check "the laser node is the group mostar's, mode 0660" \
  'grep -E "^SUBSYSTEM==\"tty\".*SYMLINK\+=\"lms200\"" "$src/deploy/udev/60-mostar-lms200.rules" | grep -q "GROUP=\"mostar\"" &&
   grep -E "^SUBSYSTEM==\"tty\".*SYMLINK\+=\"lms200\"" "$src/deploy/udev/60-mostar-lms200.rules" | grep -q "MODE=\"0660\""'
check "the motor board node is the group mostar's, mode 0660" \
  'grep -E "^SUBSYSTEM==\"tty\".*SYMLINK\+=\"mostar-drive\"" "$src/deploy/udev/70-mostar-drive.rules" | grep -q "GROUP=\"mostar\"" &&
   grep -E "^SUBSYSTEM==\"tty\".*SYMLINK\+=\"mostar-drive\"" "$src/deploy/udev/70-mostar-drive.rules" | grep -q "MODE=\"0660\""'

if command -v systemd-analyze >/dev/null; then
  for unit in "$robot" "$relay" "$tunnel" "$tunnel_hub" "$endpoints" "$endpoints_timer"; do
    name=$(basename "$unit")
    sed 's|^ExecStart=/usr/[^ ]*|ExecStart=/bin/true|' "$src/deploy/$unit" > "$work/$name"
    out=$(systemd-analyze verify "$work/$name" 2>&1) && status=0 || status=$?
    check "systemd-analyze verify $name: no complaint" '[ "$status" = 0 ] && [ -z "$out" ]'
    [ -z "$out" ] || echo "$out"
  done
else
  echo "skip: systemd-analyze is missing"
fi
if command -v udevadm >/dev/null && udevadm verify --help >/dev/null 2>&1; then
  check "udevadm verify accepts the rules" 'udevadm verify "$src"/deploy/udev/*.rules >/dev/null 2>&1'
fi

[ "$failures" -eq 0 ] || { echo "deploy_units_test: $failures check(s) failed"; exit 1; }
echo "deploy_units_test: all checks passed"
