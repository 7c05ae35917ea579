#!/usr/bin/env bash
# The Internet deployment in network namespaces: a robot behind NAT A, a pilot and an observer
# behind NAT B (one public address), another observer behind NAT C, and one public host (the
# hub) that everyone dials out to. Every NAT masquerades its LAN and drops every connection
# that starts outside it, so no host behind a NAT has an inbound port. All LANs use the same
# private range (192.168.1.0/24), as home and cellular networks do.
#
#                      PREFIX_hub 198.18.0.10
#                            |
#   PREFIX_nata --wan-- PREFIX_inet --wan-- PREFIX_natb --lan-- PREFIX_pilot, PREFIX_obs1
#   198.18.1.2 |             |              198.18.2.2
#   lan: PREFIX_robot   PREFIX_natc 198.18.3.2 --lan-- PREFIX_obs2
#
# Hosts behind a NAT are 192.168.1.10 (robot, pilot, obs2) and 192.168.1.11 (obs1); each NAT's
# LAN side is 192.168.1.1. The addresses exist only inside these namespaces.
#
#   nat_topology.sh up PREFIX [--netem NETEM_RELAY] [--delay-ms 50] [--jitter-ms 5]
#                             [--loss 0.01] [--rate-kbit 8000] [--log-dir DIR] [--block-udp]
#       create it. With --netem, the three NATs' public links are netem_relay processes (delay,
#       jitter and loss each way, a rate-limited queue; defaults above: 50 ms one-way on each
#       side, so host to host through the hub is 100 ms one-way); without it they are veth
#       pairs. PIDs of the relays go to /tmp/PREFIX.netem.pids. With --block-udp the three NATs
#       forward no UDP from their LAN (a site that allows only TCP out, as some corporate,
#       hotel and campus networks do); the drops count in the NAT's counter "udp_blocked"
#       (`nat_topology.sh blocked PREFIX SITE` prints it).
#   nat_topology.sh outage PREFIX SITE on|off   cut (or restore) SITE's public link both ways
#       (SITE: a, b, c or hub): an nftables table in the NAT (or hub) that drops everything on
#       its public interface, so existing NAT mappings stay as a short outage leaves them.
#   nat_topology.sh readdress PREFIX SITE N      give SITE's NAT the public address 198.18.X.N
#       (the robot's router got a new address from its provider)
#   nat_topology.sh blocked PREFIX SITE          UDP datagrams SITE's NAT dropped (--block-udp)
#   nat_topology.sh down PREFIX                  delete everything (also kills what runs inside)
#   nat_topology.sh namespaces PREFIX            print the namespace names, one per line
# Needs root, `ip netns`, nftables and /dev/net/tun (with --netem). Exit 77 where namespaces
# cannot be created.
set -euo pipefail

die() { echo "nat_topology.sh: $*" >&2; exit 1; }
here=$(cd "$(dirname "$0")" && pwd)

names() {  # all namespaces of PREFIX
  local p=$1
  echo "${p}_inet ${p}_hub ${p}_nata ${p}_natb ${p}_natc ${p}_robot ${p}_pilot ${p}_obs1 ${p}_obs2"
}

site_index() {  # a|b|c|hub -> the third octet of its public /24
  case "$1" in hub) echo 0 ;; a) echo 1 ;; b) echo 2 ;; c) echo 3 ;; *) die "unknown site $1" ;; esac
}

site_ns() {  # a|b|c|hub -> namespace that owns the public interface
  case "$1" in hub) echo "$2_hub" ;; a|b|c) echo "$2_nat$1" ;; *) die "unknown site $1" ;; esac
}

new_ns() {
  ip netns add "$1"
  ip -n "$1" link set lo up
  # DDS multicast stays on loopback unless a profile says otherwise.
  ip -n "$1" link set lo multicast on
  ip -n "$1" route add 224.0.0.0/4 dev lo
}

# A public link between the inet router and SITE's namespace: interface "wan" there, "wanX" in
# inet, addresses 198.18.X.1 (inet) and 198.18.X.2 (the site; 198.18.0.10 for the hub).
public_link() {
  local p=$1 site=$2 idx ns tag addr
  idx=$(site_index "$site")
  ns=$(site_ns "$site" "$p")
  addr="198.18.$idx.2"
  [ "$site" != hub ] || addr="198.18.0.10"
  if [ -n "$netem" ] && [ "$site" != hub ]; then
    "$netem" --netns-a "${p}_inet" --netns-b "$ns" --dev-a "wan$idx" --dev-b wan \
      --addr-a "198.18.$idx.1" --addr-b "$addr" --delay-ms "$delay_ms" --jitter-ms "$jitter_ms" \
      --loss "$loss" --rate-kbit "$rate_kbit" --seed "$((idx + 7))" --duration-s 3600 \
      >"$log_dir/netem_$site.log" 2>&1 &
    echo $! >>"/tmp/$p.netem.pids"
    for _ in $(seq 100); do
      ip -n "$ns" link show wan >/dev/null 2>&1 && ip -n "${p}_inet" link show "wan$idx" \
        >/dev/null 2>&1 && grep -q ready "$log_dir/netem_$site.log" && break
      sleep 0.05
    done
    grep -q ready "$log_dir/netem_$site.log" || die "netem_relay for site $site did not start"
  else
    tag=$(echo -n "$p$site" | md5sum | cut -c1-8)
    ip link add "pi$tag" type veth peer name "ps$tag"
    ip link set "pi$tag" netns "${p}_inet"
    ip link set "ps$tag" netns "$ns"
    ip -n "${p}_inet" link set "pi$tag" name "wan$idx"
    ip -n "$ns" link set "ps$tag" name wan
    ip -n "${p}_inet" addr add "198.18.$idx.1/24" dev "wan$idx"
    ip -n "$ns" addr add "$addr/24" dev wan
    ip -n "${p}_inet" link set "wan$idx" up
    ip -n "$ns" link set wan up
  fi
  ip -n "$ns" route add default via "198.18.$idx.1" dev wan onlink
}

# A NAT router: LAN bridge 192.168.1.1/24, masquerade to "wan", nothing inbound that the LAN did
# not start; with $2 = block-udp no UDP out either (counted).
nat_router() {
  local ns=$1 udp_rule=""
  [ "${2:-}" != block-udp ] || udp_rule='iifname "br0" meta l4proto udp counter name udp_blocked drop'
  ip -n "$ns" link add br0 type bridge
  ip -n "$ns" addr add 192.168.1.1/24 dev br0
  ip -n "$ns" link set br0 up
  ip netns exec "$ns" sysctl -qw net.ipv4.ip_forward=1
  ip netns exec "$ns" nft -f - <<EOF
table ip nat {
  chain postrouting { type nat hook postrouting priority srcnat; oifname "wan" masquerade; }
}
table ip filter {
  counter udp_blocked {}
  chain forward {
    type filter hook forward priority filter; policy drop;
    $udp_rule
    iifname "br0" accept
    ct state established,related accept
  }
  chain input {
    type filter hook input priority filter; policy accept;
    iifname "wan" ct state established,related accept
    iifname "wan" drop
  }
}
EOF
}

# Host NAME behind the NAT namespace NATNS with address 192.168.1.HOST.
lan_host() {
  local p=$1 natns=$2 name=$3 host=$4 tag
  tag=$(echo -n "$p$name" | md5sum | cut -c1-8)
  new_ns "${p}_$name"
  ip link add "lh$tag" type veth peer name "ln$tag"
  ip link set "lh$tag" netns "${p}_$name"
  ip link set "ln$tag" netns "$natns"
  ip -n "${p}_$name" link set "lh$tag" name lan0
  ip -n "${p}_$name" addr add "192.168.1.$host/24" dev lan0
  ip -n "${p}_$name" link set lan0 up
  ip -n "$natns" link set "ln$tag" master br0
  ip -n "$natns" link set "ln$tag" up
  ip -n "${p}_$name" route add default via 192.168.1.1
}

cmd=${1:-}
case "$cmd" in
  up)
    p=${2:-}; [ -n "$p" ] || die "usage: nat_topology.sh up PREFIX [options]"
    shift 2
    netem="" delay_ms=50 jitter_ms=5 loss=0.01 rate_kbit=8000 log_dir=/tmp block_udp=""
    while [ $# -gt 0 ]; do
      case "$1" in
        --netem) netem=$2; shift 2 ;;
        --delay-ms) delay_ms=$2; shift 2 ;;
        --jitter-ms) jitter_ms=$2; shift 2 ;;
        --loss) loss=$2; shift 2 ;;
        --rate-kbit) rate_kbit=$2; shift 2 ;;
        --log-dir) log_dir=$2; shift 2 ;;
        --block-udp) block_udp=block-udp; shift ;;
        *) die "unknown option $1" ;;
      esac
    done
    "$here/netns.sh" check || exit 77
    for ns in inet hub nata natb natc; do new_ns "${p}_$ns"; done
    ip netns exec "${p}_inet" sysctl -qw net.ipv4.ip_forward=1
    rm -f "/tmp/$p.netem.pids"
    for site in hub a b c; do public_link "$p" "$site"; done
    for site in a b c; do nat_router "${p}_nat$site" $block_udp; done
    lan_host "$p" "${p}_nata" robot 10
    lan_host "$p" "${p}_natb" pilot 10
    lan_host "$p" "${p}_natb" obs1 11
    lan_host "$p" "${p}_natc" obs2 10
    ;;
  outage)
    p=${2:-}; site=${3:-}; state=${4:-}
    [ -n "$p" ] && [ -n "$site" ] && [ -n "$state" ] || die "usage: outage PREFIX SITE on|off"
    ns=$(site_ns "$site" "$p")
    if [ "$state" = on ]; then
      ip netns exec "$ns" nft -f - <<'EOF'
table inet outage {
  chain input { type filter hook input priority -10; iifname "wan" drop; }
  chain output { type filter hook output priority -10; oifname "wan" drop; }
  chain forward { type filter hook forward priority -10; iifname "wan" drop; oifname "wan" drop; }
}
EOF
    else
      ip netns exec "$ns" nft delete table inet outage 2>/dev/null || true
    fi
    ;;
  readdress)
    p=${2:-}; site=${3:-}; n=${4:-}
    [ -n "$p" ] && [ -n "$site" ] && [ -n "$n" ] || die "usage: readdress PREFIX SITE N"
    ns=$(site_ns "$site" "$p")
    idx=$(site_index "$site")
    # A point-to-point address works on both kinds of link; inet routes it to that link.
    ip -n "$ns" addr flush dev wan
    ip -n "$ns" addr add "198.18.$idx.$n/32" peer "198.18.$idx.1" dev wan
    ip -n "$ns" route replace default via "198.18.$idx.1" dev wan onlink
    ip -n "${p}_inet" route replace "198.18.$idx.$n/32" dev "wan$idx"
    ;;
  blocked)
    p=${2:-}; site=${3:-}
    [ -n "$p" ] && [ -n "$site" ] || die "usage: blocked PREFIX SITE"
    ip netns exec "$(site_ns "$site" "$p")" nft list counter ip filter udp_blocked |
      sed -n 's/.*packets \([0-9]*\).*/\1/p'
    ;;
  down)
    p=${2:-}; [ -n "$p" ] || die "usage: nat_topology.sh down PREFIX"
    if [ -f "/tmp/$p.netem.pids" ]; then
      kill $(cat "/tmp/$p.netem.pids") 2>/dev/null || true
      rm -f "/tmp/$p.netem.pids"
    fi
    for ns in $(names "$p"); do
      if [ -e "/var/run/netns/$ns" ]; then
        pids=$(ip netns pids "$ns" 2>/dev/null || true)
        [ -z "$pids" ] || kill -9 $pids 2>/dev/null || true
        ip netns del "$ns" || true
      fi
    done
    ;;
  namespaces)
    p=${2:-}; [ -n "$p" ] || die "usage: namespaces PREFIX"
    names "$p" | tr ' ' '\n'
    ;;
  *)
    die "usage: nat_topology.sh up|outage|readdress|blocked|down|namespaces PREFIX ..."
    ;;
esac
