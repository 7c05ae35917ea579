#include "common/dds/profile_check.h"

#include <openssl/pem.h>
#include <openssl/x509.h>
#include <pwd.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <vector>

#include "common/dds/interface_wait.h"
#include "common/identity/certificate.h"
#include "common/identity/certificate_subject.h"

namespace mostar::dds {
namespace {

namespace fdds = eprosima::fastdds::dds;
using eprosima::fastrtps::types::ReturnCode_t;

constexpr char kBundleFix[] =
    "copy this host's bundle (make_pki.sh OUT_DIR/hosts/NAME/) into the folder the profile "
    "names, keys root:mostar 0640 (docs/security.md)";

// The path of a "file://PATH" or "file:PATH" URI, "" for other URIs.
std::string FileOf(const std::string& uri) {
  if (uri.rfind("file://", 0) == 0) return uri.substr(7);
  return uri.rfind("file:", 0) == 0 ? uri.substr(5) : "";
}

// The security properties that name files, with what each is for.
struct SecurityFile {
  const char* property;
  const char* what;
  bool private_key;
};
constexpr SecurityFile kSecurityFiles[] = {
    {"dds.sec.auth.builtin.PKI-DH.identity_ca", "identity CA certificate", false},
    {"dds.sec.auth.builtin.PKI-DH.identity_certificate", "own certificate", false},
    {"dds.sec.auth.builtin.PKI-DH.identity_crl", "certificate revocation list", false},
    {"dds.sec.auth.builtin.PKI-DH.private_key", "private key", true},
    {"dds.sec.access.builtin.Access-Permissions.permissions_ca", "permissions CA certificate",
     false},
    {"dds.sec.access.builtin.Access-Permissions.governance", "governance", false},
    {"dds.sec.access.builtin.Access-Permissions.permissions", "permissions", false},
};

const std::string* Property(const fdds::DomainParticipantQos& qos, const std::string& name) {
  for (const auto& p : qos.properties().properties()) {
    if (p.name() == name) return &p.value();
  }
  return nullptr;
}

// A private key the service user cannot read (checked as root, where access() always passes).
bool ServiceUserCannotRead(const std::string& path, const std::string& service_user) {
  if (geteuid() != 0 || service_user.empty()) return false;
  const passwd* pw = getpwnam(service_user.c_str());
  struct stat st {};
  if (pw == nullptr || stat(path.c_str(), &st) != 0) return false;
  if (st.st_uid == pw->pw_uid) return (st.st_mode & S_IRUSR) == 0;
  if (st.st_gid == pw->pw_gid) return (st.st_mode & S_IRGRP) == 0;
  return (st.st_mode & S_IROTH) == 0;
}

// The CRL's nextUpdate lies in the past (or it cannot be read: `error`).
bool CrlExpired(const std::string& path, std::string* error) {
  FILE* f = std::fopen(path.c_str(), "r");
  if (f == nullptr) {
    *error = "cannot open it";
    return false;
  }
  X509_CRL* crl = PEM_read_X509_CRL(f, nullptr, nullptr, nullptr);
  std::fclose(f);
  if (crl == nullptr) {
    *error = "not a PEM certificate revocation list";
    return false;
  }
  const ASN1_TIME* next = X509_CRL_get0_nextUpdate(crl);
  const bool expired = next != nullptr && X509_cmp_current_time(next) < 0;
  X509_CRL_free(crl);
  return expired;
}

void CheckSecurityFiles(const fdds::DomainParticipantQos& qos, const std::string& service_user,
                        ConfigReport* report, ProfileCheck* result) {
  bool all_readable = true;
  for (const SecurityFile& f : kSecurityFiles) {
    const std::string* value = Property(qos, f.property);
    if (value == nullptr) continue;
    const std::string path = FileOf(*value);
    if (path.empty()) continue;  // SecuritySettingsFromProperties names the non-file ones
    if (access(path.c_str(), R_OK) != 0) {
      report->Fail(std::string("the ") + f.what + " " + path + " cannot be read", kBundleFix);
      all_readable = false;
    } else if (f.private_key && ServiceUserCannotRead(path, service_user)) {
      report->Fail(
          "the private key " + path + " cannot be read by the service user " + service_user,
          "chown root:" + service_user + " " + path + " && chmod 0640 " + path);
      all_readable = false;
    }
  }
  if (all_readable) report->Ok("DDS Security files readable");
  const std::string* ca = Property(qos, kSecurityFiles[0].property);
  const std::string* cert = Property(qos, kSecurityFiles[1].property);
  if (cert != nullptr) result->certificate_path = FileOf(*cert);
  if (ca != nullptr && cert != nullptr && access(FileOf(*ca).c_str(), R_OK) == 0 &&
      access(FileOf(*cert).c_str(), R_OK) == 0) {
    std::string error;
    std::vector<uint8_t> der;
    auto identity_ca = identity::IdentityCa::LoadFile(FileOf(*ca), &error);
    std::optional<identity::SubjectInfo> subject;
    if (identity_ca && identity::ReadPemCertificate(FileOf(*cert), &der, &error)) {
      subject = identity_ca->Verify(der, &error);
    }
    if (!subject) {
      report->Fail("the own certificate " + FileOf(*cert) + " is not valid: " + error,
                   "renew it on the administrator's computer (make_pki.sh OUT_DIR --renew NAME) "
                   "and copy the new bundle here");
    } else {
      std::string why;
      auto parsed = identity::CertificateSubject::Parse(subject->rfc2253, &why);
      std::optional<std::string> id;
      if (parsed) id = parsed->ClientId(&why);
      if (id) {
        result->own_client_id = *id;
        report->Ok("own certificate valid, issued by the identity CA, client id '" + *id + "'");
      } else {
        report->Fail("the own certificate " + FileOf(*cert) + " names no client id (" + why + ")",
                     "make the certificate with make_pki.sh (its CN is the client id)");
      }
    }
  }
  const std::string* crl = Property(qos, kSecurityFiles[2].property);
  if (crl != nullptr && access(FileOf(*crl).c_str(), R_OK) == 0) {
    std::string error;
    if (CrlExpired(FileOf(*crl), &error)) {
      report->Fail("the certificate revocation list " + FileOf(*crl) +
                       " has expired: DDS Security refuses every certificate",
                   "make_pki.sh OUT_DIR --refresh-crl on the administrator's computer, then copy "
                   "identity_ca.crl.pem to every host (monthly, docs/security.md)");
    } else if (!error.empty()) {
      report->Fail("the certificate revocation list " + FileOf(*crl) + ": " + error, kBundleFix);
    } else {
      report->Ok("certificate revocation list current");
    }
  }
}

}  // namespace

ProfileCheck CheckDdsProfile(const ParticipantOptions& options, const std::string& service_user,
                             ConfigReport* report) {
  ProfileCheck result;
  std::string error;
  if (!options.IsValid(&error)) {
    report->Fail(error, "give --dds-profile loopback or the path of an .xml profiles file");
    return result;
  }
  if (options.profile == "loopback") {
    report->Ok("DDS profile loopback: nothing leaves this computer");
    return result;
  }
  if (access(options.profile.c_str(), R_OK) != 0) {
    report->Fail("the DDS profile " + options.profile + " cannot be read",
                 "make it with make_overlay.sh and make_pki.sh (docs/networking.md, From zero) "
                 "and copy this host's bundle; or give another with --dds-profile");
    return result;
  }
  auto* factory = fdds::DomainParticipantFactory::get_instance();
  if (factory->load_XML_profiles_file(options.profile) != ReturnCode_t::RETCODE_OK) {
    report->Fail("the DDS profile " + options.profile +
                     " is not a valid Fast DDS XML profiles "
                     "file (Fast DDS printed why above)",
                 "compare it with the shipped profiles in /usr/share/mostar/dds (deploy/dds)");
    return result;
  }
  const std::string name =
      options.xml_participant_profile.empty() ? options.name : options.xml_participant_profile;
  fdds::DomainParticipantQos qos;
  if (factory->get_participant_qos_from_profile(name, qos) != ReturnCode_t::RETCODE_OK) {
    report->Fail(options.profile + " has no participant profile named '" + name + "'",
                 "use the profile made for this program: its <participant profile_name=\"" + name +
                     "\"> (make_overlay.sh and make_pki.sh write them)");
    return result;
  }
  report->Ok("DDS profile " + options.profile + " loads (participant profile '" + name + "')");
  SecuritySettings settings;
  if (!SecuritySettingsFromProperties(qos.properties(), &settings, &error)) {
    report->Fail(options.profile + ": " + error, "make the profile secure with make_pki.sh");
    return result;
  }
  const SecurityPolicy policy = CheckSecurityPolicy(false, settings, options.insecure);
  if (!policy.allowed()) {
    report->Fail(options.profile + ": " + policy.message,
                 "use the profile make_pki.sh made for this host (NAME.xml), or --insecure on a "
                 "network you trust (anyone on it can then read and command the robot)");
  } else if (policy.security_off()) {
    report->Ok("DDS Security off, as asked (--insecure): " + policy.message);
  } else {
    result.secure = true;
    report->Ok("DDS Security complete (PKI-DH, permissions, AES-GCM-GMAC)");
  }
  if (settings.authentication) CheckSecurityFiles(qos, service_user, report, &result);
  const std::vector<std::string> missing =
      MissingAddresses(WhitelistedAddresses(qos), LocalIpv4Addresses());
  if (missing.empty()) {
    report->Ok("the profile's interface addresses exist on this host");
  } else {
    std::string list;
    for (const std::string& m : missing) list += (list.empty() ? "" : ", ") + m;
    report->Fail("address " + list + " of the profile's interfaceWhiteList is not on this host",
                 "bring its network up (the overlay: systemctl start wg-quick@mostar, or "
                 "wg-quick up mostar); a service started before it waits 45 s for it, then "
                 "systemd starts it again");
  }
  return result;
}

}  // namespace mostar::dds
