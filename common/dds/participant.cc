#include "common/dds/participant.h"

#include <arpa/inet.h>
#include <fastdds/rtps/transport/TCPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <thread>
#include <vector>

#include "common/dds/interface_wait.h"
#include "common/identity/certificate.h"
#include "common/identity/certificate_subject.h"
#include "common/identity/peer_certificate.h"
#include "common/log/log.h"

namespace mostar::dds {

namespace fdds = eprosima::fastdds::dds;
namespace frtps = eprosima::fastrtps;

namespace {

// TCP participants created in this process and left undeleted (see EndProcess).
std::atomic<int> g_abandoned_tcp_participants{0};

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Fast DDS only logs an error when a TCP listening port is taken (another robot_server, a
// relay) and then runs unreachable; refuse to start instead. Binds each TCPv4 listening port on
// every address the way Fast DDS' acceptor does (SO_REUSEADDR, so only a listener conflicts).
bool TcpListeningPortsFree(const fdds::DomainParticipantQos& qos, std::string* error) {
  for (const auto& transport : qos.transport().user_transports) {
    auto tcp =
        std::dynamic_pointer_cast<eprosima::fastdds::rtps::TCPv4TransportDescriptor>(transport);
    if (!tcp) continue;
    for (uint16_t port : tcp->listening_ports) {
      if (port == 0) continue;
      const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
      if (fd < 0) continue;
      const int one = 1;
      ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
      sockaddr_in address{};
      address.sin_family = AF_INET;
      address.sin_port = htons(port);
      address.sin_addr.s_addr = htonl(INADDR_ANY);
      const bool bound = ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0 &&
                         ::listen(fd, 1) == 0;
      const int bind_errno = errno;
      ::close(fd);
      if (!bound) {
        *error = "TCP port " + std::to_string(port) + " cannot be listened on (" +
                 std::strerror(bind_errno) + "): another robot_server or relay may be using it";
        return false;
      }
    }
  }
  return true;
}

// Loopback-only participant QoS: see the header.
fdds::DomainParticipantQos LoopbackQos(const ParticipantOptions& options) {
  fdds::DomainParticipantQos qos = fdds::PARTICIPANT_QOS_DEFAULT;
  qos.name(options.name);
  qos.transport().use_builtin_transports = false;

  auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
  udp->interfaceWhiteList.push_back("127.0.0.1");
  udp->maxInitialPeersRange = 32;  // up to 32 participants per domain on this host
  udp->sendBufferSize = 4u << 20;
  udp->receiveBufferSize = 4u << 20;
  qos.transport().user_transports.push_back(udp);

  auto shm = std::make_shared<eprosima::fastdds::rtps::SharedMemTransportDescriptor>();
  shm->segment_size(options.shm_segment_bytes);
  qos.transport().user_transports.push_back(shm);

  // Unicast discovery to this host; no port given, so Fast DDS derives the well-known
  // discovery ports of participant ids 0..maxInitialPeersRange-1 in this domain.
  frtps::rtps::Locator_t peer;
  peer.kind = LOCATOR_KIND_UDPv4;
  frtps::rtps::IPLocator::setIPv4(peer, "127.0.0.1");
  qos.wire_protocol().builtin.initialPeersList.push_back(peer);
  qos.wire_protocol().builtin.discovery_config.leaseDuration_announcementperiod =
      frtps::Duration_t(1, 0);
  qos.wire_protocol().builtin.discovery_config.leaseDuration = frtps::Duration_t(10, 0);
  return qos;
}

}  // namespace

bool ParticipantOptions::IsValid(std::string* error) const {
  if (domain_id < 0 || domain_id > 232) {
    *error = "DDS domain id " + std::to_string(domain_id) + " is outside [0, 232]";
    return false;
  }
  if (profile != "loopback" && !EndsWith(profile, ".xml")) {
    *error = "DDS profile '" + profile + "' is neither 'loopback' nor an .xml file";
    return false;
  }
  if (tcp_user_timeout_ms < 0 || tcp_user_timeout_ms > 600000) {
    *error = "TCP user timeout must be in [0, 600000] ms";
    return false;
  }
  if (shm_segment_bytes < (1u << 20)) {
    *error = "shared-memory segment must be at least 1 MiB";
    return false;
  }
  return true;
}

namespace {

// Waits (polling every 200 ms, up to options.wait_for_interfaces) until every address of the
// profile's interface whitelists exists on this host; false with `error` naming the missing ones.
bool WaitForWhitelistedAddresses(const fdds::DomainParticipantQos& qos,
                                 const ParticipantOptions& options, std::string* error) {
  const std::vector<std::string> wanted = WhitelistedAddresses(qos);
  if (wanted.empty()) return true;
  const auto deadline = std::chrono::steady_clock::now() + options.wait_for_interfaces;
  bool said = false;
  for (;;) {
    const std::vector<std::string> missing = MissingAddresses(wanted, LocalIpv4Addresses());
    if (missing.empty()) {
      if (said) MOSTAR_LOG(INFO) << options.profile << ": the interface addresses are up";
      return true;
    }
    std::string list;
    for (const std::string& m : missing) list += (list.empty() ? "" : ", ") + m;
    if (std::chrono::steady_clock::now() >= deadline) {
      *error = options.profile + ": address " + list +
               " of the profile's interfaceWhiteList does not exist on this host (is its network "
               "up, e.g. the WireGuard overlay? docs/networking.md)";
      return false;
    }
    if (!said) {
      MOSTAR_LOG(WARNING)
          << options.profile << ": waiting up to " << options.wait_for_interfaces.count() / 1000.0
          << " s for address " << list
          << " (the profile's interfaceWhiteList) to exist on this host on a running "
             "interface";
      said = true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
}

}  // namespace

std::unique_ptr<Participant> Participant::Create(const ParticipantOptions& options,
                                                 std::string* error) {
  if (!options.IsValid(error)) return nullptr;
  auto* factory = fdds::DomainParticipantFactory::get_instance();
  fdds::DomainParticipantQos qos;
  if (options.profile == "loopback") {
    qos = LoopbackQos(options);
  } else {
    if (factory->load_XML_profiles_file(options.profile) != ReturnCode_t::RETCODE_OK) {
      *error = options.profile + ": cannot load the DDS XML profiles file";
      return nullptr;
    }
    const std::string name =
        options.xml_participant_profile.empty() ? options.name : options.xml_participant_profile;
    if (factory->get_participant_qos_from_profile(name, qos) != ReturnCode_t::RETCODE_OK) {
      *error = options.profile + ": no participant profile named '" + name + "'";
      return nullptr;
    }
  }
  SecuritySettings settings;
  if (!SecuritySettingsFromProperties(qos.properties(), &settings, error)) return nullptr;
  const SecurityPolicy policy =
      CheckSecurityPolicy(options.profile == "loopback", settings, options.insecure);
  if (!policy.allowed()) {
    *error = options.profile + ": " + policy.message;
    return nullptr;
  }
  if (!TcpListeningPortsFree(qos, error)) return nullptr;
  if (!WaitForWhitelistedAddresses(qos, options, error)) return nullptr;
  std::unique_ptr<Participant> p(new Participant(options));
  if (policy.security_off()) {
    MOSTAR_LOG(WARNING) << "participant '" << options.name << "' (" << options.profile
                        << "): " << policy.message;
    p->security_off_ = true;
  }
  if (!p->SetUpSecurity(settings, &qos, error)) return nullptr;
  p->address_watch_ = std::make_unique<AddressWatch>(WhitelistedAddresses(qos));
  if (AnnouncesHostAddresses(qos)) {
    p->readdress_watch_ =
        std::make_unique<ReaddressWatch>(LocalIpv4Addresses(), std::chrono::seconds(1));
  }
  for (const auto& transport : qos.transport().user_transports) {
    if (std::dynamic_pointer_cast<eprosima::fastdds::rtps::TCPTransportDescriptor>(transport)) {
      p->uses_tcp_ = true;
    }
  }
  p->participant_ = factory->create_participant(options.domain_id, qos, p->identities_.get(),
                                                fdds::StatusMask::none());
  if (p->participant_ == nullptr) {
    *error = "cannot create the DDS participant (domain " + std::to_string(options.domain_id) +
             ", profile " + options.profile + ")";
    return nullptr;
  }
  if (p->uses_tcp_ && options.tcp_user_timeout_ms > 0) {
    p->tcp_guard_ = std::make_unique<TcpUserTimeoutGuard>(options.tcp_user_timeout_ms,
                                                          std::chrono::milliseconds(200));
  }
  p->publisher_ = p->participant_->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
  p->subscriber_ = p->participant_->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  if (p->publisher_ == nullptr || p->subscriber_ == nullptr) {
    *error = "cannot create the DDS publisher/subscriber";
    return nullptr;
  }
  MOSTAR_LOG(DEBUG) << "DDS participant '" << options.name << "' on domain " << options.domain_id
                    << " with profile " << options.profile;
  return p;
}

bool Participant::SetUpSecurity(const SecuritySettings& settings, fdds::DomainParticipantQos* qos,
                                std::string* error) {
  // Remote participants announcing more than this USER_DATA are ignored (a certificate is
  // about 500 bytes).
  if (qos->allocation().data_limits.max_user_data == 0) {
    qos->allocation().data_limits.max_user_data = kMaxUserDataBytes;
  }
  if (!settings.authentication) return true;
  std::vector<uint8_t> der;
  if (!identity::ReadPemCertificate(settings.identity_certificate_path, &der, error)) return false;
  std::unique_ptr<identity::IdentityCa> ca =
      identity::IdentityCa::LoadFile(settings.identity_ca_path, error);
  if (!ca) return false;
  std::string why;
  std::optional<identity::SubjectInfo> own = identity::SubjectOfCertificate(der, &why);
  std::optional<identity::CertificateSubject> subject;
  if (own) subject = identity::CertificateSubject::Parse(own->rfc2253, &why);
  std::optional<std::string> client_id;
  if (subject) client_id = subject->ClientId(&why);
  if (client_id) {
    own_client_id_ = *client_id;
  } else {
    MOSTAR_LOG(WARNING) << settings.identity_certificate_path
                        << ": this certificate names no client id (" << why << ")";
  }
  qos->user_data().data_vec(identity::AnnouncedCertificateUserData(der));
  identities_ = std::make_unique<PeerIdentityListener>(std::move(ca));
  return true;
}

std::vector<std::string> Participant::MissingProfileAddresses() const {
  std::lock_guard<std::mutex> lock(address_mutex_);
  if (!address_watch_) return {};
  bool changed = false;
  std::vector<std::string> missing = address_watch_->Check(&changed);
  if (changed) {
    if (missing.empty()) {
      MOSTAR_LOG(INFO) << options_.profile << ": the profile's addresses are back on this host";
    } else {
      std::string list;
      for (const std::string& m : missing) list += (list.empty() ? "" : ", ") + m;
      MOSTAR_LOG(WARNING) << options_.profile << ": address " << list
                          << " of the profile's interfaceWhiteList is gone from this host (the "
                             "overlay down?): no peer reaches this participant until it is back";
    }
  }
  return missing;
}

bool Participant::NeedsNewParticipant() const {
  std::lock_guard<std::mutex> lock(address_mutex_);
  if (!readdress_watch_) return false;
  const std::vector<std::string> local = LocalIpv4Addresses();
  const bool stale = readdress_watch_->Check(local, std::chrono::steady_clock::now());
  if (stale && !readdress_logged_) {
    readdress_logged_ = true;
    const auto join = [](const std::vector<std::string>& list) {
      std::string out;
      for (const std::string& a : list) out += (out.empty() ? "" : ", ") + a;
      return out.empty() ? std::string("none") : out;
    };
    MOSTAR_LOG(WARNING) << options_.profile << ": this host's addresses changed (announced "
                        << join(readdress_watch_->announced()) << "; now " << join(local)
                        << "): peers keep sending to the announced ones, so participant '"
                        << options_.name << "' must be made again";
  }
  return stale;
}

std::optional<std::string> Participant::AnnouncedClientId(
    const identity::GuidPrefix& prefix) const {
  if (!identities_) return std::nullopt;
  return identities_->AnnouncedClientId(prefix);
}

PeerIdentityCounters Participant::identity_counters() const {
  return identities_ ? identities_->counters() : PeerIdentityCounters();
}

Participant::~Participant() {
  if (participant_ == nullptr) return;
  if (identities_ &&
      participant_->set_listener(nullptr, fdds::StatusMask::none(), std::chrono::seconds(2)) !=
          ReturnCode_t::RETCODE_OK) {
    (void)identities_.release();  // a callback may still use it: never freed
  }
  participant_->delete_contained_entities();
  if (uses_tcp_) {
    ++g_abandoned_tcp_participants;  // see EndProcess
    return;
  }
  fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
}

int EndProcess(int code) {
  if (g_abandoned_tcp_participants.load() == 0) return code;
  std::fflush(nullptr);
  std::_Exit(code);
}

fdds::Topic* Participant::GetTopic(const std::string& name, fdds::TypeSupport type,
                                   std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = topics_.find(name);
  if (it != topics_.end()) return it->second;
  if (participant_->find_type(type.get_type_name()).empty() &&
      type.register_type(participant_) != ReturnCode_t::RETCODE_OK) {
    *error = "cannot register DDS type " + type.get_type_name();
    return nullptr;
  }
  fdds::Topic* topic =
      participant_->create_topic(name, type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
  if (topic == nullptr) {
    *error = "cannot create DDS topic " + name;
    return nullptr;
  }
  topics_[name] = topic;
  return topic;
}

}  // namespace mostar::dds
