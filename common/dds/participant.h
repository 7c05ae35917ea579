// RAII DDS participant for mostar (Fast DDS 2.9), with one publisher and one subscriber.
//
// Profiles (ParticipantOptions::profile):
//   "loopback" (default): all traffic stays on this machine: UDPv4 restricted to 127.0.0.1 by an
//       interface whitelist, unicast discovery to 127.0.0.1, and shared memory with a segment
//       sized for stereo frames. Used by the demo and the tests.
//   a path ending in ".xml": a Fast DDS XML profiles file; the participant profile named
//       `xml_participant_profile` (default: the role, "robot" or "operator") is used.
// The domain id comes from the options; see domain.h for the flag/environment convention.
// With DDS Security (the profile's properties enable builtin.PKI-DH) the participant announces
// its identity certificate in its USER_DATA and notes, for each authenticated remote
// participant, the client id (certificate CN) it announces (security.h): AnnouncedClientId, a
// claim for logs.
// Secure by default: a profile other than "loopback" whose properties do not enable DDS Security
// (PKI-DH, Access-Permissions, AES-GCM-GMAC) is refused unless `insecure` is set; then the
// participant logs a warning and says so in security_off() (CheckSecurityPolicy).
// Teardown order is handled here: contained entities first, then the participant. A participant
// with a TCP transport is not deleted (see EndProcess): programs end through EndProcess.
#pragma once

#include <chrono>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "common/dds/interface_wait.h"
#include "common/dds/security.h"
#include "common/dds/tcp_user_timeout.h"
#include "common/identity/guid_binding.h"

namespace mostar::dds {

struct ParticipantOptions {
  int domain_id = 0;                    // 0..232
  std::string profile = "loopback";     // "loopback" or a path to a Fast DDS XML profiles file
  std::string xml_participant_profile;  // profile name inside the XML file (default: name)
  std::string name = "mostar";          // participant name, e.g. "robot" or "operator"
  // --insecure: allow a network profile without DDS Security (a warning, and security_off()).
  bool insecure = false;
  // Shared-memory segment size for the loopback profile; must hold a few JPEG frames.
  uint32_t shm_segment_bytes = 8u << 20;
  // With a TCP transport: TCP_USER_TIMEOUT for the process's TCP sockets, so that a peer that
  // stopped reading or vanished blocks sends for at most this long (tcp_user_timeout.h);
  // 0 leaves the kernel default (about 15 minutes).
  int tcp_user_timeout_ms = kDefaultTcpUserTimeoutMs;
  static constexpr int kDefaultTcpUserTimeoutMs = 4000;
  // A profile whose transports are restricted to local addresses (interfaceWhiteList) that do
  // not exist yet: wait up to this long for them (logged), then fail naming them. 0: fail at
  // once. Service programs wait (a WireGuard address that comes up after the program starts);
  // a participant made without them would never be discovered on them (interface_wait.h).
  std::chrono::milliseconds wait_for_interfaces{0};

  bool IsValid(std::string* error) const;
};

class Participant {
 public:
  // Creates the participant; returns null and sets `error` on failure.
  static std::unique_ptr<Participant> Create(const ParticipantOptions& options, std::string* error);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  // Registers `type` (once per type name) and returns the topic `name` (created once).
  // Returns null and sets `error` on failure. Thread-safe.
  eprosima::fastdds::dds::Topic* GetTopic(const std::string& name,
                                          eprosima::fastdds::dds::TypeSupport type,
                                          std::string* error);

  eprosima::fastdds::dds::DomainParticipant* get() const { return participant_; }
  eprosima::fastdds::dds::Publisher* publisher() const { return publisher_; }
  eprosima::fastdds::dds::Subscriber* subscriber() const { return subscriber_; }
  const ParticipantOptions& options() const { return options_; }
  // True when the participant's transports include TCPv4/TCPv6 (the WAN profiles).
  bool uses_tcp() const { return uses_tcp_; }
  // TCP sockets given TCP_USER_TIMEOUT so far (0 without a TCP transport).
  int tcp_sockets_guarded() const { return tcp_guard_ ? tcp_guard_->sockets_set() : 0; }

  // DDS Security authentication (PKI-DH) is on: DDS access control applies the signed
  // permissions of the certificate each remote participant's handshake proved.
  bool secure() const { return identities_ != nullptr; }
  // The client id (certificate CN) the authenticated remote participant with GUID prefix
  // `prefix` announces with a verified certificate; nullopt when not secure(), or when that
  // participant is not authenticated or announced no such certificate. A claim for logs: an
  // insider can announce another client's certificate (peer_identity_table.h); who wrote a
  // sample is the partition its reader is in (sender_partition.h). Thread-safe.
  std::optional<std::string> AnnouncedClientId(const identity::GuidPrefix& prefix) const;
  // The CN of this participant's own certificate when secure() and it is a valid client id;
  // empty otherwise.
  const std::string& own_client_id() const { return own_client_id_; }
  // Started with --insecure on a network profile without (complete) DDS Security.
  bool security_off() const { return security_off_; }
  // The addresses of the profile's interfaceWhiteList missing from this host now (the overlay
  // went down under the running program); logs each change (gone, back). Empty without a
  // whitelist. Thread-safe; one getifaddrs() per call.
  std::vector<std::string> MissingProfileAddresses() const;
  // For a profile that announces the host's addresses (no interfaceWhiteList: lan.xml): true
  // once none of the addresses announced when the participant was made has been on this host
  // for 1 s while another one is (a lease renewed to a new address, a network that came up
  // after the program). Peers then keep sending to the old address (interface_wait.h): the
  // program ends in order and restarts in place (common/process/restart_in_place.h). Logs the
  // first time, with both address lists. Thread-safe; one getifaddrs() per call.
  bool NeedsNewParticipant() const;
  PeerIdentityCounters identity_counters() const;

 private:
  explicit Participant(ParticipantOptions options) : options_(std::move(options)) {}
  // Reads the security settings of `qos`; when PKI-DH is on, puts this participant's
  // certificate into its USER_DATA and makes the identity listener.
  bool SetUpSecurity(const SecuritySettings& settings,
                     eprosima::fastdds::dds::DomainParticipantQos* qos, std::string* error);
  static constexpr size_t kMaxUserDataBytes = 4096;

  ParticipantOptions options_;
  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  bool uses_tcp_ = false;
  std::unique_ptr<TcpUserTimeoutGuard> tcp_guard_;    // TCP participants only
  std::unique_ptr<PeerIdentityListener> identities_;  // secure participants only
  std::string own_client_id_;
  bool security_off_ = false;
  mutable std::mutex address_mutex_;
  mutable std::unique_ptr<AddressWatch> address_watch_;      // guarded by address_mutex_
  mutable std::unique_ptr<ReaddressWatch> readdress_watch_;  // guarded by address_mutex_
  mutable bool readdress_logged_ = false;                    // guarded by address_mutex_
  std::mutex mutex_;
  std::map<std::string, eprosima::fastdds::dds::Topic*> topics_;
};

// How a program that may have created participants ends: `int main() { return
// dds::EndProcess(Run()); }`, after every local object has been destroyed.
//
// Fast DDS 2.9's TCP transport can leave a connection's receive thread running after its
// participant is deleted; the thread then uses the freed transport when the peer next sends or
// closes, and the process dies with SIGSEGV (seen at robot_server exit with an operator still
// connected). So TCP participants are never deleted: their readers and writers are, and the
// process ends here with std::_Exit(code) after flushing stdio, without static destructors
// (Fast DDS' factory would delete the participant there). The kernel closes the sockets; peers
// see the connection drop. Without TCP participants this just returns `code`.
int EndProcess(int code);

}  // namespace mostar::dds
