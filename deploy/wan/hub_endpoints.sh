#!/usr/bin/env bash
# Keeps the overlay hub's peer endpoints across a restart of its WireGuard. A restarted hub
# knows no peer's endpoint (WireGuard learns them from the peers' packets), and a peer starts a
# new handshake only when the hub has not answered for 15 s; so the endpoints are saved while
# the interface runs and restored when it comes back, with a keepalive that makes the hub start
# every handshake at once, through the peers' NAT mappings (docs/networking.md, "Restarts of the hub").
# The hub's config (mostar-make-overlay) calls it from wg-quick: `restore` first of all PostUp,
# `save` as PreDown; mostar-hub-endpoints.timer saves every minute (a crash keeps that copy).
#
# Usage: hub_endpoints.sh save|restore INTERFACE STATE_DIR
#   save      writes `wg show INTERFACE endpoints` to STATE_DIR/wg-INTERFACE.endpoints
#             (atomically; a failed read keeps the last copy)
#   restore   for each saved peer that is still in the config and has no handshake yet: the
#             peer is set again (removed and added with its allowed IPs and preshared key, so
#             that a handshake attempted before the restore, without an endpoint, does not
#             hold the new one back for WireGuard's 5 s), with the saved endpoint and a
#             persistent keepalive of 25 s, which starts the handshake. A missing file or an
#             unknown peer is no error: the hub then learns endpoints as it always does. A saved
#             line whose endpoint is not ADDRESS:PORT is skipped and said (the peer is left as
#             wg-quick made it); a peer that cannot be set again gets its routes back without
#             an endpoint, so no peer is ever lost from the hub.
# Exit status: 0, or 1 with a message when the interface cannot be read or set (a restore that
# fails leaves the hub as wg-quick made it: never a reason to fail wg-quick up).
set -euo pipefail

usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//' >&"$((${1:-2} ? 2 : 1))"; exit "${1:-2}"; }
case "${1:-}" in -h | --help) usage 0 ;; esac
[ $# -eq 3 ] || usage
action=$1 interface=$2 dir=$3
file=$dir/wg-$interface.endpoints
[ -d "$dir" ] || { echo "hub_endpoints.sh: no folder $dir (STATE_DIR)" >&2; exit 1; }

case $action in
  save)
    if ! wg show "$interface" endpoints >"$file.new"; then
      rm -f "$file.new"
      echo "hub_endpoints.sh: cannot read $interface's endpoints; $file kept" >&2
      exit 1
    fi
    mv "$file.new" "$file"
    ;;
  restore)
    [ -f "$file" ] || exit 0
    handshakes=$(wg show "$interface" latest-handshakes) || exit 1
    allowed=$(wg show "$interface" allowed-ips)
    preshared=$(wg show "$interface" preshared-keys)
    restored=0
    while read -r key endpoint; do
      if [ -z "$endpoint" ] || [ "$endpoint" = "(none)" ]; then continue; fi
      handshake=$(awk -v k="$key" '$1 == k { print $2 }' <<<"$handshakes")
      [ "$handshake" = 0 ] || continue  # not a peer any more, or already back by itself
      if ! [[ "$endpoint" =~ ^([0-9.]+|\[[0-9A-Fa-f:.]+\]):[0-9]+$ ]]; then
        echo "hub_endpoints.sh: $file: '$endpoint' is no ADDRESS:PORT; peer $key skipped" >&2
        continue
      fi
      ips=$(awk -v k="$key" '$1 == k { $1 = ""; print }' <<<"$allowed" | xargs | tr ' ' ',')
      [ "$ips" != "(none)" ] || ips=""
      psk=$(awk -v k="$key" '$1 == k { print $2 }' <<<"$preshared")
      psk_args=()
      if [ -n "$psk" ] && [ "$psk" != "(none)" ]; then psk_args=(preshared-key /dev/stdin); fi
      wg set "$interface" peer "$key" remove
      if wg set "$interface" peer "$key" allowed-ips "$ips" endpoint "$endpoint" \
          persistent-keepalive 25 "${psk_args[@]}" <<<"$psk"; then
        restored=$((restored + 1))
      else
        echo "hub_endpoints.sh: peer $key not restored; set again without its endpoint" >&2
        wg set "$interface" peer "$key" allowed-ips "$ips" "${psk_args[@]}" <<<"$psk"
      fi
    done <"$file"
    echo "hub_endpoints.sh: $restored peer endpoints restored on $interface from $file" >&2
    ;;
  *) usage ;;
esac
