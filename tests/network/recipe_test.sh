#!/usr/bin/env bash
# docs/networking.md, "The Internet deployment: From zero", followed step by step on the
# installed layout (`cmake --install` into a folder: /usr/bin, /usr/share/mostar, /etc/mostar
# under it), in network namespaces: the hub, the robot behind NAT A, alice (pilot) and carol
# (observer) behind NAT B (tests/network/nat_topology.sh, no delay). By-hand equivalents where
# namespaces cannot run systemd or share one file system:
#   - `systemctl enable --now X` is the unit's ExecStart line run in the host's namespace;
#   - every host's /etc/mostar is one folder ($work/etc/mostar), each bundle copied into it;
#   - domains: D and D + 1 (per run) instead of 0 and 1;
#   - the copied simulator configuration's scene is given by its installed path (the installed
#     folder is not /usr/share/mostar here, so the fallback of config_paths.h cannot find it).
# Also: the robot's service and carol's console started before their overlays (boot order),
# the robot's overlay restarted under the running server (wg-quick down, up), and a second
# observer, dave behind NAT C, added while everything runs (the scripts again with his name,
# `wg syncconf` on the hub), then the hub restarted (its relay stopped with its overlay and
# started after it, as the units' BindsTo and WantedBy do; the hub's state folder, where it
# keeps its peers' endpoints across the restart, is $work/var instead of /var/lib/mostar).
# Checked: each --check-config as the recipe runs it (the robot's before its overlay names only
# the missing address); the pilot gets the lease and drives, also after the overlay restart
# and after the hub's restart (within 12 s: without the endpoints kept, the peers' WireGuard
# starts a new handshake only 15 s after the hub went silent);
# alice, carol and dave decode video through the relay; the robot has one reader of its H.264
# stream.
#
# Usage: recipe_test.sh BUILD_DIR NETEM_RELAY SOURCE_DIR   (as root)
# Exit 77 (CTest: skipped) where namespaces, wireguard-go or /dev/net/tun are missing.
set -euo pipefail
[ $# -eq 3 ] || { echo "usage: recipe_test.sh BUILD_DIR NETEM_RELAY SOURCE_DIR" >&2; exit 2; }
build=$1; src=$3
here=$(cd "$(dirname "$0")" && pwd)
"$here/netns.sh" check || exit 77
for tool in nft wg wg-quick wireguard-go openssl xvfb-run; do
  command -v "$tool" >/dev/null || { echo "recipe_test: $tool is missing" >&2; exit 77; }
done
[ -c /dev/net/tun ] || { echo "recipe_test: /dev/net/tun is missing" >&2; exit 77; }
source "$here/lib.sh"

prefix="mr$$"
tag=$(echo -n "$prefix" | md5sum | cut -c1-4)
work=$(mktemp -d /tmp/mostar_recipe_XXXXXX)
export WG_QUICK_USERSPACE_IMPLEMENTATION=wireguard-go
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  sleep 1
  pkill -9 -f "$work" 2>/dev/null || true
  for p in "${pids[@]}"; do kill -9 "$p" 2>/dev/null || true; wait "$p" 2>/dev/null || true; done
  "$here/nat_topology.sh" down "$prefix" >/dev/null 2>&1 || true
  if [ "${KEEP_WORK:-0}" = 1 ]; then echo "work dir kept: $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT
trap "exit 1" INT TERM
fail_now() {
  echo "FAIL: $*"
  for f in "$work"/*.log; do echo "--- $f"; tail -15 "$f"; done
  exit 1
}
# Runs a command that must succeed (a --check-config); on failure prints its problems.
passes() {  # description, command...
  local what=$1 out
  shift
  if out=$("$@" 2>&1); then
    echo "ok: $what"
  else
    echo "FAIL: $what"
    grep -A1 "^PROBLEM" <<<"$out" || echo "$out" | tail -5
    failures=$((failures + 1))
  fi
}
# Up to $2 tenths of a second until the shell condition $1 holds.
wait_for() {
  local i
  for ((i = 0; i < $2; i++)); do eval "$1" && return 0; sleep 0.1; done
  return 1
}

# --- the installed layout
root=$work/root
DESTDIR=$root cmake --install "$build" --prefix /usr >"$work/install.log" 2>&1 ||
  fail_now "cmake --install"
bin=$root/usr/bin
share=$root/usr/share/mostar
etc=$work/etc/mostar
pki_dir=$etc/pki
mkdir -p "$pki_dir" "$work/var"
domain=$((100 + RANDOM % 100))
observer_domain=$((domain + 1))

"$here/nat_topology.sh" up "$prefix" --log-dir "$work" >/dev/null || fail_now "topology"
ns() { echo "${prefix}_$1"; }  # hub robot pilot (alice) obs1 (carol) obs2 (dave)

# --- 1. the administrator's computer: overlay, then PKI
"$bin/mostar-make-overlay" "$work/site/overlay" --hub-endpoint 198.18.0.10:51820 \
  --peer robot --peer alice --observer carol --hub-state-dir "$work/var" \
  >"$work/make_overlay.log" 2>&1 ||
  fail_now "mostar-make-overlay"
"$bin/mostar-make-pki" "$work/site/pki" --profile-dir "$work/site/overlay" \
  --install-dir "$pki_dir" --robot robot --pilot alice --observer carol --relay hub \
  >"$work/make_pki.log" 2>&1 || fail_now "mostar-make-pki"
for h in robot alice carol hub; do cp "$work/site/pki/hosts/$h/"* "$pki_dir/"; done
# wg-quick names the interface after its file: unique per run, at most 15 characters.
wg_conf() { cp "$work/site/overlay/$1" "$work/w$tag$2.conf"; echo "$work/w$tag$2.conf"; }

# --- 2. the hub
ip netns exec "$(ns hub)" wg-quick up "$(wg_conf mostar-hub.conf hub)" >"$work/wg_hub.log" 2>&1 ||
  fail_now "the hub's overlay"
passes "the relay's --check-config passes" \
  ip netns exec "$(ns hub)" "$bin/mostar_relay" --check-config --dds-profile "$pki_dir/hub.xml"
relay() {  # mostar-relay.service's ExecStart line
  ip netns exec "$(ns hub)" "$bin/mostar_relay" --dds-profile "$pki_dir/hub.xml" \
    --robot-domain "$domain" --observer-domain "$observer_domain" --video-repair-period-ms 250 \
    >>"$work/relay.log" 2>&1 &
  relay_pid=$!
  pids+=("$relay_pid")
}
relay

# --- 3. the robot: its configuration from the simulator example, started before its overlay
cp "$share/config/server_sim_h264.pbtxt" "$etc/server.pbtxt"
sed -i -e '/client_id: "\(operator\|operator-2\|observer\|relay\)"/d' \
  -e "s|^scene_file: .*|scene_file: \"$share/scenes/corridor.pbtxt\"|" "$etc/server.pbtxt"
printf 'dds { profile: "%s" video_repair_period_ms: 250 video_repair_deadline_auto: true }\n' \
  "$pki_dir/robot.xml" >>"$etc/server.pbtxt"
out=$(ip netns exec "$(ns robot)" "$bin/robot_server" --check-config --config "$etc/server.pbtxt" 2>&1 || true)
echo "$out" | grep -E "^PROBLEM" || true
check "before the overlay, the robot's --check-config names only its overlay address" \
  '[ "$(grep -c "^PROBLEM" <<<"$out")" = 1 ] && grep -q "interfaceWhiteList is not on this host" <<<"$out"'
ip netns exec "$(ns robot)" "$bin/robot_server" --config "$etc/server.pbtxt" --domain "$domain" \
  --trace "$work/server.csv" >"$work/robot.log" 2>&1 &
robot_pid=$!
pids+=("$robot_pid")
wait_for "grep -q 'waiting up to' '$work/robot.log' 2>/dev/null" 100 || fail_now "robot_server does not wait for its overlay"
ip netns exec "$(ns robot)" wg-quick up "$(wg_conf robot.conf robot)" >"$work/wg_robot.log" 2>&1 ||
  fail_now "the robot's overlay"
check "robot_server sees its overlay come up" \
  "wait_for \"grep -q 'interface addresses are up' '$work/robot.log'\" 100"
passes "with the overlay up the robot's --check-config passes" \
  ip netns exec "$(ns robot)" "$bin/robot_server" --check-config --config "$etc/server.pbtxt"

# --- 4. each operator
ip netns exec "$(ns pilot)" wg-quick up "$(wg_conf alice.conf alice)" >"$work/wg_alice.log" 2>&1 ||
  fail_now "alice's overlay"
# Every peer's first handshake with the hub (its keepalive starts it), as `wg show` would tell.
handshake() {  # peer
  local h=$1 n
  case $h in alice) n=$(ns pilot) ;; carol) n=$(ns obs1) ;; dave) n=$(ns obs2) ;; *) n=$(ns robot) ;; esac
  wait_for "[ \"\$(ip netns exec $n wg show w$tag$h latest-handshakes | awk '{print \$2}')\" -gt 0 ] 2>/dev/null" 150 ||
    fail_now "no WireGuard handshake from $h"
}
for h in robot alice; do handshake "$h"; done
alice=(--dds-profile "$pki_dir/alice.xml" --role pilot --video-via-relay --domain "$domain"
  --video-domain "$observer_domain")
carol=(--dds-profile "$pki_dir/carol.xml" --role observer --domain "$observer_domain")
passes "alice's --check-config passes" \
  ip netns exec "$(ns pilot)" "$bin/operator_client" "${alice[@]}" --headless --check-config
duration=45  # s: the consoles then end by themselves and print their reports
console_pids=()
console() {  # namespace, log, arguments...
  local n=$1 log=$2 seconds=${console_seconds:-$duration}
  shift 2
  ip netns exec "$n" xvfb-run -a -s "-screen 0 640x480x24 -noreset" "$bin/operator_client" \
    --headless --window-size 320x240 --duration "$seconds" \
    --calibration "$share/config/calibration_sim.pbtxt" "$@" >"$log" 2>&1 &
  pids+=($!)
  console_pids+=($!)
}
console "$(ns pilot)" "$work/alice.log" "${alice[@]}" --drive 0.1,0 --trace "$work/alice.csv"
# carol's console starts before her overlay (a laptop whose WireGuard comes up later): it waits
# for its address, then watches like the others.
console "$(ns obs1)" "$work/carol.log" "${carol[@]}" --trace "$work/carol.csv"
check "carol's console waits for her overlay address" \
  'wait_for "grep -q \"waiting up to .* for address\" \"$work/carol.log\"" 150'
ip netns exec "$(ns obs1)" wg-quick up "$(wg_conf carol.conf carol)" >"$work/wg_carol.log" 2>&1 ||
  fail_now "carol's overlay"
handshake carol
drove_after() {  # a drive output above zero in the server's trace after epoch ns $1
  awk -F, -v t="$1" '$1 == "drive_out_mmps" && $2 > t && $3 > 0 { found = 1 } END { exit !found }' \
    "$work/server.csv" 2>/dev/null
}
check "alice gets the lease and drives" 'wait_for "drove_after 0" 400'

# --- 5. an observer added later (dave, behind NAT C): steps 1, 2 (the hub's peers reloaded)
# and 4 for him alone; the relay, the robot and the other consoles keep running.
"$bin/mostar-make-overlay" "$work/site/overlay" --hub-endpoint 198.18.0.10:51820 \
  --observer dave --hub-state-dir "$work/var" >>"$work/make_overlay.log" 2>&1 || fail_now "mostar-make-overlay adding dave"
"$bin/mostar-make-pki" "$work/site/pki" --profile-dir "$work/site/overlay" --observer dave \
  >>"$work/make_pki.log" 2>&1 || fail_now "mostar-make-pki adding dave"
cp "$work/site/pki/hosts/dave/"* "$pki_dir/"
hub_conf=$(wg_conf mostar-hub.conf hub)
ip netns exec "$(ns hub)" bash -c "wg syncconf w${tag}hub <(wg-quick strip '$hub_conf')" ||
  fail_now "the hub's overlay reload"
ip netns exec "$(ns obs2)" wg-quick up "$(wg_conf dave.conf dave)" >"$work/wg_dave.log" 2>&1 ||
  fail_now "dave's overlay"
handshake dave
console_seconds=35 console "$(ns obs2)" "$work/dave.log" \
  --dds-profile "$pki_dir/dave.xml" --role observer --domain "$observer_domain"

# --- the robot's overlay restarted under the running server
ip netns exec "$(ns robot)" wg-quick down "$work/w${tag}robot.conf" >>"$work/wg_robot.log" 2>&1
sleep 3
back_ns=$(date +%s%N)
ip netns exec "$(ns robot)" wg-quick up "$work/w${tag}robot.conf" >>"$work/wg_robot.log" 2>&1 ||
  fail_now "the robot's overlay did not come back"
check "alice drives again after the robot's overlay restarted" 'wait_for "drove_after $back_ns" 300'
if drove_after "$back_ns"; then
  first=$(awk -F, -v t="$back_ns" '$1 == "drive_out_mmps" && $2 > t && $3 > 0 { print $2; exit }' "$work/server.csv")
  echo "measured: driving again $(( (first - back_ns) / 1000000 )) ms after the overlay came back"
fi
check "robot_server kept running" 'kill -0 "$robot_pid" 2>/dev/null'

# --- the hub restarted: `systemctl restart wg-quick@mostar-hub` stops the relay first (BindsTo),
# and starts it again once the overlay is up (WantedBy).
kill "$relay_pid"
wait_for "! kill -0 $relay_pid 2>/dev/null" 50 || fail_now "the relay did not end within 5 s of SIGTERM"
ip netns exec "$(ns hub)" wg-quick down "$work/w${tag}hub.conf" >>"$work/wg_hub.log" 2>&1
check "the hub kept its four peers' endpoints" \
  '[ "$(awk "\$2 != \"(none)\"" "$work/var/wg-w${tag}hub.endpoints" 2>/dev/null | wc -l)" = 4 ]'
sleep 3
hub_back_ns=$(date +%s%N)
ip netns exec "$(ns hub)" wg-quick up "$work/w${tag}hub.conf" >>"$work/wg_hub.log" 2>&1 ||
  fail_now "the hub's overlay did not come back"
relay
check "alice drives again within 12 s of the hub's restart" 'wait_for "drove_after $hub_back_ns" 120'
if drove_after "$hub_back_ns"; then
  first=$(awk -F, -v t="$hub_back_ns" '$1 == "drive_out_mmps" && $2 > t && $3 > 0 { print $2; exit }' "$work/server.csv")
  echo "measured: driving again $(( (first - hub_back_ns) / 1000000 )) ms after the hub came back"
fi

# --- the end: the consoles' reports once their --duration is over
for p in "${console_pids[@]}"; do
  wait_for "! kill -0 $p 2>/dev/null" $(( (duration + 30) * 10 )) || true
done
# Video back after a restart: the first image captured after it, at alice and at carol.
video_back() {  # trace, epoch ns: ms from then to the first image captured after it, or ""
  local t
  t=$(awk -F, -v t="$2" '$1 == "left_rx" && $3 > t { print $2; exit }' "$1" 2>/dev/null || true)
  [ -z "$t" ] || echo $(( (t - $2) / 1000000 ))
}
v=$(video_back "$work/alice.csv" "$back_ns")
[ -z "$v" ] || echo "measured: video back $v ms after the overlay came back"
for who in alice carol; do
  v=$(video_back "$work/$who.csv" "$hub_back_ns")
  check "video is back at $who after the hub's restart (${v:-never} ms)" '[ -n "$v" ]'
done
pairs() { sed -n 's/.* pairs_decoded=\([0-9]*\).*/\1/p' "$1" | tail -1; }
a=$(pairs "$work/alice.log"); c=$(pairs "$work/carol.log"); d=$(pairs "$work/dave.log")
# Video flows to each (a count, not a rate: a loaded machine decodes a few pairs per second).
check "alice decoded video through the relay (${a:-no report} pairs)" '[ "${a:-0}" -ge 10 ]'
check "carol decoded video through the relay (${c:-no report} pairs)" '[ "${c:-0}" -ge 10 ]'
check "dave, added later, decoded video through the relay (${d:-no report} pairs)" \
  '[ "${d:-0}" -ge 10 ]'
readers=$(sed -n 's/.*readers of the H.264 stream: \([0-9]*\).*/\1/p' "$work/robot.log" | sort -n | tail -1)
check "the robot's uplink carried the video once (readers of the H.264 stream: ${readers:-none})" \
  '[ "${readers:-0}" = 1 ]'
if [ "$failures" -ne 0 ]; then
  for f in robot relay alice carol dave; do echo "--- $f"; tail -15 "$work/$f.log"; done
  exit 1
fi
echo "recipe_test: all checks passed"
