#!/usr/bin/env bash
# Creates the DDS Security (OMG DDS-Security 1.1, Fast DDS builtin plugins PKI-DH,
# Access-Permissions, AES-GCM-GMAC) files for one mostar robot and its operators.
#
# Run it on an admin computer, not on the robot: the CA keys stay there, and each host gets
# only its own bundle, OUT_DIR/hosts/NAME/ (docs/security.md, "The PKI from zero").
#
# Usage:
#   make_pki.sh OUT_DIR [--robot NAME] [--pilot NAME ...] [--observer NAME ...]
#                       [--relay NAME ...] [--profile BASE.xml] [--domains MIN-MAX]
#                       [--profile-dir DIR] [--install-dir DIR] [--owner USER:GROUP]
#                       [--org ORG] [--days N] [--ca-days N] [--crl-days N]
#   make_pki.sh OUT_DIR --renew NAME [--days N] [--crl-days N] [--owner USER:GROUP]
#   make_pki.sh OUT_DIR --refresh-crl [--crl-days N] [--owner USER:GROUP]
#   make_pki.sh OUT_DIR --update-permissions [--days N] [--owner USER:GROUP]
#
#   --robot NAME     the robot_server identity (default: robot; made on the first run, later
#                    runs leave it alone unless --robot is given)
#   --pilot NAME     an operator allowed to drive (repeatable)
#   --observer NAME  an operator allowed to watch only (repeatable)
#   --relay NAME     a mostar_relay identity (repeatable)
#   --profile FILE   DDS XML profiles file to make secure copies of (default: deploy/dds/lan.xml)
#   --profile-dir D  per-participant profiles: NAME's secure copy is made from D/NAME.dds.xml
#                    when that file exists (deploy/wan/make_overlay.sh writes them), else
#                    from --profile
#   --domains A-B    DDS domain ids the permissions cover (default 0-232)
#   --install-dir D  where each host keeps its bundle: the file:// paths in NAME.xml, e.g.
#                    /etc/mostar/pki (default: OUT_DIR itself, for one computer; remembered
#                    in OUT_DIR/install_dir for later runs)
#   --owner U:G      owner and group of the files in each bundle (needs root); keys are 0640,
#                    so with root:mostar a service running as User=mostar reads its key
#   --days N         lifetime of participant certificates and permissions (default 365)
#   --ca-days N      lifetime of the two CA certificates (default 3650)
#   --crl-days N     validity of the CRL, until its next update (default 31). Fast DDS
#                    refuses every certificate once the CRL has expired: --refresh-crl first
#   --renew NAME     a new key and certificate for NAME (same name and grants, permissions
#                    valid --days from now); the old certificate is revoked as superseded
#   --refresh-crl    only issue a new CRL and put it into every bundle (monthly)
#   --update-permissions
#                    re-sign every participant's permissions with the grants below (for a
#                    PKI made by an earlier version, whose permissions lack the client
#                    partitions: its consoles then fail to create their writers)
#
# Produces in OUT_DIR (existing CAs are reused, so participants can be added later):
#   identity_ca.{cert,key}.pem     signs the participants' certificates (keep the key offline)
#   permissions_ca.{cert,key}.pem  signs governance and permissions (keep the key offline)
#   identity_ca.crl.pem            revocation list (see revoke.sh)
#   governance.xml / governance.p7s          one for all participants
#   NAME.{cert,key}.pem                      each participant's identity (CA:FALSE)
#   NAME.permissions.xml / NAME.permissions.p7s
#   NAME.xml                       the profiles file with this participant's security
#                                  properties (absolute file:// paths into --install-dir)
#                                  inserted at every "mostar:security" marker: run the
#                                  program with --dds-profile INSTALL_DIR/NAME.xml
#   hosts/NAME/                    what NAME's host needs and nothing else:
#                                  identity_ca.cert.pem, permissions_ca.cert.pem,
#                                  identity_ca.crl.pem, governance.p7s, NAME.cert.pem,
#                                  NAME.key.pem (0640), NAME.permissions.p7s, NAME.xml;
#                                  the robot's also `roles` (every certificate's name and
#                                  role, read by robot_server --check-config);
#                                  copy it to INSTALL_DIR on that host (the robot's again
#                                  after adding operators)
# Never copy the CA keys (or OUT_DIR) to robots or operator computers.
#
# Grants (topics are DDS names, see common/dds/topics.h). cmd_vel, estop, control/request and
# clock/ping are published only in the publisher's own partition mostar.client.NAME (the robot
# tells who wrote a sample by the partition it came in: docs/security.md, Identities):
#   robot     publishes camera, scan, odom, health, control/lease, clock/pong;
#             subscribes cmd_vel, estop, control/request, clock/ping in mostar.client.*.
#   pilot     publishes cmd_vel, estop, control/request, clock/ping; subscribes the rest.
#   observer  subscribes camera, scan, odom, health, control/lease, clock/pong;
#             publishes clock/ping and estop (anyone watching may stop the robot), never
#             cmd_vel or control/request.
#   relay     subscribes and publishes camera, scan, odom, health, control/lease (it forwards
#             them to observers) and estop (observers' engagements, read in mostar.client.*,
#             go to the robot under the relay's name; list that name as an OBSERVER in the
#             robot's role table); never cmd_vel, control/request or clock/ping.
#   Every viewer (pilot, observer, relay) also publishes keyframe_request and video_feedback
#   in the default partition (H.264 IDRs, rate control); the robot and the relay subscribe them.
set -euo pipefail

# usage [STATUS]: the header above, to stdout for --help (status 0), else to stderr (status 2).
usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//' >&"$((${1:-2} ? 2 : 1))"; exit "${1:-2}"; }
die() { echo "make_pki.sh: $*" >&2; exit 1; }

[ $# -ge 1 ] || usage
case "$1" in -h|--help) usage 0 ;; -*) die "the first argument is OUT_DIR, not $1" ;; esac
out=$1; shift
robot=robot
robot_given=0
pilots=(); observers=(); relays=()
here=$(cd "$(dirname "$(readlink -f "$0")")" && pwd)  # also through /usr/bin links
profile="$here/../dds/lan.xml"
profile_dir=""
install_dir=""
owner=""
domain_min=0; domain_max=232
org=mostar
days=365
ca_days=3650
crl_days=31
renew=""
refresh_crl=0
update_permissions=0
while [ $# -gt 0 ]; do
  case "$1" in
    --robot) robot=$2; robot_given=1; shift 2 ;;
    --pilot) pilots+=("$2"); shift 2 ;;
    --observer) observers+=("$2"); shift 2 ;;
    --relay) relays+=("$2"); shift 2 ;;
    --profile) profile=$2; shift 2 ;;
    --profile-dir) profile_dir=$(cd "$2" && pwd) || die "no directory $2"; shift 2 ;;
    --domains) domain_min=${2%-*}; domain_max=${2#*-}; shift 2 ;;
    --org) org=$2; shift 2 ;;
    --days) days=$2; shift 2 ;;
    --ca-days) ca_days=$2; shift 2 ;;
    --crl-days) crl_days=$2; shift 2 ;;
    --install-dir) install_dir=$2; shift 2 ;;
    --owner) owner=$2; shift 2 ;;
    --renew) renew=$2; shift 2 ;;
    --refresh-crl) refresh_crl=1; shift ;;
    --update-permissions) update_permissions=1; shift ;;
    -h|--help) usage 0 ;;
    *) die "unknown option $1" ;;
  esac
done
for v in "$days" "$ca_days" "$crl_days"; do
  [[ "$v" =~ ^[1-9][0-9]*$ ]] || die "a lifetime in days must be a positive integer, not '$v'"
done
[ -z "$install_dir" ] || [[ "$install_dir" = /* ]] || die "--install-dir must be absolute"
[ -z "$owner" ] || [[ "$owner" =~ ^[A-Za-z0-9_.-]+:[A-Za-z0-9_.-]+$ ]] || die "--owner must be USER:GROUP"
for n in "$robot" "${pilots[@]}" "${observers[@]}" "${relays[@]}" ${renew:+"$renew"}; do
  [[ "$n" =~ ^[A-Za-z0-9_.-]+$ ]] || die "participant name '$n' must be [A-Za-z0-9_.-]+"
done
[ -f "$profile" ] || die "no profiles file $profile"
command -v openssl >/dev/null || die "openssl is required"

if [ -n "$renew" ] || [ "$refresh_crl" = 1 ] || [ "$update_permissions" = 1 ]; then
  [ -f "$out/ca.cnf" ] || die "$out is no directory made by make_pki.sh"
fi
mkdir -p "$out"
out=$(cd "$out" && pwd)
cd "$out"
umask 077
# The file:// paths in NAME.xml: --install-dir, else the one given before, else OUT_DIR.
if [ -z "$install_dir" ]; then
  if [ -f install_dir ]; then install_dir=$(cat install_dir); else install_dir=$out; fi
fi

# --- certificate authorities (ECDSA P-256), with an openssl 'ca' database for revocation ---
make_ca() {  # name, common name
  [ -f "$1.cert.pem" ] && return 0
  openssl req -x509 -nodes -days "$ca_days" -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 \
    -keyout "$1.key.pem" -out "$1.cert.pem" -subj "/O=$org/CN=$2" 2>/dev/null
}
make_ca identity_ca "$org identity CA"
make_ca permissions_ca "$org permissions CA"
mkdir -p ca_db
[ -f ca_db/index.txt ] || : > ca_db/index.txt
[ -f ca_db/serial ] || echo 1000 > ca_db/serial
[ -f ca_db/crlnumber ] || echo 1000 > ca_db/crlnumber
cat > ca.cnf <<EOF
[ ca ]
default_ca = identity_ca
[ identity_ca ]
dir = $out
database = \$dir/ca_db/index.txt
serial = \$dir/ca_db/serial
crlnumber = \$dir/ca_db/crlnumber
new_certs_dir = \$dir/ca_db
certificate = \$dir/identity_ca.cert.pem
private_key = \$dir/identity_ca.key.pem
default_md = sha256
default_days = $days
default_crl_days = $crl_days
policy = policy_any
unique_subject = no
copy_extensions = none
x509_extensions = participant_ext
[ policy_any ]
organizationName = supplied
commonName = supplied
[ participant_ext ]
basicConstraints = critical, CA:FALSE
subjectKeyIdentifier = hash
authorityKeyIdentifier = keyid, issuer
EOF

make_identity() {  # name [subject]
  [ -f "$1.cert.pem" ] && return 0
  openssl req -nodes -new -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 \
    -keyout "$1.key.pem" -out "$1.csr.pem" -subj "${2:-/O=$org/CN=$1}" 2>/dev/null
  openssl ca -batch -config ca.cnf -notext -in "$1.csr.pem" -out "$1.cert.pem" 2>/dev/null
  rm -f "$1.csr.pem"
}

# The role of participant NAME: from OUT_DIR/roles, else read off its permissions (made before
# roles were recorded): what it publishes tells.
role_of() {
  local role publishes
  role=$(awk -v n="$1" '$1 == n { print $2 }' roles 2>/dev/null || true)
  if [ -z "$role" ]; then
    publishes=$(sed -n '/<publish>/,/<\/publish>/p' "$1.permissions.xml")
    case $publishes in
      *rt/mostar/clock/pong*) role=robot ;;
      *rt/mostar/cmd_vel*) role=pilot ;;
      *rt/mostar/scan*) role=relay ;;
      *) role=observer ;;
    esac
  fi
  echo "$role"
}

# --- bundles: what each host needs, nothing else ---
make_bundles() {
  local p name dir f
  for p in ./*.permissions.p7s; do
    [ -e "$p" ] || continue
    name=${p#./}; name=${name%.permissions.p7s}
    [ -f "$name.cert.pem" ] && [ -f "$name.key.pem" ] && [ -f "$name.xml" ] || continue
    dir="hosts/$name"
    mkdir -p "$dir"
    for f in identity_ca.cert.pem permissions_ca.cert.pem identity_ca.crl.pem governance.p7s \
             "$name.cert.pem" "$name.permissions.p7s" "$name.xml"; do
      cp "$f" "$dir/$f"; chmod 0644 "$dir/$f"
    done
    cp "$name.key.pem" "$dir/$name.key.pem"; chmod 0640 "$dir/$name.key.pem"
    # The robot's bundle also lists every certificate's name and role, so that
    # robot_server --check-config can compare its role table with them.
    if [ "$(role_of "$name")" = robot ] && [ -f roles ]; then
      cp roles "$dir/roles"; chmod 0644 "$dir/roles"
    fi
    chmod 0755 hosts "$dir"
    [ -z "$owner" ] || chown -R "$owner" "$dir"
  done
}
issue_crl() {
  openssl ca -batch -config ca.cnf -gencrl -out identity_ca.crl.pem 2>/dev/null
  chmod 644 identity_ca.crl.pem
}

if [ "$refresh_crl" = 1 ]; then
  issue_crl
  make_bundles
  echo "make_pki.sh: new CRL in $out (next update in $crl_days days); copy" \
    "identity_ca.crl.pem to every host and restart the programs"
  exit 0
fi

if [ -n "$renew" ]; then
  [ -f "$renew.cert.pem" ] && [ -f "$renew.permissions.xml" ] || die "no participant $renew in $out"
  # The same subject (the permissions name it): /O=.../CN=NAME of the old certificate.
  subject=$(openssl x509 -in "$renew.cert.pem" -noout -subject -nameopt compat | sed 's/^subject=//')
  openssl ca -batch -config ca.cnf -revoke "$renew.cert.pem" -crl_reason superseded 2>/dev/null ||
    die "cannot revoke the old certificate of $renew"
  rm -f "$renew.cert.pem" "$renew.key.pem"
  make_identity "$renew" "$subject"
  # Same grants, valid from now: re-sign the permissions.
  validity="<validity><not_before>$(date -u +%Y-%m-%dT%H:%M:%S)</not_before>"
  validity+="<not_after>$(date -u -d "+$days days" +%Y-%m-%dT%H:%M:%S)</not_after></validity>"
  sed -i "s|<validity>.*</validity>|$validity|" "$renew.permissions.xml"
  openssl smime -sign -text -in "$renew.permissions.xml" -out "$renew.permissions.p7s" \
    -signer permissions_ca.cert.pem -inkey permissions_ca.key.pem
  issue_crl
  chmod 644 "$renew.cert.pem" "$renew.permissions.p7s"
  make_bundles
  echo "make_pki.sh: renewed $renew (valid $days days); copy hosts/$renew/ to its host and" \
    "identity_ca.crl.pem to every host, then restart the programs"
  exit 0
fi

# --- governance: who may join, what is protected ---
cat > governance.xml <<EOF
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>$domain_min</min><max>$domain_max</max></id_range></domains>
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>NONE</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>rt/mostar/cmd_vel</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>ENCRYPT</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
        <topic_rule>
          <topic_expression>rt/mostar/*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>false</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>SIGN</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
EOF
openssl smime -sign -text -in governance.xml -out governance.p7s \
  -signer permissions_ca.cert.pem -inkey permissions_ca.key.pem

# --- permissions per participant ---
# What the robot must know the sender of (commands, e-stops, control requests, clock pings) is
# published in the sender's own partition, mostar.client.NAME, and nowhere else: Fast DDS checks
# a remote writer's partitions against the permissions of the certificate that authenticated,
# so the robot, reading each client in its partition, knows who wrote a sample whatever GUID the
# participant announced (docs/security.md, Identities). Everything else is in the default
# partition.
sensors="rt/mostar/camera/* rt/mostar/scan rt/mostar/odom rt/mostar/sonar rt/mostar/sonar/* rt/mostar/bumpers rt/mostar/health rt/mostar/control/lease"
privileged="rt/mostar/cmd_vel rt/mostar/estop rt/mostar/control/request rt/mostar/clock/ping"
# Viewers' requests for an H.264 IDR and their receive reports (rate control): in the default
# partition, since the robot only rate-limits them (one IDR per 300 ms, a bounded table of
# reports) whoever sends them.
viewer_requests="rt/mostar/keyframe_request rt/mostar/video_feedback"
topics_xml() { for t in "$@"; do printf '            <topic>%s</topic>\n' "$t"; done; }
criteria() {  # publish|subscribe, "topics", partition ("" = the default partition)
  [ -n "$2" ] || return 0
  printf '        <%s>\n          <topics>\n' "$1"
  # shellcheck disable=SC2086
  topics_xml $2
  printf '          </topics>\n'
  [ -z "$3" ] || printf '          <partitions><partition>%s</partition></partitions>\n' "$3"
  printf '        </%s>\n' "$1"
}
# One <allow_rule>. Fast DDS decides a topic by the first rule naming it, and accepts a
# partition listed anywhere in that rule's publish (or subscribe) criteria: topics in other
# partitions go into a rule of their own.
allow_rule() {  # "publish topics", partition, "subscribe topics", partition
  printf '      <allow_rule>\n'
  printf '        <domains><id_range><min>%s</min><max>%s</max></id_range></domains>\n' \
    "$domain_min" "$domain_max"
  criteria publish "$1" "$2"
  criteria subscribe "$3" "$4"
  printf '      </allow_rule>\n'
}
rules_for() {  # role, name
  case $1 in
    robot)
      allow_rule "$sensors rt/mostar/clock/pong" "" "$privileged" "mostar.client.*"
      allow_rule "" "" "$viewer_requests" "" ;;
    pilot)
      allow_rule "$privileged" "mostar.client.$2" "$sensors rt/mostar/clock/pong" ""
      allow_rule "$viewer_requests" "" "" "" ;;
    observer)
      allow_rule "rt/mostar/clock/ping rt/mostar/estop" "mostar.client.$2" \
        "$sensors rt/mostar/clock/pong" ""
      allow_rule "$viewer_requests" "" "" "" ;;
    relay)
      allow_rule "$sensors $viewer_requests" "" "$sensors $viewer_requests" ""
      allow_rule "rt/mostar/estop" "mostar.client.$2" "rt/mostar/estop" "mostar.client.*" ;;
    *) die "unknown role '$1' of $2" ;;
  esac
}
make_permissions() {  # name, role
  local subject not_before not_after
  subject=$(openssl x509 -in "$1.cert.pem" -noout -subject -nameopt RFC2253 | sed 's/^subject=//')
  not_before=$(date -u +%Y-%m-%dT%H:%M:%S)
  not_after=$(date -u -d "+$days days" +%Y-%m-%dT%H:%M:%S)
  cat > "$1.permissions.xml" <<EOF
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">
  <permissions>
    <grant name="$1_grant">
      <subject_name>$subject</subject_name>
      <validity><not_before>$not_before</not_before><not_after>$not_after</not_after></validity>
$(rules_for "$2" "$1")
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
EOF
  openssl smime -sign -text -in "$1.permissions.xml" -out "$1.permissions.p7s" \
    -signer permissions_ca.cert.pem -inkey permissions_ca.key.pem
  # Each participant's role, for --update-permissions.
  { grep -v "^$1 " roles 2>/dev/null || true; echo "$1 $2"; } > roles.new
  mv roles.new roles
}

if [ "$update_permissions" = 1 ]; then
  for f in ./*.permissions.xml; do
    [ -e "$f" ] || continue
    name=${f#./}; name=${name%.permissions.xml}
    make_permissions "$name" "$(role_of "$name")"
    chmod 644 "$name.permissions.p7s"
  done
  make_bundles
  echo "make_pki.sh: permissions re-signed with client partitions ($(tr '\n' ' ' < roles));" \
    "copy each NAME.permissions.p7s (or hosts/NAME/) to its host and restart the programs"
  exit 0
fi

# --- a secure copy of the profiles file for each participant ---
make_profile() {  # name
  local f="file://$install_dir"
  local props
  props=$(cat <<EOF
<propertiesPolicy>
          <properties>
            <property><name>dds.sec.auth.plugin</name><value>builtin.PKI-DH</value></property>
            <property><name>dds.sec.auth.builtin.PKI-DH.identity_ca</name><value>$f/identity_ca.cert.pem</value></property>
            <property><name>dds.sec.auth.builtin.PKI-DH.identity_certificate</name><value>$f/$1.cert.pem</value></property>
            <property><name>dds.sec.auth.builtin.PKI-DH.identity_crl</name><value>$f/identity_ca.crl.pem</value></property>
            <property><name>dds.sec.auth.builtin.PKI-DH.private_key</name><value>$f/$1.key.pem</value></property>
            <property><name>dds.sec.access.plugin</name><value>builtin.Access-Permissions</value></property>
            <property><name>dds.sec.access.builtin.Access-Permissions.permissions_ca</name><value>$f/permissions_ca.cert.pem</value></property>
            <property><name>dds.sec.access.builtin.Access-Permissions.governance</name><value>$f/governance.p7s</value></property>
            <property><name>dds.sec.access.builtin.Access-Permissions.permissions</name><value>$f/$1.permissions.p7s</value></property>
            <property><name>dds.sec.crypto.plugin</name><value>builtin.AES-GCM-GMAC</value></property>
          </properties>
        </propertiesPolicy>
EOF
)
  local source=$profile
  if [ -n "$profile_dir" ] && [ -f "$profile_dir/$1.dds.xml" ]; then source="$profile_dir/$1.dds.xml"; fi
  grep -q "mostar:security" "$source" || die "$source has no <!-- mostar:security --> marker"
  PROPS="$props" awk '{ if ($0 ~ /<!-- mostar:security -->/) { match($0, /^ */); printf "%s%s\n", substr($0, 1, RLENGTH), ENVIRON["PROPS"] } else print }' \
    "$source" > "$1.xml"
}

echo "$install_dir" > install_dir
if [ "$robot_given" = 1 ] || [ ! -f "$robot.cert.pem" ]; then
  make_identity "$robot"
  make_permissions "$robot" robot
  make_profile "$robot"
fi
for p in "${pilots[@]}"; do
  make_identity "$p"
  make_permissions "$p" pilot
  make_profile "$p"
done
for o in "${observers[@]}"; do
  make_identity "$o"
  make_permissions "$o" observer
  make_profile "$o"
done
for r in "${relays[@]}"; do
  make_identity "$r"
  make_permissions "$r" relay
  make_profile "$r"
done

issue_crl
chmod 644 ./*.cert.pem ./*.p7s ./*.xml
make_bundles
echo "make_pki.sh: wrote $out (robot: $robot; pilots: ${pilots[*]:-none};" \
  "observers: ${observers[*]:-none}; relays: ${relays[*]:-none}); copy hosts/NAME/ to" \
  "$install_dir on NAME's host"
