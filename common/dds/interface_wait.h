// The local addresses a DDS profile's transports are restricted to (interfaceWhiteList), and
// whether this host has them yet. A participant created while a whitelisted address does not
// exist (robot_server started before its WireGuard overlay address) announces no locator on it
// and is never discovered there, silently (Fast DDS 2.9.1's UDPv4Transport keeps only the
// whitelisted addresses it finds on the host when the transport is made, and with none left
// falls back to 192.0.2.0); so service programs wait for the addresses first
// (ParticipantOptions::wait_for_interfaces).
#pragma once

#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <string>
#include <vector>

namespace mostar::dds {

// Every address in the interfaceWhiteList of `qos`'s UDPv4/TCPv4 transports, once each, in
// order. Empty when no transport is restricted.
std::vector<std::string> WhitelistedAddresses(
    const eprosima::fastdds::dds::DomainParticipantQos& qos);

// The IPv4 addresses of this host's interfaces now (getifaddrs), dotted.
std::vector<std::string> LocalIpv4Addresses();

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

}  // namespace mostar::dds
