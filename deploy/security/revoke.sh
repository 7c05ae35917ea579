#!/usr/bin/env bash
# Revokes a participant's identity certificate and regenerates the CRL.
#
# Usage: revoke.sh PKI_DIR NAME
#
# PKI_DIR is a directory made by make_pki.sh. Afterwards copy PKI_DIR/identity_ca.crl.pem to
# every robot and operator computer and restart their programs: Fast DDS reads the CRL
# (property dds.sec.auth.builtin.PKI-DH.identity_crl) when a participant starts, and then
# refuses to authenticate the revoked certificate.
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: revoke.sh PKI_DIR NAME" >&2; exit 2; }
cd "$1"
[ -f ca.cnf ] && [ -f "$2.cert.pem" ] || { echo "revoke.sh: no $2.cert.pem or ca.cnf in $1" >&2; exit 1; }
openssl ca -batch -config ca.cnf -revoke "$2.cert.pem" 2>/dev/null
openssl ca -batch -config ca.cnf -gencrl -out identity_ca.crl.pem 2>/dev/null
chmod 644 identity_ca.crl.pem
echo "revoke.sh: revoked $2; distribute $(pwd)/identity_ca.crl.pem and restart the participants"
