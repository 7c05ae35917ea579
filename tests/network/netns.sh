#!/usr/bin/env bash
# Two network namespaces for network tests: "<prefix>_robot" and "<prefix>_operator", joined by
# a veth pair with the private test addresses 10.231.0.1/24 (robot) and 10.231.0.2/24
# (operator), which exist only inside the two namespaces. Loopback is up in each (with a
# multicast route, so default DDS discovery stays inside the namespace).
#
#   netns.sh up PREFIX [--rate RATE]   create; RATE (e.g. 8mbit) shapes both directions with tbf
#   netns.sh down PREFIX               delete (also kills processes left inside)
#   netns.sh check                     exit 0 when namespaces can be created here, 77 otherwise
#
# Delay, jitter and loss: run netem_relay between the two namespaces (a second link over TUN
# devices, 10.232.0.1 <-> 10.232.0.2). Needs root.
set -euo pipefail

die() { echo "netns.sh: $*" >&2; exit 1; }

cmd=${1:-}
case "$cmd" in
  check)
    probe="mostar_probe_$$"
    if ip netns add "$probe" 2>/dev/null; then
      ip netns del "$probe"
      exit 0
    fi
    echo "netns.sh: cannot create network namespaces here (need root and 'ip netns')" >&2
    exit 77
    ;;
  up)
    prefix=${2:-}; [ -n "$prefix" ] || die "usage: netns.sh up PREFIX [--rate RATE]"
    shift 2
    rate=""
    while [ $# -gt 0 ]; do
      case "$1" in
        --rate) rate=$2; shift 2 ;;
        *) die "unknown option $1" ;;
      esac
    done
    r="${prefix}_robot"; o="${prefix}_operator"
    # veth names are limited to 15 characters: derive short unique ones from the prefix.
    tag=$(echo -n "$prefix" | md5sum | cut -c1-8)
    ip netns add "$r"
    ip netns add "$o"
    ip link add "vr$tag" type veth peer name "vo$tag"
    ip link set "vr$tag" netns "$r"
    ip link set "vo$tag" netns "$o"
    for ns in "$r" "$o"; do
      ip -n "$ns" link set lo up
      ip -n "$ns" link set lo multicast on
      ip -n "$ns" route add 224.0.0.0/4 dev lo
    done
    ip -n "$r" link set "vr$tag" name veth0
    ip -n "$o" link set "vo$tag" name veth0
    ip -n "$r" addr add 10.231.0.1/24 dev veth0
    ip -n "$o" addr add 10.231.0.2/24 dev veth0
    ip -n "$r" link set veth0 up
    ip -n "$o" link set veth0 up
    if [ -n "$rate" ]; then
      for ns in "$r" "$o"; do
        ip netns exec "$ns" tc qdisc add dev veth0 root tbf rate "$rate" burst 32kb latency 50ms
      done
    fi
    ;;
  down)
    prefix=${2:-}; [ -n "$prefix" ] || die "usage: netns.sh down PREFIX"
    for ns in "${prefix}_robot" "${prefix}_operator"; do
      if [ -e "/var/run/netns/$ns" ]; then
        pids=$(ip netns pids "$ns" 2>/dev/null || true)
        [ -z "$pids" ] || kill $pids 2>/dev/null || true
        ip netns del "$ns" || true
      fi
    done
    ;;
  *)
    die "usage: netns.sh up PREFIX [--rate RATE] | down PREFIX | check"
    ;;
esac
