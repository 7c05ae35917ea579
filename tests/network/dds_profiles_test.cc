// Loads every shipped DDS XML profile file (deploy/dds/) the way common/dds/participant.cc does
// and checks that each participant profile the programs select by role exists and carries the
// transport and discovery settings docs/networking.md promises.
#include <fastdds/rtps/transport/TCPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <memory>
#include <string>
#include <vector>

#include "common/dds/participant.h"

namespace mostar::network {
namespace {

namespace fdds = eprosima::fastdds::dds;
namespace frtps = eprosima::fastrtps;
using eprosima::fastdds::rtps::SharedMemTransportDescriptor;
using eprosima::fastdds::rtps::TCPv4TransportDescriptor;
using eprosima::fastdds::rtps::UDPv4TransportDescriptor;

std::string Profile(const std::string& file) {
  return std::string(MOSTAR_TEST_SOURCE_DIR) + "/deploy/dds/" + file;
}

fdds::DomainParticipantQos Load(const std::string& file, const std::string& profile) {
  auto* factory = fdds::DomainParticipantFactory::get_instance();
  EXPECT_EQ(factory->load_XML_profiles_file(Profile(file)), ReturnCode_t::RETCODE_OK) << file;
  fdds::DomainParticipantQos qos;
  EXPECT_EQ(factory->get_participant_qos_from_profile(profile, qos), ReturnCode_t::RETCODE_OK)
      << file << ": " << profile;
  return qos;
}

template <class Descriptor>
std::vector<std::shared_ptr<Descriptor>> Transports(const fdds::DomainParticipantQos& qos) {
  std::vector<std::shared_ptr<Descriptor>> found;
  for (const auto& t : qos.transport().user_transports) {
    if (auto d = std::dynamic_pointer_cast<Descriptor>(t)) found.push_back(d);
  }
  return found;
}

double Seconds(const frtps::Duration_t& d) { return d.seconds + d.nanosec * 1e-9; }

// WAN participants are dropped after a short silence: shorter than the robot's TCP user timeout,
// so that a peer whose connection the kernel dropped is forgotten and discovered afresh (Fast DDS
// 2.9 does not recover a TCP participant that outlives its connection), and long enough for two
// announcements to be missed.
void ExpectWanLease(const fdds::DomainParticipantQos& qos, const std::string& what) {
  const auto& discovery = qos.wire_protocol().builtin.discovery_config;
  const double lease_s = Seconds(discovery.leaseDuration);
  EXPECT_LT(lease_s, mostar::dds::ParticipantOptions::kDefaultTcpUserTimeoutMs / 1000.0) << what;
  EXPECT_GE(lease_s, 3 * Seconds(discovery.leaseDuration_announcementperiod)) << what;
}

// Over the WireGuard overlay (UDP; the TCP fallback only tunnels its datagrams) a short outage
// keeps every match: the lease outlasts a 5 s cut with two announcements to spare, and a
// vanished peer is still forgotten within 10 s.
void ExpectOverlayLease(const fdds::DomainParticipantQos& qos, const std::string& what) {
  const auto& discovery = qos.wire_protocol().builtin.discovery_config;
  const double lease_s = Seconds(discovery.leaseDuration);
  const double announcement_s = Seconds(discovery.leaseDuration_announcementperiod);
  EXPECT_GE(lease_s, 5.0 + 2 * announcement_s) << what;
  EXPECT_LE(lease_s, 10.0) << what;
}

// Fast DDS keeps loaded profiles in one process-wide registry and refuses a second profile of
// the same name, so the shipped files (which all define "robot" and "operator") cannot be
// loaded into one process. Each check therefore runs in a child process of its own; loading the
// same file twice in one process is fine (mostar_relay creates two participants from one file).
#define IN_OWN_PROCESS(body)                              \
  EXPECT_EXIT(                                            \
      {                                                   \
        body;                                             \
        std::exit(::testing::Test::HasFailure() ? 1 : 0); \
      },                                                  \
      ::testing::ExitedWithCode(0), "")

class DdsProfilesTest : public ::testing::Test {
 protected:
  void SetUp() override { GTEST_FLAG_SET(death_test_style, "threadsafe"); }
};

void CheckLan();
void CheckWan();
void CheckWanViaRelay();
void CheckDiscoveryServer();
void CheckWanUdp();
void CheckOverlay();
void CheckUnknownProfile();

TEST_F(DdsProfilesTest, LanProfilesUseUdpAndLargeSharedMemory) { IN_OWN_PROCESS(CheckLan()); }
TEST_F(DdsProfilesTest, WanRobotIsTcpServerAndOperatorsDialIt) { IN_OWN_PROCESS(CheckWan()); }
TEST_F(DdsProfilesTest, WanViaRelayOperatorDialsTheRelay) { IN_OWN_PROCESS(CheckWanViaRelay()); }
TEST_F(DdsProfilesTest, DiscoveryServerProfilesAreClientsOfServerZero) {
  IN_OWN_PROCESS(CheckDiscoveryServer());
}
TEST_F(DdsProfilesTest, WanUdpProfilesAreUnicastWithSmallFragments) {
  IN_OWN_PROCESS(CheckWanUdp());
}
TEST_F(DdsProfilesTest, OverlayProfilesUseOnlyTheOverlayAndDialTheRobot) {
  IN_OWN_PROCESS(CheckOverlay());
}
TEST_F(DdsProfilesTest, UnknownProfileNameIsRefused) { IN_OWN_PROCESS(CheckUnknownProfile()); }

void CheckLan() {
  for (const char* name : {"robot", "operator", "relay", "relay_observers"}) {
    const auto qos = Load("lan.xml", name);
    EXPECT_FALSE(qos.transport().use_builtin_transports) << name;
    ASSERT_EQ(Transports<UDPv4TransportDescriptor>(qos).size(), 1u) << name;
    EXPECT_EQ(Transports<UDPv4TransportDescriptor>(qos)[0]->receiveBufferSize, 4u << 20);
    const auto shm = Transports<SharedMemTransportDescriptor>(qos);
    ASSERT_EQ(shm.size(), 1u) << name;
    EXPECT_EQ(shm[0]->segment_size(), 8u << 20) << name;
    EXPECT_EQ(qos.wire_protocol().builtin.discovery_config.discoveryProtocol,
              frtps::rtps::DiscoveryProtocol_t::SIMPLE);
    EXPECT_DOUBLE_EQ(
        Seconds(qos.wire_protocol().builtin.discovery_config.leaseDuration_announcementperiod),
        1.0);
  }
}

void CheckWan() {
  const auto robot = Load("wan.xml", "robot");
  ASSERT_EQ(robot.transport().user_transports.size(), 1u);
  const auto server = Transports<TCPv4TransportDescriptor>(robot);
  ASSERT_EQ(server.size(), 1u);
  ASSERT_EQ(server[0]->listening_ports.size(), 1u);
  EXPECT_EQ(server[0]->listening_ports[0], 15100);
  EXPECT_EQ(server[0]->get_WAN_address(), "203.0.113.10");
  EXPECT_TRUE(server[0]->enable_tcp_nodelay);
  EXPECT_DOUBLE_EQ(
      Seconds(robot.wire_protocol().builtin.discovery_config.leaseDuration_announcementperiod),
      1.0);

  for (const char* name : {"robot", "operator", "relay", "relay_observers"}) {
    ExpectWanLease(Load("wan.xml", name), std::string("wan.xml ") + name);
  }
  for (const char* name : {"operator", "relay"}) {
    const auto client = Load("wan.xml", name);
    const auto tcp = Transports<TCPv4TransportDescriptor>(client);
    ASSERT_EQ(tcp.size(), 1u) << name;
    EXPECT_TRUE(tcp[0]->listening_ports.empty()) << name << " must not need a listening port";
    const auto& peers = client.wire_protocol().builtin.initialPeersList;
    ASSERT_EQ(peers.size(), 1u) << name;
    EXPECT_EQ(peers.begin()->kind, LOCATOR_KIND_TCPv4);
    EXPECT_EQ(frtps::rtps::IPLocator::toIPv4string(*peers.begin()), "203.0.113.10");
    EXPECT_EQ(frtps::rtps::IPLocator::getPhysicalPort(*peers.begin()), 15100);
    // The peer must equal the locator the robot announces (WAN part included), or Fast DDS
    // 2.9 sends every message several times over the same connection.
    EXPECT_EQ(frtps::rtps::IPLocator::toWanstring(*peers.begin()), "203.0.113.10") << name;
  }

  const auto relay_server =
      Transports<TCPv4TransportDescriptor>(Load("wan.xml", "relay_observers"));
  ASSERT_EQ(relay_server.size(), 1u);
  ASSERT_EQ(relay_server[0]->listening_ports.size(), 1u);
  EXPECT_EQ(relay_server[0]->listening_ports[0], 15101);
}

void CheckWanViaRelay() {
  const auto qos = Load("wan_via_relay.xml", "operator");
  ExpectWanLease(qos, "wan_via_relay.xml operator");
  const auto& peers = qos.wire_protocol().builtin.initialPeersList;
  ASSERT_EQ(peers.size(), 1u);
  EXPECT_EQ(frtps::rtps::IPLocator::toIPv4string(*peers.begin()), "198.51.100.20");
  EXPECT_EQ(frtps::rtps::IPLocator::toWanstring(*peers.begin()), "198.51.100.20");
  EXPECT_EQ(frtps::rtps::IPLocator::getPhysicalPort(*peers.begin()), 15101);
}

void CheckDiscoveryServer() {
  for (const char* name : {"robot", "operator", "relay", "relay_observers"}) {
    const auto qos = Load("discovery_server.xml", name);
    const auto& discovery = qos.wire_protocol().builtin.discovery_config;
    EXPECT_EQ(discovery.discoveryProtocol, frtps::rtps::DiscoveryProtocol_t::CLIENT) << name;
    ASSERT_EQ(discovery.m_DiscoveryServers.size(), 1u) << name;
    const auto& server = discovery.m_DiscoveryServers.front();
    EXPECT_EQ(server.guidPrefix.value[0], 0x44) << name;
    ASSERT_FALSE(server.metatrafficUnicastLocatorList.empty());
    const auto& locator = *server.metatrafficUnicastLocatorList.begin();
    EXPECT_EQ(frtps::rtps::IPLocator::toIPv4string(locator), "192.0.2.10");
    EXPECT_EQ(locator.port, 11811u);
  }
}

void CheckWanUdp() {
  for (const char* name : {"robot", "operator", "relay", "relay_observers"}) {
    const auto qos = Load("wan_udp.xml", name);
    ExpectWanLease(qos, std::string("wan_udp.xml ") + name);
    EXPECT_FALSE(qos.transport().use_builtin_transports) << name;
    const auto udp = Transports<UDPv4TransportDescriptor>(qos);
    ASSERT_EQ(udp.size(), 1u) << name;
    EXPECT_EQ(qos.transport().user_transports.size(), 1u) << name << ": UDP only";
    // One lost packet must cost one fragment, not a whole 64 KB datagram.
    EXPECT_LE(udp[0]->maxMessageSize, 1472u) << name;
    const auto& peers = qos.wire_protocol().builtin.initialPeersList;
    const bool dials = std::string(name) == "operator" || std::string(name) == "relay";
    if (dials) {
      ASSERT_EQ(peers.size(), 1u) << name;
      EXPECT_EQ(frtps::rtps::IPLocator::toIPv4string(*peers.begin()), "203.0.113.10") << name;
    }
  }
}

// The template deploy/wan/make_overlay.sh fills per peer: its defaults are hub 10.77.0.1 and
// robot 10.77.0.2.
void CheckOverlay() {
  for (const char* name : {"robot", "operator", "operator_video", "relay", "relay_observers"}) {
    const auto qos = Load("overlay.xml", name);
    ExpectOverlayLease(qos, std::string("overlay.xml ") + name);
    EXPECT_FALSE(qos.transport().use_builtin_transports) << name;
    const auto udp = Transports<UDPv4TransportDescriptor>(qos);
    ASSERT_EQ(udp.size(), 1u) << name;
    EXPECT_EQ(qos.transport().user_transports.size(), 1u) << name << ": UDP only";
    // Room for the DDS Security handshake (Fast DDS 2.9 sizes it by maxMessageSize; it needs
    // about 5 KB), small enough that a lost packet costs a few KB of repair, not 64 KB.
    EXPECT_GE(udp[0]->maxMessageSize, 8192u) << name;
    EXPECT_LE(udp[0]->maxMessageSize, 16384u) << name;
    // The overlay address, and loopback for participants of the same computer.
    EXPECT_EQ(udp[0]->interfaceWhiteList, (std::vector<std::string>{"10.77.0.2", "127.0.0.1"}))
        << name;
    // Unicast discovery: operators and the relay's robot side dial the robot's overlay address,
    // an operator's video participant the relay on the hub.
    const auto& discovery = qos.wire_protocol().builtin.discovery_config;
    EXPECT_EQ(discovery.discoveryProtocol, frtps::rtps::DiscoveryProtocol_t::SIMPLE) << name;
    const auto& peers = qos.wire_protocol().builtin.initialPeersList;
    const bool dials = std::string(name) == "operator" || std::string(name) == "relay";
    if (std::string(name) == "operator_video") {
      ASSERT_EQ(peers.size(), 1u) << name;
      EXPECT_EQ(frtps::rtps::IPLocator::toIPv4string(*peers.begin()), "10.77.0.1") << name;
    } else if (dials) {
      ASSERT_EQ(peers.size(), 1u) << name;
      EXPECT_EQ(frtps::rtps::IPLocator::toIPv4string(*peers.begin()), "10.77.0.2") << name;
    } else {
      EXPECT_EQ(peers.size(), 0u) << name;
    }
  }
}

void CheckUnknownProfile() {
  auto* factory = fdds::DomainParticipantFactory::get_instance();
  ASSERT_EQ(factory->load_XML_profiles_file(Profile("lan.xml")), ReturnCode_t::RETCODE_OK);
  fdds::DomainParticipantQos qos;
  EXPECT_NE(factory->get_participant_qos_from_profile("no_such_role", qos),
            ReturnCode_t::RETCODE_OK);
}

}  // namespace
}  // namespace mostar::network
