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
  std::string identity_ca_path;           // file of dds.sec.auth.builtin.PKI-DH.identity_ca
  std::string identity_certificate_path;  // file of ...identity_certificate
};

// Reads the settings from a participant's properties. False with `error` when PKI-DH is on but
// its CA or certificate property is missing or not a "file:" URI.
bool SecuritySettingsFromProperties(const eprosima::fastrtps::rtps::PropertyPolicy& properties,
                                    SecuritySettings* settings, std::string* error);

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
