#include "common/dds/interface_wait.h"

#include <arpa/inet.h>
#include <fastrtps/xmlparser/XMLProfileManager.h>
#include <gtest/gtest.h>
#include <ifaddrs.h>
#include <net/if.h>
#include <netinet/in.h>

#include <algorithm>
#include <chrono>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fstream>

#include "common/dds/domain.h"
#include "common/dds/participant.h"
#include "common/testing/subprocess.h"

namespace mostar::dds {
namespace {

TEST(InterfaceWaitTest, MissingAddressesAreThoseNotOnTheHost) {
  EXPECT_EQ(MissingAddresses({"10.77.0.2", "127.0.0.1"}, {"127.0.0.1", "192.168.1.5"}),
            (std::vector<std::string>{"10.77.0.2"}));
  EXPECT_TRUE(MissingAddresses({"127.0.0.1"}, {"127.0.0.1"}).empty());
  EXPECT_TRUE(MissingAddresses({}, {}).empty());
}

TEST(InterfaceWaitTest, TheHostHasLoopback) {
  const std::vector<std::string> local = LocalIpv4Addresses();
  EXPECT_NE(std::find(local.begin(), local.end(), "127.0.0.1"), local.end());
}

// An address whose interface is not running yet (wg-quick adds it before `ip link set up`) is
// not one Fast DDS uses, so it does not count as there.
TEST(InterfaceWaitTest, OnlyRunningInterfacesCount) {
  sockaddr_in up_address{};
  up_address.sin_family = AF_INET;
  inet_pton(AF_INET, "10.77.0.4", &up_address.sin_addr);
  sockaddr_in down_address = up_address;
  inet_pton(AF_INET, "10.77.0.5", &down_address.sin_addr);
  sockaddr_in6 v6{};
  v6.sin6_family = AF_INET6;
  ifaddrs v6_entry{};
  v6_entry.ifa_addr = reinterpret_cast<sockaddr*>(&v6);
  v6_entry.ifa_flags = IFF_UP | IFF_RUNNING;
  ifaddrs down{};
  down.ifa_addr = reinterpret_cast<sockaddr*>(&down_address);
  down.ifa_flags = IFF_UP;  // address added, no carrier yet
  down.ifa_next = &v6_entry;
  ifaddrs no_address{};
  no_address.ifa_flags = IFF_UP | IFF_RUNNING;
  no_address.ifa_next = &down;
  ifaddrs running{};
  running.ifa_addr = reinterpret_cast<sockaddr*>(&up_address);
  running.ifa_flags = IFF_UP | IFF_RUNNING;
  running.ifa_next = &no_address;
  EXPECT_EQ(RunningIpv4Addresses(&running), (std::vector<std::string>{"10.77.0.4"}));
  down.ifa_flags = IFF_UP | IFF_RUNNING;
  EXPECT_EQ(RunningIpv4Addresses(&running), (std::vector<std::string>{"10.77.0.4", "10.77.0.5"}));
  EXPECT_TRUE(RunningIpv4Addresses(nullptr).empty());
}

// A UDPv4 profile whose transport is restricted to `addresses`, participant profile `name`.
std::string WriteProfile(const std::string& dir, const std::string& name,
                         const std::vector<std::string>& addresses) {
  const std::string path = dir + "/" + name + ".xml";
  std::ofstream out(path);
  out << R"(<?xml version="1.0" encoding="UTF-8" ?>
<profiles xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <transport_descriptors>
    <transport_descriptor>
      <transport_id>udp_)"
      << name << R"(</transport_id>
      <type>UDPv4</type>
      <interfaceWhiteList>
)";
  for (const std::string& a : addresses) out << "        <address>" << a << "</address>\n";
  out << R"(      </interfaceWhiteList>
    </transport_descriptor>
  </transport_descriptors>
  <participant profile_name=")"
      << name << R"(">
    <rtps>
      <builtin>
        <initialPeersList>
          <locator><udpv4><address>127.0.0.1</address></udpv4></locator>
        </initialPeersList>
      </builtin>
      <userTransports><transport_id>udp_)"
      << name << R"(</transport_id></userTransports>
      <useBuiltinTransports>false</useBuiltinTransports>
    </rtps>
  </participant>
</profiles>
)";
  return path;
}

ParticipantOptions Options(const std::string& profile, const std::string& name) {
  ParticipantOptions options;
  options.domain_id = PerProcessDomainId();
  options.profile = profile;
  options.xml_participant_profile = name;
  options.name = name;
  options.insecure = true;  // a network profile without DDS Security, for this test only
  return options;
}

// An address of the whitelist that this host does not have (TEST-NET-1): the participant waits
// for it as long as asked, then fails naming it; with the addresses present it starts at once.
TEST(InterfaceWaitTest, AParticipantWaitsForItsWhitelistedAddressesThenNamesTheMissingOne) {
  const std::string dir = testing::MakeTempDir("mostar_ifwait_");
  ASSERT_FALSE(dir.empty());
  ParticipantOptions absent =
      Options(WriteProfile(dir, "ifwait_absent", {"192.0.2.77", "127.0.0.1"}), "ifwait_absent");
  absent.wait_for_interfaces = std::chrono::milliseconds(600);
  std::string error;
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(Participant::Create(absent, &error), nullptr);
  EXPECT_GE(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(600));
  EXPECT_NE(error.find("address 192.0.2.77 of the profile's interfaceWhiteList"), std::string::npos)
      << error;
  EXPECT_EQ(error.find("127.0.0.1"), std::string::npos) << error;

  const ParticipantOptions present =
      Options(WriteProfile(dir, "ifwait_present", {"127.0.0.1"}), "ifwait_present");
  auto participant = Participant::Create(present, &error);
  EXPECT_NE(participant, nullptr) << error;
}

// The overlay going down and coming back under a running program: each change is reported once.
TEST(InterfaceWaitTest, AnAddressWatchReportsEachChangeOnce) {
  AddressWatch watch({"10.77.0.2", "127.0.0.1"});
  bool changed = true;
  EXPECT_TRUE(watch.Check({"127.0.0.1", "10.77.0.2"}, &changed).empty());
  EXPECT_FALSE(changed);
  EXPECT_EQ(watch.Check({"127.0.0.1"}, &changed), std::vector<std::string>{"10.77.0.2"});
  EXPECT_TRUE(changed);
  watch.Check({"127.0.0.1"}, &changed);
  EXPECT_FALSE(changed);
  EXPECT_TRUE(watch.Check({"10.77.0.2", "127.0.0.1"}, &changed).empty());
  EXPECT_TRUE(changed);
  AddressWatch none({});
  EXPECT_TRUE(none.Check(&changed).empty());
  EXPECT_FALSE(changed);
}

TEST(InterfaceWaitTest, AnnouncedAddressesAreStaleOnlyWhenNoneIsLeftAndANewOneExists) {
  // A DHCP lease renewed to a new address: the old one gone, the new one there.
  EXPECT_TRUE(AnnouncedAddressesStale({"192.168.1.5"}, {"127.0.0.1", "192.168.1.9"}));
  // A robot started before its network: it announced loopback only, then the LAN came up.
  EXPECT_TRUE(AnnouncedAddressesStale({"127.0.0.1"}, {"127.0.0.1", "192.168.1.9"}));
  EXPECT_TRUE(AnnouncedAddressesStale({}, {"192.168.1.9"}));
  // Still reachable on one announced address: a second interface came or went.
  EXPECT_FALSE(AnnouncedAddressesStale({"192.168.1.5", "10.0.0.3"}, {"10.0.0.3", "192.168.1.9"}));
  EXPECT_FALSE(AnnouncedAddressesStale({"192.168.1.5"}, {"192.168.1.5", "172.17.0.1"}));
  // Network down: a new participant would not be reachable either; the same address may come back.
  EXPECT_FALSE(AnnouncedAddressesStale({"192.168.1.5"}, {"127.0.0.1"}));
  EXPECT_FALSE(AnnouncedAddressesStale({"192.168.1.5"}, {}));
  EXPECT_FALSE(AnnouncedAddressesStale({"127.0.0.1"}, {"127.0.0.1"}));
}

TEST(InterfaceWaitTest, AReaddressWatchWaitsForTheHoldWithoutABreak) {
  using std::chrono::milliseconds;
  ReaddressWatch watch({"192.168.1.5"}, milliseconds(1000));
  const ReaddressWatch::TimePoint t0{};
  EXPECT_FALSE(watch.Check({"192.168.1.5"}, t0));
  EXPECT_FALSE(watch.Check({"192.168.1.9"}, t0 + milliseconds(100)));  // stale from here
  EXPECT_FALSE(watch.Check({"192.168.1.9"}, t0 + milliseconds(1000)));
  EXPECT_FALSE(watch.Check({}, t0 + milliseconds(1050)));  // a break: no address at all
  EXPECT_FALSE(watch.Check({"192.168.1.9"}, t0 + milliseconds(1200)));
  EXPECT_FALSE(watch.Check({"192.168.1.9"}, t0 + milliseconds(2199)));
  EXPECT_TRUE(watch.Check({"192.168.1.9"}, t0 + milliseconds(2200)));
  EXPECT_FALSE(watch.Check({"192.168.1.5", "192.168.1.9"}, t0 + milliseconds(2300)));
}

// Which shipped profiles announce the host's addresses (and so need a new participant when they
// change) and which are pinned to addresses that must come back as they were.
TEST(InterfaceWaitTest, TheLanProfileAnnouncesHostAddressesAndPinnedProfilesDoNot) {
  namespace fdds = eprosima::fastdds::dds;
  eprosima::fastrtps::xmlparser::XMLProfileManager::DeleteInstance();
  auto* factory = fdds::DomainParticipantFactory::get_instance();
  const std::string deploy = std::string(MOSTAR_TEST_SOURCE_DIR) + "/deploy/dds/";
  ASSERT_EQ(factory->load_XML_profiles_file(deploy + "lan.xml"), ReturnCode_t::RETCODE_OK);
  fdds::DomainParticipantQos qos;
  ASSERT_EQ(factory->get_participant_qos_from_profile("robot", qos), ReturnCode_t::RETCODE_OK);
  EXPECT_TRUE(AnnouncesHostAddresses(qos));
  eprosima::fastrtps::xmlparser::XMLProfileManager::DeleteInstance();
  ASSERT_EQ(factory->load_XML_profiles_file(deploy + "overlay.xml"), ReturnCode_t::RETCODE_OK);
  ASSERT_EQ(factory->get_participant_qos_from_profile("robot", qos), ReturnCode_t::RETCODE_OK);
  EXPECT_FALSE(AnnouncesHostAddresses(qos));  // whitelisted overlay address
  eprosima::fastrtps::xmlparser::XMLProfileManager::DeleteInstance();
  const std::string dir = testing::MakeTempDir("mostar_ifwait_");
  ASSERT_EQ(factory->load_XML_profiles_file(WriteProfile(dir, "pinned", {"127.0.0.1"})),
            ReturnCode_t::RETCODE_OK);
  ASSERT_EQ(factory->get_participant_qos_from_profile("pinned", qos), ReturnCode_t::RETCODE_OK);
  EXPECT_FALSE(AnnouncesHostAddresses(qos));
  eprosima::fastrtps::xmlparser::XMLProfileManager::DeleteInstance();
  fdds::DomainParticipantQos builtin;
  EXPECT_TRUE(AnnouncesHostAddresses(builtin));
  builtin.wire_protocol().builtin.metatrafficUnicastLocatorList.push_back(
      eprosima::fastrtps::rtps::Locator_t(7400));
  EXPECT_FALSE(AnnouncesHostAddresses(builtin));  // locators set by hand stay as they are
}

}  // namespace
}  // namespace mostar::dds
