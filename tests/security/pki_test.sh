#!/usr/bin/env bash
# deploy/security/make_pki.sh and revoke.sh, checked with openssl: participant certificates are
# no CAs and live about a year, the CRL about a month, each host bundle holds its own files and
# no CA key, renewal keeps the name and revokes the old certificate, revocation reaches the
# bundles. No network, no DDS.
#
# Usage: pki_test.sh SOURCE_DIR
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: pki_test.sh SOURCE_DIR" >&2; exit 2; }
src=$1
make_pki="$src/deploy/security/make_pki.sh"
revoke="$src/deploy/security/revoke.sh"
command -v openssl >/dev/null || { echo "pki_test: openssl is missing"; exit 77; }
work=$(mktemp -d /tmp/mostar_pki_XXXXXX)
trap 'rm -rf "$work"' EXIT

failures=0
check() {  # description, condition
  if eval "$2"; then echo "ok: $1"; else echo "FAIL: $1 ($2)"; failures=$((failures + 1)); fi
}
epoch() { date -u -d "$1" +%s; }
days_between() { echo $((($(epoch "$2") - $(epoch "$1")) / 86400)); }
cert_days() {
  days_between "$(openssl x509 -in "$1" -noout -startdate | cut -d= -f2)" \
    "$(openssl x509 -in "$1" -noout -enddate | cut -d= -f2)"
}
crl_days() {
  days_between "$(openssl crl -in "$1" -noout -lastupdate | cut -d= -f2)" \
    "$(openssl crl -in "$1" -noout -nextupdate | cut -d= -f2)"
}
basic_constraints() { openssl x509 -in "$1" -noout -ext basicConstraints | tail -n +2 | tr -d ' '; }
serial() { openssl x509 -in "$1" -noout -serial | cut -d= -f2; }
verifies() {  # certificate: against the identity CA with the CRL
  openssl verify -CAfile "$pki/identity_ca.cert.pem" -crl_check \
    -CRLfile "$pki/identity_ca.crl.pem" "$1" >/dev/null 2>&1
}

pki="$work/admin/pki"
"$make_pki" "$pki" --profile "$src/deploy/dds/lan.xml" --install-dir /etc/mostar/pki \
  --robot robot --pilot alice --observer carol --relay hub >/dev/null

for n in robot alice carol hub; do
  check "$n's certificate is no CA" '[ "$(basic_constraints "$pki/$n.cert.pem")" = "CA:FALSE" ]'
  check "$n's certificate lives about a year" \
    '[ "$(cert_days "$pki/$n.cert.pem")" -ge 360 ] && [ "$(cert_days "$pki/$n.cert.pem")" -le 370 ]'
  check "$n's certificate verifies against the identity CA and the CRL" 'verifies "$pki/$n.cert.pem"'
done
check "the identity CA is a CA" '[ "$(basic_constraints "$pki/identity_ca.cert.pem")" = "CA:TRUE" ]'
check "the CAs live longer than the participants" \
  '[ "$(cert_days "$pki/identity_ca.cert.pem")" -gt 3000 ]'
check "the CRL is valid about a month" \
  '[ "$(crl_days "$pki/identity_ca.crl.pem")" -ge 28 ] && [ "$(crl_days "$pki/identity_ca.crl.pem")" -le 31 ]'
not_after=$(sed -n 's|.*<not_after>\([^<]*\)</not_after>.*|\1|p' "$pki/alice.permissions.xml")
check "the permissions expire with the certificate (within a day)" \
  '[ $(( $(epoch "$not_after") - $(epoch "$(openssl x509 -in "$pki/alice.cert.pem" -noout -enddate | cut -d= -f2)") )) -le 86400 ]'

bundle="$pki/hosts/robot"
# roles: every certificate's name and role, for robot_server --check-config (no secret).
expected="governance.p7s identity_ca.cert.pem identity_ca.crl.pem permissions_ca.cert.pem robot.cert.pem robot.key.pem robot.permissions.p7s robot.xml roles"
check "the robot's bundle holds its own files and nothing else" \
  '[ "$(cd "$bundle" && ls | sort | tr "\n" " " | sed "s/ $//")" = "$expected" ]'
check "the robot's roles file names every participant with its role" \
  'grep -qx "robot robot" "$bundle/roles" && grep -qx "alice pilot" "$bundle/roles"'
check "only the robot's bundle has the roles file" '[ ! -e "$pki/hosts/alice/roles" ]'
check "no bundle holds a CA key" '! ls "$pki"/hosts/*/*_ca.key.pem >/dev/null 2>&1'
check "a bundle's key is 0640, its certificate 0644" \
  '[ "$(stat -c %a "$bundle/robot.key.pem")" = 640 ] && [ "$(stat -c %a "$bundle/robot.cert.pem")" = 644 ]'
check "the bundle's profile points into the install directory" \
  'grep -q "file:///etc/mostar/pki/robot.key.pem" "$bundle/robot.xml" && ! grep -q "$pki" "$bundle/robot.xml"'
check "the bundle's key matches its certificate" \
  '[ "$(openssl pkey -in "$bundle/robot.key.pem" -pubout)" = "$(openssl x509 -in "$bundle/robot.cert.pem" -noout -pubkey)" ]'

# A participant added later keeps the CAs and the install directory.
ca_before=$(serial "$pki/identity_ca.cert.pem")
cp "$pki/robot.xml" "$work/robot_before.xml"
"$make_pki" "$pki" --profile "$src/deploy/dds/wan.xml" --pilot bob >/dev/null
check "adding a participant keeps the CA" '[ "$(serial "$pki/identity_ca.cert.pem")" = "$ca_before" ]'
check "adding a participant leaves the robot's profile alone" \
  'cmp -s "$pki/robot.xml" "$work/robot_before.xml"'
check "adding a participant keeps the install directory" \
  'grep -q "file:///etc/mostar/pki/bob.cert.pem" "$pki/hosts/bob/bob.xml"'

# Renewal: a new key and certificate under the same subject; the old one is revoked.
cp "$pki/alice.cert.pem" "$work/alice_old.cert.pem"
old_subject=$(openssl x509 -in "$pki/alice.cert.pem" -noout -subject)
"$make_pki" "$pki" --renew alice >/dev/null
check "a renewed certificate is a new one" \
  '[ "$(serial "$pki/alice.cert.pem")" != "$(serial "$work/alice_old.cert.pem")" ]'
check "a renewed certificate keeps the subject" \
  '[ "$(openssl x509 -in "$pki/alice.cert.pem" -noout -subject)" = "$old_subject" ]'
check "a renewed certificate verifies" 'verifies "$pki/alice.cert.pem"'
check "the replaced certificate is revoked" '! verifies "$work/alice_old.cert.pem"'
check "the renewed permissions are signed by the permissions CA" \
  'openssl smime -verify -in "$pki/alice.permissions.p7s" -CAfile "$pki/permissions_ca.cert.pem" -out /dev/null 2>/dev/null'
check "the renewed bundle has the new certificate" \
  'cmp -s "$pki/alice.cert.pem" "$pki/hosts/alice/alice.cert.pem"'

# Revocation reaches every bundle.
"$revoke" "$pki" carol >/dev/null
check "a revoked certificate no longer verifies" '! verifies "$pki/carol.cert.pem"'
check "the roles file marks the revoked name, in the robot's bundle too" \
  'grep -qx "carol revoked" "$pki/roles" && grep -qx "carol revoked" "$bundle/roles" &&
   grep -qx "alice pilot" "$bundle/roles"'
check "the new CRL is in every bundle" \
  'cmp -s "$pki/identity_ca.crl.pem" "$pki/hosts/robot/identity_ca.crl.pem"'

# The monthly CRL refresh.
"$make_pki" "$pki" --refresh-crl --crl-days 7 >/dev/null
check "--refresh-crl issues a CRL of the given validity" '[ "$(crl_days "$pki/identity_ca.crl.pem")" = 7 ]'
check "--refresh-crl keeps the revocations" '! verifies "$pki/carol.cert.pem" && verifies "$pki/robot.cert.pem"'
check "--refresh-crl updates the bundles" \
  'cmp -s "$pki/identity_ca.crl.pem" "$pki/hosts/hub/identity_ca.crl.pem"'

# Ownership for a service with User=mostar: keys group-readable by the given group.
if [ "$(id -u)" = 0 ] && getent group nogroup >/dev/null; then
  "$make_pki" "$pki" --refresh-crl --owner root:nogroup >/dev/null
  check "--owner sets the bundle's owner and group" \
    '[ "$(stat -c %U:%G:%a "$bundle/robot.key.pem")" = "root:nogroup:640" ]'
else
  echo "skip: --owner needs root"
fi

check "bad lifetimes are refused" '! "$make_pki" "$work/bad" --days 0 >/dev/null 2>&1'
check "a relative install directory is refused" \
  '! "$make_pki" "$work/bad" --install-dir etc/pki >/dev/null 2>&1'
# (the output captured first: grep -q in a pipe may end it early, a SIGPIPE under pipefail)
check "--help prints the usage to stdout and succeeds" \
  'out=$("$make_pki" --help 2>/dev/null) && grep -q "^Usage:" <<<"$out" &&
   out=$("$revoke" --help 2>/dev/null) && grep -q "^Usage:" <<<"$out"'
check "an option in place of OUT_DIR is refused" \
  '! (cd "$work" && "$make_pki" --robot x >/dev/null 2>&1) && [ ! -e "$work/--robot" ]'

[ "$failures" -eq 0 ] || { echo "pki_test: $failures check(s) failed"; exit 1; }
echo "pki_test: all checks passed"
