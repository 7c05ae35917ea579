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

}  // namespace mostar::dds
