// DDS Security as mostar uses it (builtin plugins PKI-DH, Access-Permissions, AES-GCM-GMAC):
// the settings a participant's properties enable, and the listener that learns which client
// id each authenticated remote participant is (common/identity/peer_certificate.h).
#pragma once

#include <fastdds/rtps/attributes/PropertyPolicy.h>

#include <atomic>
#include <cstdint>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <memory>
#include <string>

#include "common/identity/certificate.h"
#include "common/identity/peer_identity_table.h"

namespace mostar::dds {

struct SecuritySettings {
  bool authentication = false;            // dds.sec.auth.plugin is builtin.PKI-DH
  bool access_control = false;            // dds.sec.access.plugin is builtin.Access-Permissions
  bool cryptography = false;              // dds.sec.crypto.plugin is builtin.AES-GCM-GMAC
  std::string identity_ca_path;           // file of dds.sec.auth.builtin.PKI-DH.identity_ca
  std::string identity_certificate_path;  // file of ...identity_certificate

  // All three plugins: authentication, permissions and encryption.
  bool complete() const { return authentication && access_control && cryptography; }
};

// Reads the settings from a participant's properties. False with `error` when PKI-DH is on but
// its CA or certificate property is missing or not a "file:" URI.
bool SecuritySettingsFromProperties(const eprosima::fastrtps::rtps::PropertyPolicy& properties,
                                    SecuritySettings* settings, std::string* error);

// Secure by default: whether a program may start a participant with these settings.
enum class SecurityVerdict : uint8_t {
  kSecure = 0,       // DDS Security complete (PKI-DH, permissions, AES-GCM-GMAC)
  kLoopback,         // the loopback profile: nothing leaves this machine
  kInsecureAllowed,  // a network profile without (complete) DDS Security, allowed by --insecure
  kRefused,          // the same without --insecure: the program must not start
};

struct SecurityPolicy {
  SecurityVerdict verdict = SecurityVerdict::kRefused;
  // Why, for kRefused (the error) and kInsecureAllowed (the start-up warning); empty otherwise.
  std::string message;

  bool allowed() const { return verdict != SecurityVerdict::kRefused; }
  // DDS traffic leaves this machine without DDS Security (shown in health and HUD).
  bool security_off() const { return verdict == SecurityVerdict::kInsecureAllowed; }
};

// The decision. `profile_is_loopback`: the built-in "loopback" profile (an XML file counts as
// a network profile whatever it holds); `settings`: from the profile's participant properties;
// `insecure`: the operator asked for --insecure (or `dds { insecure: true }`). Pure.
SecurityPolicy CheckSecurityPolicy(bool profile_is_loopback, const SecuritySettings& settings,
                                   bool insecure);

struct PeerIdentityCounters {
  uint64_t certificates_verified = 0;  // announced certificates that proved a client id
  uint64_t certificates_refused = 0;   // announced but not proving one (CA, GUID, CN)
  uint64_t without_certificate = 0;    // participants that announced none
  uint64_t authenticated = 0;          // AUTHORIZED events
};

// Participant listener (given at creation, so no discovery is missed): binds each remote
// participant's GUID prefix to the client id its announced certificate proves, and marks it
// authenticated when DDS Security says so (PeerIdentityTable). Callbacks are quick and never
// block. Thread-safe.
class PeerIdentityListener : public eprosima::fastdds::dds::DomainParticipantListener {
 public:
  explicit PeerIdentityListener(std::unique_ptr<identity::IdentityCa> ca);

  // The client id of an authenticated remote participant with a verified certificate.
  std::optional<std::string> ClientIdOf(const identity::GuidPrefix& prefix) const {
    return table_.ClientIdOf(prefix);
  }
  identity::PeerIdentityStats table_stats() const { return table_.stats(); }
  PeerIdentityCounters counters() const;

  void on_participant_discovery(eprosima::fastdds::dds::DomainParticipant* participant,
                                eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override;
  void onParticipantAuthentication(
      eprosima::fastdds::dds::DomainParticipant* participant,
      eprosima::fastrtps::rtps::ParticipantAuthenticationInfo&& info) override;

 private:
  const std::unique_ptr<identity::IdentityCa> ca_;
  identity::PeerIdentityTable table_;
  std::atomic<uint64_t> verified_{0};
  std::atomic<uint64_t> refused_{0};
  std::atomic<uint64_t> without_certificate_{0};
  std::atomic<uint64_t> authenticated_{0};
};

}  // namespace mostar::dds
