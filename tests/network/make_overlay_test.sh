#!/usr/bin/env bash
# deploy/wan/make_overlay.sh: the hub's and peers' WireGuard configs agree on keys and
# addresses, a peer with its own key never has a private key written for it, a second run adds
# peers and keeps the existing ones, the DDS profiles carry each peer's overlay address, and bad
# arguments are refused with a message.
# Usage: make_overlay_test.sh SOURCE_DIR. Exit 77 (skipped) without wg/wg-quick or python3.
set -euo pipefail
src=$1
gen="$src/deploy/wan/make_overlay.sh"
for tool in wg wg-quick python3; do
  command -v "$tool" >/dev/null || { echo "make_overlay_test: $tool is missing" >&2; exit 77; }
done
umask 077
work=$(mktemp -d /tmp/mostar_overlay_gen_XXXXXX)
trap 'rm -rf "$work"' EXIT
failures=0
check() { if eval "$2"; then echo "ok: $1"; else echo "FAIL: $1"; failures=$((failures + 1)); fi; }
field() { awk -v n="$1" -v c="$2" -F'\t' '$1 == n { print $c }' "$work/out/peers.tsv"; }
conf_value() { sed -n "s/^$2 = //p" "$1" | head -1; }

wg genkey > "$work/bob.key"
bob_pub=$(wg pubkey < "$work/bob.key")
"$gen" "$work/out" --hub-endpoint hub.example.org:51820 --peer robot --peer alice \
  --peer "bob:$bob_pub" --observer dave > "$work/log"
out="$work/out"

check "four peers with consecutive addresses" \
  '[ "$(field robot 2) $(field alice 2) $(field bob 2) $(field dave 2)" = "10.77.0.2 10.77.0.3 10.77.0.4 10.77.0.5" ]'
check "the hub config names every peer's public key once" \
  '[ "$(grep -c "^PublicKey = " "$out/mostar-hub.conf")" = 4 ] &&
   grep -q "^PublicKey = $(field alice 3)$" "$out/mostar-hub.conf" &&
   grep -q "^PublicKey = $bob_pub$" "$out/mostar-hub.conf"'
check "the hub routes each peer's /32 only" \
  '[ "$(grep "^AllowedIPs" "$out/mostar-hub.conf" | tr "\n" " ")" = "AllowedIPs = 10.77.0.2/32 AllowedIPs = 10.77.0.3/32 AllowedIPs = 10.77.0.4/32 AllowedIPs = 10.77.0.5/32 " ]'
check "the hub listens on the endpoint's port and forwards inside the overlay only" \
  '[ "$(conf_value "$out/mostar-hub.conf" ListenPort)" = 51820 ] &&
   grep -q "oifname != %i drop" "$out/mostar-hub.conf"'
check "a peer's private key matches the public key the hub has for it" \
  '[ "$(conf_value "$out/robot.conf" PrivateKey | wg pubkey)" = "$(field robot 3)" ]'
check "every peer dials the hub with a keepalive and routes the whole overlay to it" \
  '[ "$(conf_value "$out/alice.conf" Endpoint)" = hub.example.org:51820 ] &&
   [ "$(conf_value "$out/alice.conf" PublicKey)" = "$(cat "$out/hub.pub")" ] &&
   [ "$(conf_value "$out/alice.conf" AllowedIPs)" = 10.77.0.0/24 ] &&
   [ -n "$(conf_value "$out/alice.conf" PersistentKeepalive)" ]'
check "a peer with its own key gets no private key, only a PostUp that reads it" \
  '! grep -q PrivateKey "$out/bob.conf" && [ ! -e "$out/bob.key" ] &&
   grep -q "^PostUp = wg set %i private-key /etc/wireguard/mostar.key" "$out/bob.conf"'
check "private keys are readable by their owner only" \
  '[ "$(stat -c %a "$out/hub.key")" = 600 ] && [ "$(stat -c %a "$out/robot.conf")" = 600 ]'
for f in mostar-hub robot alice bob; do
  cp "$out/$f.conf" "$work/t$f.conf"
  check "wg-quick parses $f.conf" 'wg-quick strip "$work/t$f.conf" > "$work/$f.stripped"'
done
check "the stripped configs are valid wg syntax with the right keys" \
  'grep -q "^PrivateKey = $(cat "$out/hub.key")$" "$work/mostar-hub.stripped"'

profile_values() {  # file -> whitelisted addresses, then PROFILE=INITIAL_PEERS for each profile
  python3 - "$1" <<'EOF'
import sys, xml.etree.ElementTree as ET
ns = {"d": "http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles"}
root = ET.parse(sys.argv[1]).getroot()
white = [a.text for a in root.findall(".//d:interfaceWhiteList/d:address", ns)]
out = [",".join(white)]
for p in root.findall(".//d:participant", ns):
    peers = [a.text for a in p.findall(".//d:initialPeersList//d:address", ns)]
    out.append("%s=%s" % (p.get("profile_name"), ",".join(peers) or "-"))
print(" ".join(out))
EOF
}
check "alice's DDS profiles announce only her overlay address and dial the robot (her video through the relay: the hub)" \
  '[ "$(profile_values "$out/alice.dds.xml")" = "10.77.0.3,127.0.0.1 robot=- operator=10.77.0.2 operator_video=10.77.0.1 relay=10.77.0.2 relay_observers=-" ]'
check "an observer's DDS profiles dial the relay on the hub" \
  '[ "$(profile_values "$out/dave.dds.xml")" = "10.77.0.5,127.0.0.1 robot=- operator=10.77.0.1 operator_video=10.77.0.1 relay=10.77.0.1 relay_observers=-" ]'
check "the hub's DDS profiles (a relay there) use its own address and dial the robot" \
  '[ "$(profile_values "$out/hub.dds.xml")" = "10.77.0.1,127.0.0.1 robot=- operator=10.77.0.2 operator_video=10.77.0.1 relay=10.77.0.2 relay_observers=-" ]'
check "the robot's profile dials no one (operators announce themselves to it)" \
  '[ "$(profile_values "$out/robot.dds.xml")" = "10.77.0.2,127.0.0.1 robot=- operator=10.77.0.2 operator_video=10.77.0.1 relay=10.77.0.2 relay_observers=-" ]'
check "the DDS profiles keep the security marker for make_pki.sh" \
  '[ "$(grep -c "<!-- mostar:security -->" "$out/alice.dds.xml")" = 5 ]'

robot_key=$(field robot 3)
"$gen" "$out" --hub-endpoint hub.example.org:51820 --peer carol --peer robot > "$work/log2"
check "a second run keeps the existing peers' addresses and keys" \
  '[ "$(field robot 2)" = 10.77.0.2 ] && [ "$(field robot 3)" = "$robot_key" ]'
check "a second run adds the new peer at the next address" '[ "$(field carol 2)" = 10.77.0.6 ]'
check "the rewritten hub config has all five peers" \
  '[ "$(grep -c "^\[Peer\]" "$out/mostar-hub.conf")" = 5 ]'

# The TCP fallback (--tcp-hub): the same keys and addresses, the endpoint is the local tunnel.
"$gen" "$work/tcp" --hub-endpoint hub.example.org:51820 --peer robot --observer dave \
  --tcp-hub hub.example.org:443 --tunnel-port 51900 > "$work/log3"
tcp="$work/tcp"
check "a TCP fallback peer config differs from the UDP one only in the endpoint, a 1 s keepalive (and its comment)" \
  '[ "$(conf_value "$tcp/robot.tcp.conf" Endpoint)" = 127.0.0.1:51900 ] &&
   [ "$(conf_value "$tcp/robot.tcp.conf" PersistentKeepalive)" = 1 ] &&
   [ "$(diff <(grep -v "^#\|^Endpoint\|^PersistentKeepalive" "$tcp/robot.conf") <(grep -v "^#\|^Endpoint\|^PersistentKeepalive" "$tcp/robot.tcp.conf"))" = "" ]'
check "each peer's tunnel client dials the hub's TCP port and listens where WireGuard sends" \
  'grep -qx "HUB=hub.example.org:443" "$tcp/dave.wg-tcp.env" &&
   grep -qx "LISTEN=127.0.0.1:51900" "$tcp/dave.wg-tcp.env"'
check "the hub's tunnel server listens on the TCP port and forwards to its WireGuard port" \
  'grep -qx "LISTEN=0.0.0.0:443" "$tcp/hub.wg-tcp.env" &&
   grep -qx "WIREGUARD=127.0.0.1:51820" "$tcp/hub.wg-tcp.env"'
cp "$tcp/robot.tcp.conf" "$work/ttcp.conf"
check "wg-quick parses a TCP fallback peer config" 'wg-quick strip "$work/ttcp.conf" > /dev/null'
check "without --tcp-hub no fallback files are written" '[ ! -e "$out/robot.tcp.conf" ] && [ ! -e "$out/hub.wg-tcp.env" ]'

# The hub's endpoints across a restart (deploy/wan/hub_endpoints.sh) against a fake `wg` that
# serves the files in $fake and logs every `wg set`.
tool="$src/deploy/wan/hub_endpoints.sh"
check "the hub restores its peers' endpoints first on the way up and saves them on the way down" \
  '[ "$(grep -m1 "^PostUp" "$out/mostar-hub.conf")" = "PostUp = $tool restore %i /var/lib/mostar || true" ] &&
   [ "$(grep "^PreDown" "$out/mostar-hub.conf")" = "PreDown = $tool save %i /var/lib/mostar || true" ]'
"$gen" "$work/state" --hub-endpoint h:1 --peer robot --hub-state-dir "$work/hub state" >/dev/null
check "--hub-state-dir names the folder, quoted for wg-quick" \
  'grep -qF "PreDown = $tool save %i $work/hub\ state || true" "$work/state/mostar-hub.conf"'
fake=$work/fake
mkdir -p "$fake/bin" "$work/var"
cat > "$fake/bin/wg" <<'FAKE'
#!/usr/bin/env bash
fake=$(dirname "$(dirname "$0")")
if [ "$1" = show ]; then
  [ -f "$fake/$3" ] && [ ! -e "$fake/down" ] || { echo "Unable to access interface" >&2; exit 1; }
  cat "$fake/$3"
else
  args="$*"
  [ "${*: -2:1}" != preshared-key ] || args="${*:1:$#-1} $(cat "${*: -1}")"
  echo "$args" >> "$fake/set.log"
  [[ "$args" != *"endpoint 198.18.9.9:1 "* ]] || exit 1  # a peer WireGuard refuses to set
fi
FAKE
chmod +x "$fake/bin/wg"
k1=AAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAA= k2=BBBBBBBBBBBBBBBBBBBBBBBBBBBBBBBBBBBBBBBBBBB=
k3=CCCCCCCCCCCCCCCCCCCCCCCCCCCCCCCCCCCCCCCCCCC= k4=DDDDDDDDDDDDDDDDDDDDDDDDDDDDDDDDDDDDDDDDDDD=
k5=EEEEEEEEEEEEEEEEEEEEEEEEEEEEEEEEEEEEEEEEEEE= psk=PPPPPPPPPPPPPPPPPPPPPPPPPPPPPPPPPPPPPPPPPPP=
printf '%s\t%s\n' "$k1" 198.18.1.2:40000 "$k2" 198.18.2.2:50000 "$k3" "(none)" \
  "$k4" 198.18.3.2:60000 "$k5" 198.18.2.2:50001 > "$fake/endpoints"
endpoints() { PATH="$fake/bin:$PATH" "$tool" "$@" 2>>"$work/endpoints.log"; }
check "save writes the interface's endpoints to the state folder" \
  'endpoints save mostar-hub "$work/var" && cmp -s "$fake/endpoints" "$work/var/wg-mostar-hub.endpoints"'
touch "$fake/down"
check "a save that cannot read the interface fails and keeps the last copy" \
  '! endpoints save mostar-hub "$work/var" && cmp -s "$fake/endpoints" "$work/var/wg-mostar-hub.endpoints" &&
   [ ! -e "$work/var/wg-mostar-hub.endpoints.new" ]'
rm "$fake/down"
# After the restart: k1, k3 and k5 not yet back, k2 handshook by itself, k4 no longer a peer.
printf '%s\t%s\n' "$k1" 0 "$k2" 1796600000 "$k3" 0 "$k5" 0 > "$fake/latest-handshakes"
printf '%s\t%s\n' "$k1" "10.77.0.2/32" "$k2" "10.77.0.3/32" "$k3" "10.77.0.4/32" \
  "$k5" "10.77.0.6/32 10.77.9.0/24" > "$fake/allowed-ips"
printf '%s\t%s\n' "$k1" "(none)" "$k2" "(none)" "$k3" "(none)" "$k5" "$psk" > "$fake/preshared-keys"
endpoints restore mostar-hub "$work/var" || true
check "restore sets each peer not yet back again, with its endpoint, routes and a keepalive" \
  '[ "$(cat "$fake/set.log")" = "set mostar-hub peer $k1 remove
set mostar-hub peer $k1 allowed-ips 10.77.0.2/32 endpoint 198.18.1.2:40000 persistent-keepalive 25
set mostar-hub peer $k5 remove
set mostar-hub peer $k5 allowed-ips 10.77.0.6/32,10.77.9.0/24 endpoint 198.18.2.2:50001 persistent-keepalive 25 preshared-key $psk" ]'
check "restore says how many it restored" 'grep -q "2 peer endpoints restored on mostar-hub" "$work/endpoints.log"'
rm "$fake/set.log"
check "without a saved copy restore does nothing and succeeds" \
  'endpoints restore other "$work/var" && [ ! -e "$fake/set.log" ]'
# A damaged copy: one endpoint that is no address (skipped, the peer untouched), one that
# WireGuard refuses (the peer keeps its routes, without an endpoint): no peer is lost.
printf '%s\t%s\n' "$k1" "bad;endpoint" "$k3" 198.18.9.9:1 > "$work/var/wg-damaged.endpoints"
: > "$work/endpoints.log"
endpoints restore damaged "$work/var" || true
check "a damaged saved copy never costs the hub a peer" \
  '[ "$(cat "$fake/set.log")" = "set damaged peer $k3 remove
set damaged peer $k3 allowed-ips 10.77.0.4/32 endpoint 198.18.9.9:1 persistent-keepalive 25
set damaged peer $k3 allowed-ips 10.77.0.4/32" ] &&
   grep -q "is no ADDRESS:PORT; peer $k1 skipped" "$work/endpoints.log" &&
   grep -q "peer $k3 not restored" "$work/endpoints.log"'
rm -f "$fake/set.log"
check "a missing state folder is named" \
  '! endpoints save mostar-hub "$work/nowhere" && grep -q "no folder $work/nowhere" "$work/endpoints.log"'
hook=$(grep -m1 "^PostUp = " "$work/state/mostar-hub.conf" | sed "s/^PostUp = //")
touch "$fake/down"
mkdir -p "$work/hub state"
cp "$work/var/wg-mostar-hub.endpoints" "$work/hub state/"
# wg-quick evaluates each hook under set -e (a bash of its own here: `if` would suspend -e).
hook_run() { PATH="$fake/bin:$PATH" bash -ec 'eval "$1"' _ "${1//%i/mostar-hub}" 2>/dev/null; }
check "the PostUp hook as wg-quick runs it never fails the overlay's start" 'hook_run "$hook"'
check "(a check that can fail: without its || true the hook fails, wg cannot read the interface)" \
  '! hook_run "${hook% || true}"'
rm -f "$fake/down"

refused() {  # expected message part, arguments...
  local want=$1; shift
  local msg
  if msg=$("$gen" "$work/bad" "$@" 2>&1); then return 1; fi
  [[ "$msg" == *"$want"* ]]
}
check "no hub endpoint is refused" 'refused "--hub-endpoint HOST:PORT is required" --peer x'
check "an endpoint without a port is refused" 'refused "HOST:PORT" --hub-endpoint hub.example.org'
check "a bad peer name is refused" 'refused "must be" --hub-endpoint h:1 --peer "a b"'
check "a malformed public key is refused" 'refused "not a WireGuard key" --hub-endpoint h:1 --peer x:abc'
check "a peer named hub is refused" 'refused "public host" --hub-endpoint h:1 --peer hub'
check "an overlay without its robot is refused" 'refused "no peer named robot" --hub-endpoint h:1 --peer alice'
check "a TCP hub without a port is refused" 'refused "--tcp-hub must be HOST:PORT" --hub-endpoint h:1 --peer robot --tcp-hub h'
check "a bad tunnel port is refused" 'refused "--tunnel-port must be" --hub-endpoint h:1 --peer robot --tcp-hub h:443 --tunnel-port 70000'
# (the output captured first: grep -q in a pipe may end it early, a SIGPIPE under pipefail)
check "--help prints the usage to stdout and succeeds" \
  'out=$("$gen" --help 2>/dev/null) && grep -q "^Usage:" <<<"$out"'
check "an option in place of OUT_DIR is refused" \
  '! "$gen" --hub-endpoint h:1 --peer robot >/dev/null 2>&1 && [ ! -e ./--hub-endpoint ]'

[ "$failures" -eq 0 ] || exit 1
echo "make_overlay_test: all checks passed"
