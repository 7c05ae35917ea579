#!/usr/bin/env bash
# The GUID-forging insider (issue #38) against the real robot_server on the simulator, across a
# veth pair between two network namespaces: the robot in one; in the other a live pilot
# (identity_actor as alice, holding the lease, idle commands and clock pings), a witness
# (insider_witness: an honest observer, watcher, printing the robot's health and lease) and the
# insider (insider_forger, Cyclone DDS): it holds carol's (observer), mallory's (pilot) or the
# relay's credentials, announces alice's GUID and certificate, signs the handshake with its own
# key, and tries alice's privileges in the old wire form (no partition) and in the partitions
# mostar.client.alice and mostar.client.<own>.
#
# Usage: insider_test.sh ROBOT_SERVER IDENTITY_ACTOR INSIDER_FORGER INSIDER_WITNESS SOURCE_DIR
#
# One fresh robot per credential, the credentials side by side; the forger tries the privileges one after the other in that
# session (clock_pings, cmd_vel, lease_release, then estop_release, for which the observer
# watcher engages the e-stop first). Each privilege is judged from what the witness saw in that
# privilege's own window, from its first try's start to its last try's end plus 3 s (the
# forger's INSIDER lines), against the last state before the window:
#   clock_pings    alice's commands were rejected as stale (drive_safety.rejected_stale rose)
#   cmd_vel        the robot accepted a command with the forger's sequence numbers
#   lease_release  the lease left alice (holder or lease_sequence changed)
#   estop_release  the e-stop (engaged by the observer watcher) was released
# Prints the table credential | forged id | privilege | outcome | evidence and fails unless every
# row is blocked. A writer the credential's permissions refuse (Cyclone's own access control, with
# the forger's --local-access-control) is the route blocked, not an error. Exit 77 (CTest:
# skipped) when network namespaces cannot be created.
# Environment: INSIDER_CREDENTIALS, INSIDER_PRIVILEGES (subsets), INSIDER_MAKE_PKI (another
# make_pki.sh), INSIDER_PROFILE=lan|overlay (the robot's profile: deploy/dds/lan.xml, or
# overlay.xml with the namespaces' addresses, the Cyclone participants then discovering the
# robot by unicast only; not wan.xml: Cyclone DDS does not speak Fast DDS's TCP transport),
# KEEP_WORK=1 (keep the work directory).
set -euo pipefail
[ $# -eq 5 ] || {
  echo "usage: insider_test.sh ROBOT_SERVER IDENTITY_ACTOR INSIDER_FORGER INSIDER_WITNESS SOURCE_DIR" >&2
  exit 2
}
robot_server=$1; actor=$2; forger=$3; witness=$4; src=$5
net="$src/tests/network"
"$net/netns.sh" check || exit 77

credentials=${INSIDER_CREDENTIALS:-"carol mallory relay"}
privileges=${INSIDER_PRIVILEGES:-"clock_pings cmd_vel lease_release estop_release"}
# The order in a session: estop_release last (the e-stop stays engaged once pressed), cmd_vel
# after clock_pings (accepted forged commands would make alice's own ones out of order).
order=""
for p in clock_pings cmd_vel lease_release estop_release; do
  for q in $privileges; do [ "$q" != "$p" ] || { order+=" $p"; break; }; done
done
for p in $privileges; do
  case " $order " in *" $p "*) ;; *) echo "insider_test: unknown privilege $p" >&2; exit 2 ;; esac
done
make_pki=${INSIDER_MAKE_PKI:-"$src/deploy/security/make_pki.sh"}
prefix="mins$$"
work=$(mktemp -d /tmp/mostar_insider_XXXXXX)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  sleep 1
  pkill -9 -f "$work" 2>/dev/null || true  # the sessions' programs (their arguments name $work)
  for p in "${pids[@]}"; do kill -9 "$p" 2>/dev/null || true; wait "$p" 2>/dev/null || true; done
  local i
  for i in "${!cred_list[@]}"; do "$net/netns.sh" down "$prefix$i" || true; done
  if [ "${KEEP_WORK:-0}" = 1 ]; then echo "work dir kept: $work"; else rm -rf "$work"; fi
}
read -r -a cred_list <<< "$credentials"
trap cleanup EXIT
trap "exit 1" INT TERM
# The credentials' sessions run side by side, each in its own pair of namespaces (the addresses
# of netns.sh) and its own domain (the pairs share this host's /dev/shm).
for i in "${!cred_list[@]}"; do
  "$net/netns.sh" up "$prefix$i"
  # lan.xml discovers by multicast: send it over the veth pair, not the namespace's loopback.
  for ns in "$prefix${i}_robot" "$prefix${i}_operator"; do
    ip -n "$ns" route replace 224.0.0.0/4 dev veth0
  done
done
pki="$work/pki"
robot_addr=10.231.0.1; operator_addr=10.231.0.2  # tests/network/netns.sh
case ${INSIDER_PROFILE:-lan} in
  lan) profile="$src/deploy/dds/lan.xml"; profile_dir=() ;;
  overlay)
    # As attack_test.sh: make_overlay.sh's per-peer files with the namespaces' addresses.
    profile="$work/operator.dds.xml"; profile_dir=(--profile-dir "$work")
    for f in "$work/robot.dds.xml:$robot_addr" "$profile:$operator_addr"; do
      sed -e "/mostar:overlay-address/s|<address>[0-9.]*</address>|<address>${f#*:}</address>|" \
        -e "/mostar:robot-address/s|<address>[0-9.]*</address>|<address>$robot_addr</address>|" \
        "$src/deploy/dds/overlay.xml" > "${f%%:*}"
    done
    # Cyclone: the veth address only, no multicast, the robot as its one peer.
    export CYCLONEDDS_URI="<CycloneDDS><Domain id=\"any\"><General><Interfaces><NetworkInterface address=\"$operator_addr\"/></Interfaces><AllowMulticast>false</AllowMulticast><MaxMessageSize>8192B</MaxMessageSize></General><Discovery><ParticipantIndex>auto</ParticipantIndex><Peers><Peer address=\"$robot_addr\"/></Peers></Discovery></Domain></CycloneDDS>" ;;
  *) echo "insider_test: INSIDER_PROFILE must be lan or overlay" >&2; exit 2 ;;
esac

# Cyclone DDS takes domain ids up to 230 in governance and permissions.
"$make_pki" "$pki" --profile "$profile" "${profile_dir[@]}" --domains 0-230 --pilot alice \
  --pilot mallory --observer carol --observer watcher --relay relay > "$work/make_pki.log" 2>&1 \
  || { cat "$work/make_pki.log"; exit 1; }

cat > "$work/robot.pbtxt" <<EOF
robot_id: "insider-target"
source: SIM
scene_file: "$src/deploy/scenes/corridor.pbtxt"
test_pattern { frame_rate_hz: 10 jpeg_quality: 60 }
laser { baud: 38400 angle_deg: 180 resolution_cdeg: 100 unit: MM }
drive {
  limits { max_linear_mps: 0.6 max_reverse_mps: 0.2 max_angular_radps: 1.0 }
  safety { deadman_period_ms: 250 max_command_age_ms: 300 stop_distance_m: 0.30 slow_distance_m: 1.20 }
  geometry { robot_width_m: 0.68 front_extent_m: 0.15 }
  roles { client_id: "alice" role: PILOT strength: 10 }
  roles { client_id: "mallory" role: PILOT strength: 5 }
  roles { client_id: "carol" role: OBSERVER }
  roles { client_id: "watcher" role: OBSERVER }
  roles { client_id: "relay" role: OBSERVER }
}
EOF

creds() {  # the Cyclone credential flags of NAME
  echo --identity-ca "$pki/identity_ca.cert.pem" --cert "$pki/$1.cert.pem" \
    --key "$pki/$1.key.pem" --permissions-ca "$pki/permissions_ca.cert.pem" \
    --governance "$pki/governance.p7s" --permissions "$pki/$1.permissions.p7s"
}
start() {  # start NS LOG COMMAND...: in the background, pid in $started
  local ns=$1 log=$2; shift 2
  ip netns exec "$ns" "$@" > "$log" 2>&1 &
  started=$!
  pids+=("$started")
}
stop() { kill "$@" 2>/dev/null || true; for p in "$@"; do wait "$p" 2>/dev/null || true; done; }
# Waits up to $2 s until the witness log $1 has a line matching the regex $3.
wait_for() {
  local i
  for ((i = 0; i < $2 * 10; i++)); do grep -qE "$3" "$1" && return 0; sleep 0.1; done
  return 1
}
field() { sed -n "s/.* $1=\([^ ]*\).*/\1/p"; }

# judge WITNESS_LOG FORGER_OUT PRIVILEGE -> "outcome evidence"
judge() {
  local wlog=$1 fout=$2 priv=$3
  local t0 t1
  t0=$(grep "^INSIDER name=$priv " "$fout" | head -1 | field t_start)
  t1=$(grep "^INSIDER name=$priv " "$fout" | tail -1 | field t_end)
  [ -n "$t0" ] || { echo "error forger_made_no_try"; return; }
  awk -v t0="$t0" -v t1="$t1" -v priv="$priv" '
    function val(k,   i, kv) { for (i = 1; i <= NF; i++) { split($i, kv, "="); if (kv[1] == k) return kv[2] } return "" }
    /^WITNESS/ {
      t = val("t") + 0; kind = val("kind")
      if (t < t0) {
        if (kind == "health") { b_estop = val("estop"); b_stale = val("rejected_stale") + 0; b_holder = val("holder"); nb++ }
        if (kind == "lease") { b_seq = val("lease_sequence"); b_lholder = val("holder") }
        next
      }
      if (t > t1 + 3) next
      if (kind == "health") {
        na++
        if (val("estop") == "0") released = 1
        if (val("holder") != "alice") left = 1
        s = val("rejected_stale") + 0; if (s > max_stale) max_stale = s
        if (val("last_command_sequence") + 0 >= 3000000000) forged_cmd = 1
      }
      if (kind == "lease") { if (val("holder") != "alice" || (b_seq != "" && val("lease_sequence") != b_seq)) left = 1; last_seq = val("lease_sequence") }
    }
    END {
      if (nb == 0 || na == 0) { print "error witness_saw_no_health_before_or_after"; exit }
      if (b_holder != "alice") { print "error alice_did_not_hold_the_lease_before holder=" b_holder; exit }
      if (priv == "estop_release") {
        if (b_estop != "1") { print "error estop_not_engaged_before"; exit }
        print (released ? "open" : "blocked") " estop_released=" (released ? 1 : 0)
      } else if (priv == "clock_pings") {
        if (max_stale + 0 < b_stale) max_stale = b_stale
        print (max_stale - b_stale > 5 ? "open" : "blocked") " rejected_stale=" b_stale "->" max_stale + 0
      } else if (priv == "lease_release") {
        print (left ? "open" : "blocked") " lease_left_alice=" (left ? 1 : 0) " lease_sequence=" b_seq "->" (last_seq == "" ? b_seq : last_seq)
      } else {
        print (forged_cmd ? "open" : "blocked") " forged_command_accepted=" (forged_cmd ? 1 : 0)
      }
    }' "$wlog"
}

# One credential's session: robot, witness, alice and the forger in pair number $2, on domain
# 120 + 10 * $2 + pid % 10; its rows go to $work/CRED.rows, its log to $work/CRED.out.
session() {
  local cred=$1 i=$2
  local robot_ns="$prefix${i}_robot" operator_ns="$prefix${i}_operator"
  local domain=$((120 + 10 * i + $$ % 10))
  local robot_pid witness_pid alice_pid forger_pid ok engaged go tries authenticated priv
  local outcome evidence matched extra
  echo "== $cred forging alice:$order"
  start "$robot_ns" "$work/$cred.robot.log" "$robot_server" --domain "$domain" \
    --config "$work/robot.pbtxt" --source sim --dds-profile "$pki/robot.xml"
  robot_pid=$started
  # shellcheck disable=SC2046
  start "$operator_ns" "$work/$cred.witness" "$witness" --domain "$domain" $(creds watcher) \
    --duration-s 300
  witness_pid=$started
  start "$operator_ns" "$work/$cred.alice.log" "$actor" --domain "$domain" \
    --dds-profile "$pki/alice.xml" --sender-id alice --take --commands idle --pings \
    --duration-s 300
  alice_pid=$started
  ok=1
  wait_for "$work/$cred.witness" 40 'kind=health .*holder=alice' || ok=0
  engaged=1
  if [ "$ok" = 1 ]; then
    sleep 2
    tries=()
    for p in $order; do tries+=(--try "$p"); done
    go="$work/$cred.go"
    # shellcheck disable=SC2046
    ip netns exec "$operator_ns" timeout 240 "$forger" --domain "$domain" $(creds "$cred") \
      --victim-cert "$pki/alice.cert.pem" --victim alice --self "$cred" "${tries[@]}" \
      --wait-before estop_release --go-file "$go" > "$work/$cred.forger" \
      2> "$work/$cred.forger.err" &
    forger_pid=$!
    pids+=("$forger_pid")
    if [[ " $order " = *" estop_release "* ]]; then
      engaged=0
      while kill -0 "$forger_pid" 2>/dev/null \
        && ! grep -q '^INSIDER_WAITING name=estop_release' "$work/$cred.forger"; do sleep 0.1; done
      if grep -q '^INSIDER_WAITING name=estop_release' "$work/$cred.forger"; then
        # The observer watcher presses the e-stop (it may); the robot keeps it engaged. A press
        # whose participant the robot did not match in time is pressed again (at most 3 times).
        for attempt in 1 2 3; do
          ip netns exec "$operator_ns" "$actor" --domain "$domain" --dds-profile "$pki/watcher.xml" \
            --sender-id watcher --estop engage --duration-s 3 >> "$work/$cred.engage.log" 2>&1 || true
          if wait_for "$work/$cred.witness" 5 'kind=health estop=1'; then engaged=$attempt; break; fi
        done
      fi
      touch "$go"
    fi
    wait "$forger_pid" || true
    sleep 3
    cat "$work/$cred.forger"
  fi
  authenticated=$(grep -c "alice.*authenticated\|authenticated.*alice" "$work/$cred.robot.log" || true)
  for priv in $order; do
    if [ "$ok" = 1 ]; then
      read -r outcome evidence <<< "$(judge "$work/$cred.witness" "$work/$cred.forger" "$priv")"
      [ "$priv" != estop_release ] || [ "$engaged" != 0 ] || evidence+=" (the watcher's e-stop was not seen engaged)"
    else
      outcome=error
      evidence="setup_failed(alice_not_holding_the_lease)"
    fi
    matched=$(grep "^INSIDER name=$priv " "$work/$cred.forger" 2>/dev/null \
      | sed -n 's/.* wire=\([a-z]*\) .* outcome=\([a-z_]*\) matched=\([0-9]*\).*/\1:\2:\3/p' | tr '\n' ',' || true)
    extra=""
    if [ "$priv" = estop_release ]; then
      extra=" engaged_at_press=$engaged robot_log_release_from_alice=$(grep -c "emergency stop release from alice$" "$work/$cred.robot.log" || true)"
    fi
    echo "| $cred | alice | $priv | $outcome | $evidence wires=${matched%,} robot_log_alice_authenticated=$authenticated$extra |" >> "$work/$cred.rows"
  done
  stop "$alice_pid" "$witness_pid" "$robot_pid"
}

session_pids=()
for i in "${!cred_list[@]}"; do
  session "${cred_list[$i]}" "$i" > "$work/${cred_list[$i]}.out" 2>&1 &
  session_pids+=($!)
done
for p in "${session_pids[@]}"; do wait "$p" || true; done
rows=()
failures=0
for cred in "${cred_list[@]}"; do
  cat "$work/$cred.out"
  while IFS= read -r r; do
    rows+=("$r")
    [[ "$r" = *" | blocked | "* ]] || failures=$((failures + 1))
  done < <(cat "$work/$cred.rows" 2>/dev/null || echo "| $cred | alice | - | error | the session wrote no rows |")
done

echo
echo "| credential | forged id | privilege | outcome | evidence |"
echo "|---|---|---|---|---|"
for r in "${rows[@]}"; do echo "$r"; done
echo
if [ "$failures" -ne 0 ]; then
  echo "FAIL: $failures insider attempt(s) not blocked"
  for f in "$work"/*.forger.err; do echo "--- $f"; grep -v '^$' "$f" | tail -5; done
  exit 1
fi
echo "insider_test: all insider attempts blocked"
