// The local addresses a DDS profile's transports are restricted to (interfaceWhiteList), and
// whether this host has them yet. A participant created while a whitelisted address does not
// exist (robot_server started before its WireGuard overlay address) announces no locator on it
// and is never discovered there, silently (Fast DDS 2.9.1's UDPv4Transport keeps only the
// whitelisted addresses it finds on the host when the transport is made, and with none left
// falls back to 192.0.2.0); so service programs wait for the addresses first
// (ParticipantOptions::wait_for_interfaces).
#pragma once

#include <chrono>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <optional>
#include <string>
#include <vector>

struct ifaddrs;

namespace mostar::dds {

// Every address in the interfaceWhiteList of `qos`'s UDPv4/TCPv4 transports, once each, in
// order. Empty when no transport is restricted.
std::vector<std::string> WhitelistedAddresses(
    const eprosima::fastdds::dds::DomainParticipantQos& qos);

// The IPv4 addresses of this host's running interfaces now (getifaddrs), dotted: the ones Fast
// DDS 2.9.1 can use. Its IPFinder skips an interface without IFF_RUNNING, so a participant
// created between `ip address add` and `ip link set up` (wg-quick does both, in that order)
// would never use that address although it exists.
std::vector<std::string> LocalIpv4Addresses();

// The IPv4 addresses of the interfaces in a getifaddrs list that have IFF_RUNNING, dotted, in
// list order. Pure.
std::vector<std::string> RunningIpv4Addresses(const ifaddrs* list);

// The entries of `wanted` that are not in `local`. Pure.
std::vector<std::string> MissingAddresses(const std::vector<std::string>& wanted,
                                          const std::vector<std::string>& local);

// Watches the addresses a running participant's profile needs (the overlay restarted or taken
// down under a running program): Check() says which are missing now and whether that changed
// since the previous call, for the log and the health. Its participant is reachable again as
// soon as the same address is back (sockets stay bound to it: tests/network/boot_order_test.sh
// measured the first scan 0.1 s after). Not thread-safe.
class AddressWatch {
 public:
  explicit AddressWatch(std::vector<std::string> wanted) : wanted_(std::move(wanted)) {}
  // The wanted addresses missing from `local` (default: this host's now); `changed`
  // (optional) is set when the missing set differs from the previous call's (the first call
  // compares with none missing).
  std::vector<std::string> Check(bool* changed = nullptr);
  std::vector<std::string> Check(const std::vector<std::string>& local, bool* changed);
  const std::vector<std::string>& wanted() const { return wanted_; }

 private:
  std::vector<std::string> wanted_;
  std::vector<std::string> last_missing_;
};

// A UDP profile without an interfaceWhiteList (lan.xml) announces instead every non-loopback
// IPv4 address the host has when the participant is made, and keeps announcing those: Fast DDS
// 2.9.1 copies them into each endpoint at creation, and a later rescan
// (DomainParticipant::set_qos) updates only the participant's own locators, not its readers'.
// When the host's address changes (a DHCP lease renewed to a new address, a program started
// before its network), peers keep sending to the old address and only a new participant is
// reachable again: the programs then restart in place (common/process/restart_in_place.h).

// True when `qos` is such a profile: the builtin transports, or a UDPv4 user transport, with no
// interfaceWhiteList on any transport and no unicast locators set in the profile.
bool AnnouncesHostAddresses(const eprosima::fastdds::dds::DomainParticipantQos& qos);

// Whether a participant that announced `announced` (the host's addresses when it was made) is
// out of reach now while a new one would not be: none of its non-loopback announced addresses is
// in `local`, and `local` has a non-loopback address it did not announce. Pure.
bool AnnouncedAddressesStale(const std::vector<std::string>& announced,
                             const std::vector<std::string>& local);

// AnnouncedAddressesStale held for `hold` without a break (a renewal passing through no address
// at all, or briefly through both, does not count). Not thread-safe.
class ReaddressWatch {
 public:
  using TimePoint = std::chrono::steady_clock::time_point;
  ReaddressWatch(std::vector<std::string> announced, std::chrono::milliseconds hold)
      : announced_(std::move(announced)), hold_(hold) {}
  // True once the announced addresses have been stale for `hold` up to `now`.
  bool Check(const std::vector<std::string>& local, TimePoint now);
  const std::vector<std::string>& announced() const { return announced_; }

 private:
  std::vector<std::string> announced_;
  std::chrono::milliseconds hold_;
  std::optional<TimePoint> stale_since_;
};

}  // namespace mostar::dds
