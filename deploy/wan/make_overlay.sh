#!/usr/bin/env bash
# Creates the WireGuard overlay that carries mostar across the Internet: one hub on a public
# host, every robot and operator a peer that dials out to it (no inbound port anywhere but the
# hub's UDP port; keepalives hold the NAT mappings; a peer may change its public address).
# Peers reach each other through the hub, which forwards between them inside the tunnel only.
#
# Usage:
#   make_overlay.sh OUT_DIR --hub-endpoint HOST:PORT [--peer NAME[:PUBLIC_KEY] ...]
#                   [--observer NAME[:PUBLIC_KEY] ...]
#                   [--robot robot] [--subnet 10.77.0] [--mtu 1420] [--keepalive-s 15]
#                   [--dds-template deploy/dds/overlay.xml]
#                   [--tcp-hub HOST:PORT [--tunnel-port 51821]]
#
#   --hub-endpoint HOST:PORT  the public host's address (or DNS name) and UDP port
#   --peer NAME               a robot or operator computer; its key pair is made here
#   --peer NAME:PUBLIC_KEY    a peer that made its own key (`wg genkey | tee mostar.key |
#                             wg pubkey`): only its public key comes here, and its config
#                             reads the private key from /etc/wireguard/mostar.key
#   --observer NAME[:KEY]     a computer that only watches, through mostar_relay on the hub:
#                             like --peer, but its DDS profiles dial the hub, not the robot
#   --robot NAME              which peer is the robot (default: robot), the one operators dial
#   --subnet A.B.C            the overlay's /24 (default 10.77.0): hub .1, peers from .2 in
#                             the order they are first named
#   --tcp-hub HOST:PORT       also write the TCP fallback for sites that block UDP: the hub's
#                             mostar_wg_tcp server listens on TCP PORT (e.g. 443); each peer's
#                             NAME.tcp.conf names its local mostar_wg_tcp client
#                             (127.0.0.1:TUNNEL_PORT) as the hub's endpoint
#   --tunnel-port PORT        the local UDP port of that client (default 51821)
#   --hub-state-dir DIR       where the hub keeps its peers' endpoints across a restart
#                             (default /var/lib/mostar, the package's state folder); the
#                             hub's config calls hub_endpoints.sh (beside this script, as
#                             installed: /usr/share/mostar/wan) to save and restore them
# Running it again with new names adds peers with the same hub and the same addresses for the
# existing ones (state in OUT_DIR/peers.tsv); the hub's config is rewritten: reload it with
# `wg syncconf mostar-hub <(wg-quick strip mostar-hub)`.
#
# Produces in OUT_DIR (private keys mode 0600):
#   hub.key, hub.pub, mostar-hub.conf   the hub's wg-quick config (listens on PORT, forwards
#                                       between peers only)
#   hub.dds.xml                         DDS profiles for a mostar_relay on the hub
#   NAME.conf                           the peer's wg-quick config (interface "mostar" once
#                                       installed as /etc/wireguard/mostar.conf)
#   NAME.dds.xml                        the DDS profiles for that peer: UDP over the overlay
#                                       only, dialling the robot (observers: the hub; see
#                                       deploy/dds/overlay.xml); pass the directory to
#                                       make_pki.sh --profile-dir, then NAME.xml to the program
#   peers.tsv                           name, overlay address, public key, who made the key,
#                                       role (peer or observer)
# and with --tcp-hub (docs/networking.md, "TCP fallback"):
#   NAME.tcp.conf                       NAME.conf with the endpoint 127.0.0.1:TUNNEL_PORT:
#                                       install it as /etc/wireguard/mostar.conf instead
#   NAME.wg-tcp.env                     /etc/mostar/wg-tcp.env for mostar-wg-tcp.service
#   hub.wg-tcp.env                      /etc/mostar/wg-tcp-hub.env for mostar-wg-tcp-hub.service
# Copy to each computer only its own NAME.conf (and NAME.dds.xml). The hub never sees a peer's
# private key when the peer made its own.
set -euo pipefail

# usage [STATUS]: the header above, to stdout for --help (status 0), else to stderr (status 2).
usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//' >&"$((${1:-2} ? 2 : 1))"; exit "${1:-2}"; }
die() { echo "make_overlay.sh: $*" >&2; exit 1; }

[ $# -ge 1 ] || usage
case "$1" in -h|--help) usage 0 ;; -*) die "the first argument is OUT_DIR, not $1" ;; esac
out=$1; shift
here=$(cd "$(dirname "$(readlink -f "$0")")" && pwd)  # also through /usr/bin links
endpoint="" subnet=10.77.0 mtu=1420 keepalive=15 robot=robot
template="$here/../dds/overlay.xml"
tcp_hub="" tunnel_port=51821 hub_state=/var/lib/mostar
peers=()
while [ $# -gt 0 ]; do
  case "$1" in
    --hub-endpoint) endpoint=$2; shift 2 ;;
    --peer) peers+=("peer:$2"); shift 2 ;;
    --observer) peers+=("observer:$2"); shift 2 ;;
    --subnet) subnet=$2; shift 2 ;;
    --robot) robot=$2; shift 2 ;;
    --mtu) mtu=$2; shift 2 ;;
    --keepalive-s) keepalive=$2; shift 2 ;;
    --dds-template) template=$2; shift 2 ;;
    --tcp-hub) tcp_hub=$2; shift 2 ;;
    --tunnel-port) tunnel_port=$2; shift 2 ;;
    --hub-state-dir) hub_state=$2; shift 2 ;;
    -h|--help) usage 0 ;;
    *) die "unknown option $1" ;;
  esac
done
endpoints_tool=$(printf %q "$here/hub_endpoints.sh") hub_state_q=$(printf %q "$hub_state")
[ -n "$endpoint" ] || die "--hub-endpoint HOST:PORT is required"
[[ "$endpoint" =~ ^[A-Za-z0-9.:-]+:[0-9]+$ ]] || die "--hub-endpoint must be HOST:PORT"
[[ "$subnet" =~ ^[0-9]+\.[0-9]+\.[0-9]+$ ]] || die "--subnet must be three octets, e.g. 10.77.0"
[ -f "$template" ] || die "no DDS template $template"
if [ -n "$tcp_hub" ]; then
  [[ "$tcp_hub" =~ ^[A-Za-z0-9.:-]+:[0-9]+$ ]] || die "--tcp-hub must be HOST:PORT"
fi
[[ "$tunnel_port" =~ ^[0-9]+$ ]] && [ "$tunnel_port" -ge 1 ] && [ "$tunnel_port" -le 65535 ] ||
  die "--tunnel-port must be 1..65535"
command -v wg >/dev/null || die "wg is required (Debian package wireguard-tools)"
port=${endpoint##*:}

mkdir -p "$out"
out=$(cd "$out" && pwd)
umask 077
touch "$out/peers.tsv"

if [ ! -f "$out/hub.key" ]; then
  wg genkey > "$out/hub.key"
  wg pubkey < "$out/hub.key" > "$out/hub.pub"
fi

# Add new peers to peers.tsv (name, address, public key; "own" marks a peer-made key).
for tagged in "${peers[@]}"; do
  role=${tagged%%:*}
  spec=${tagged#*:}
  name=${spec%%:*}
  key=""
  [ "$name" = "$spec" ] || key=${spec#*:}
  [[ "$name" =~ ^[A-Za-z0-9_.-]+$ ]] || die "peer name '$name' must be [A-Za-z0-9_.-]+"
  [ "$name" != hub ] || die "'hub' is the public host's name"
  if awk -v n="$name" '$1 == n { found = 1 } END { exit !found }' "$out/peers.tsv"; then
    continue
  fi
  last=$(awk 'BEGIN { m = 1 } { split($2, a, "."); if (a[4] > m) m = a[4] } END { print m }' \
    "$out/peers.tsv")
  [ "$last" -lt 254 ] || die "the /24 is full"
  own=made
  if [ -z "$key" ]; then
    wg genkey > "$out/$name.key"
    key=$(wg pubkey < "$out/$name.key")
  else
    [[ "$key" =~ ^[A-Za-z0-9+/]{43}=$ ]] || die "public key of $name is not a WireGuard key"
    own=own
  fi
  printf '%s\t%s\t%s\t%s\t%s\n' "$name" "$subnet.$((last + 1))" "$key" "$own" "$role" \
    >> "$out/peers.tsv"
done

# The hub: listens, forwards between peers inside the overlay and nowhere else.
{
  echo "# mostar overlay hub (wg-quick). Install as /etc/wireguard/mostar-hub.conf."
  echo "[Interface]"
  echo "Address = $subnet.1/24"
  echo "ListenPort = $port"
  echo "MTU = $mtu"
  echo "PrivateKey = $(cat "$out/hub.key")"
  echo "# Restarted, the hub knows no peer's endpoint, and a peer starts a new handshake only 15 s"
  echo "# after the hub went silent: the endpoints are saved on the way down (and every minute by"
  echo "# mostar-hub-endpoints.timer) and restored first thing on the way up (docs/networking.md)."
  echo "PostUp = $endpoints_tool restore %i $hub_state_q || true"
  echo "PreDown = $endpoints_tool save %i $hub_state_q || true"
  echo "# Forward between peers (packets that came in on this interface), never out of it."
  echo "PostUp = sysctl -qw net.ipv4.conf.%i.forwarding=1"
  echo "PostUp = nft add table inet mostar_hub; nft add chain inet mostar_hub forward '{ type filter hook forward priority 0; }'; nft add rule inet mostar_hub forward iifname %i oifname != %i drop"
  echo "PostDown = nft delete table inet mostar_hub"
  while IFS=$'\t' read -r name addr key _; do
    echo
    echo "[Peer]"
    echo "# $name"
    echo "PublicKey = $key"
    echo "AllowedIPs = $addr/32"
  done < "$out/peers.tsv"
} > "$out/mostar-hub.conf"

robot_addr=$(awk -v n="$robot" -F'\t' '$1 == n { print $2 }' "$out/peers.tsv")
[ -n "$robot_addr" ] || die "no peer named $robot (the robot; see --robot)"
while IFS=$'\t' read -r name addr key own role; do
  {
    echo "# mostar overlay peer $name ($addr). Install as /etc/wireguard/mostar.conf."
    echo "[Interface]"
    echo "Address = $addr/24"
    echo "MTU = $mtu"
    if [ "$own" = made ]; then
      echo "PrivateKey = $(cat "$out/$name.key")"
    else
      echo "PostUp = wg set %i private-key /etc/wireguard/mostar.key"
    fi
    echo
    echo "[Peer]"
    echo "# hub"
    echo "PublicKey = $(cat "$out/hub.pub")"
    echo "Endpoint = $endpoint"
    echo "AllowedIPs = $subnet.0/24"
    echo "PersistentKeepalive = $keepalive"
  } > "$out/$name.conf"
  if [ -n "$tcp_hub" ]; then
    # The same peer behind the TCP fallback: WireGuard sends to the local tunnel client, and
    # a keepalive after 1 s of silence, so that after the tunnel reconnects the hub learns the
    # new endpoint within 1 s even when the peer has nothing else to send (a robot whose DDS
    # peers were all dropped sends nothing until someone announces itself to it).
    sed -e "s#^Endpoint = .*#Endpoint = 127.0.0.1:$tunnel_port#" \
        -e "s#^PersistentKeepalive = .*#PersistentKeepalive = 1#" \
        -e "s#^\(\# mostar overlay peer .*\)\$#\1 Over TCP via mostar-wg-tcp.service.#" \
        "$out/$name.conf" > "$out/$name.tcp.conf"
    {
      echo "# mostar_wg_tcp client of peer $name. Install as /etc/mostar/wg-tcp.env."
      echo "HUB=$tcp_hub"
      echo "LISTEN=127.0.0.1:$tunnel_port"
    } > "$out/$name.wg-tcp.env"
    chmod 0644 "$out/$name.wg-tcp.env"
  fi
  # Operators dial the robot; observers dial the relay on the hub.
  dials=$robot_addr
  [ "$role" != observer ] || dials=$subnet.1
  sed -e "/mostar:overlay-address/ s#<address>[0-9.]*</address>#<address>$addr</address>#" \
      -e "/mostar:robot-address/ s#<address>[0-9.]*</address>#<address>$dials</address>#" \
      -e "/mostar:hub-address/ s#<address>[0-9.]*</address>#<address>$subnet.1</address>#" \
      "$template" > "$out/$name.dds.xml"
  chmod 0644 "$out/$name.dds.xml"
done < "$out/peers.tsv"
# The hub's own DDS profiles (for mostar_relay on the hub).
sed -e "/mostar:overlay-address/ s#<address>[0-9.]*</address>#<address>$subnet.1</address>#" \
    -e "/mostar:robot-address/ s#<address>[0-9.]*</address>#<address>$robot_addr</address>#" \
    -e "/mostar:hub-address/ s#<address>[0-9.]*</address>#<address>$subnet.1</address>#" \
    "$template" > "$out/hub.dds.xml"
chmod 0644 "$out/hub.pub" "$out/peers.tsv" "$out/hub.dds.xml"
if [ -n "$tcp_hub" ]; then
  {
    echo "# mostar_wg_tcp server on the hub. Install as /etc/mostar/wg-tcp-hub.env."
    echo "LISTEN=0.0.0.0:${tcp_hub##*:}"
    echo "WIREGUARD=127.0.0.1:$port"
  } > "$out/hub.wg-tcp.env"
  chmod 0644 "$out/hub.wg-tcp.env"
fi
echo "make_overlay.sh: hub $endpoint ($subnet.1), peers: $(cut -f1,2 "$out/peers.tsv" | tr '\t\n' '= ')"
