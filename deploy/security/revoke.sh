#!/usr/bin/env bash
# Revokes a participant's identity certificate and regenerates the CRL.
#
# Usage: revoke.sh PKI_DIR NAME
#
# PKI_DIR is a directory made by make_pki.sh (on the admin computer that keeps the CA keys).
# The new CRL is also put into every host bundle (PKI_DIR/hosts/*/). Afterwards copy
# identity_ca.crl.pem to every robot and operator computer and restart their programs: Fast
# DDS reads the CRL (property dds.sec.auth.builtin.PKI-DH.identity_crl) when a participant
# starts, and then refuses to authenticate the revoked certificate. The name's line in
# PKI_DIR/roles (and the robot bundle's copy) says "revoked": copy the robot's bundle again and
# remove the name from its role table (robot_server --check-config says so). Issuing the name
# again (make_pki.sh --pilot NAME) gives it a new certificate and role. The CRL is valid for
# make_pki.sh's --crl-days (31 by default): `make_pki.sh PKI_DIR --refresh-crl` before then.
set -euo pipefail
case "${1:-}" in -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;; esac
[ $# -eq 2 ] || { echo "usage: revoke.sh PKI_DIR NAME" >&2; exit 2; }
cd "$1"
[ -f ca.cnf ] && [ -f "$2.cert.pem" ] || { echo "revoke.sh: no $2.cert.pem or ca.cnf in $1" >&2; exit 1; }
openssl ca -batch -config ca.cnf -revoke "$2.cert.pem" 2>/dev/null
openssl ca -batch -config ca.cnf -gencrl -out identity_ca.crl.pem 2>/dev/null
chmod 644 identity_ca.crl.pem
for bundle in hosts/*/; do
  [ -d "$bundle" ] && cp identity_ca.crl.pem "$bundle" && chmod 644 "$bundle/identity_ca.crl.pem"
done
# The roles file marks the name revoked (robot_server --check-config then names a role-table
# line that nobody can act as any more); the robot's bundle gets it again.
if [ -f roles ]; then
  awk -v n="$2" '$1 == n { $2 = "revoked" } { print }' roles >roles.new && mv roles.new roles
  for bundle in hosts/*/; do
    [ -f "$bundle/roles" ] && cp roles "$bundle/roles" && chmod 644 "$bundle/roles"
  done
fi
echo "revoke.sh: revoked $2; distribute $(pwd)/identity_ca.crl.pem and restart the participants"
