// DDS Security as mostar uses it (builtin plugins PKI-DH, Access-Permissions, AES-GCM-GMAC):
// the settings a participant's properties enable, and the listener that learns which client
// id each authenticated remote participant is (common/identity/peer_certificate.h).
#pragma once

#include <fastdds/rtps/attributes/PropertyPolicy.h>

#include <atomic>
#include <cstdint>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "common/identity/certificate.h"
#include "common/identity/peer_identity_table.h"
#include "common/time/time.h"

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

// Which remote-participant events PeerIdentityListener logs: a participant's event only when
// it differs from the last one logged for it (a peer refused at every announcement is logged
// once), and at most kBurst lines at once, then one per kRefill; the rest are counted. Pure
// (the caller passes the time); not thread-safe.
class PeerEventLogBudget {
 public:
  static constexpr int kBurst = 20;
  static constexpr Duration kRefill = std::chrono::milliseconds(500);
  static constexpr size_t kMaxRemembered = 1024;  // participants; forgotten all at once beyond
  enum class Event { kDiscovered, kAuthenticated, kRefused, kDropped, kLeft };
  // True when `event` of `prefix` at `now` should be logged; then `*suppressed` is the number
  // of events not logged for lack of budget since the last logged one.
  bool Allow(const identity::GuidPrefix& prefix, Event event, SteadyTime now, uint64_t* suppressed);

 private:
  std::map<identity::GuidPrefix, Event> last_;
  int tokens_ = kBurst;
  std::optional<SteadyTime> last_refill_;
  uint64_t suppressed_ = 0;
};

// Participant listener (given at creation, so no discovery is missed): binds each remote
// participant's GUID prefix to the client id of the verified certificate it announces, and marks
// it authenticated when DDS Security says so (PeerIdentityTable). Logs each remote participant
// discovered (with the id it announces), authenticated (by some certificate of the identity CA:
// the announced id stays a claim), failing authentication, dropped (silent for its lease) or
// gone (PeerEventLogBudget). Callbacks are quick and never block. Thread-safe.
class PeerIdentityListener : public eprosima::fastdds::dds::DomainParticipantListener {
 public:
  explicit PeerIdentityListener(std::unique_ptr<identity::IdentityCa> ca);

  // The client id an authenticated remote participant announces with a verified certificate:
  // a claim for logs, never for authorization (peer_identity_table.h).
  std::optional<std::string> AnnouncedClientId(const identity::GuidPrefix& prefix) const {
    return table_.AnnouncedClientId(prefix);
  }
  identity::PeerIdentityStats table_stats() const { return table_.stats(); }
  PeerIdentityCounters counters() const;

  void on_participant_discovery(eprosima::fastdds::dds::DomainParticipant* participant,
                                eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override;
  void onParticipantAuthentication(
      eprosima::fastdds::dds::DomainParticipant* participant,
      eprosima::fastrtps::rtps::ParticipantAuthenticationInfo&& info) override;

 private:
  // "announcing 'alice'" or "announcing no client certificate", for the logs.
  std::string Announcing(const identity::GuidPrefix& prefix) const;
  // Logs `text` for `event` of `prefix` when the budget allows.
  void Log(const identity::GuidPrefix& prefix, PeerEventLogBudget::Event event,
           const std::string& text);

  const std::unique_ptr<identity::IdentityCa> ca_;
  std::mutex log_mutex_;
  PeerEventLogBudget log_budget_;  // guarded by log_mutex_
  identity::PeerIdentityTable table_;
  std::atomic<uint64_t> verified_{0};
  std::atomic<uint64_t> refused_{0};
  std::atomic<uint64_t> without_certificate_{0};
  std::atomic<uint64_t> authenticated_{0};
};

}  // namespace mostar::dds
