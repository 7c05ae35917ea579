#include "common/dds/interface_wait.h"

#include <arpa/inet.h>
#include <fastdds/rtps/transport/SocketTransportDescriptor.h>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <ifaddrs.h>
#include <net/if.h>
#include <netinet/in.h>

#include <algorithm>
#include <memory>

namespace mostar::dds {

std::vector<std::string> WhitelistedAddresses(
    const eprosima::fastdds::dds::DomainParticipantQos& qos) {
  std::vector<std::string> out;
  for (const auto& transport : qos.transport().user_transports) {
    const auto socket =
        std::dynamic_pointer_cast<eprosima::fastdds::rtps::SocketTransportDescriptor>(transport);
    if (!socket) continue;
    for (const std::string& address : socket->interfaceWhiteList) {
      if (std::find(out.begin(), out.end(), address) == out.end()) out.push_back(address);
    }
  }
  return out;
}

std::vector<std::string> RunningIpv4Addresses(const ifaddrs* list) {
  std::vector<std::string> out;
  for (const ifaddrs* i = list; i != nullptr; i = i->ifa_next) {
    if (i->ifa_addr == nullptr || i->ifa_addr->sa_family != AF_INET) continue;
    if ((i->ifa_flags & IFF_RUNNING) == 0) continue;  // as Fast DDS's IPFinder::getIPs
    char text[INET_ADDRSTRLEN] = {};
    const auto* in = reinterpret_cast<const sockaddr_in*>(i->ifa_addr);
    if (inet_ntop(AF_INET, &in->sin_addr, text, sizeof(text)) != nullptr) out.emplace_back(text);
  }
  return out;
}

std::vector<std::string> LocalIpv4Addresses() {
  ifaddrs* list = nullptr;
  if (getifaddrs(&list) != 0) return {};
  std::vector<std::string> out = RunningIpv4Addresses(list);
  freeifaddrs(list);
  return out;
}

std::vector<std::string> MissingAddresses(const std::vector<std::string>& wanted,
                                          const std::vector<std::string>& local) {
  std::vector<std::string> out;
  for (const std::string& w : wanted) {
    if (std::find(local.begin(), local.end(), w) == local.end()) out.push_back(w);
  }
  return out;
}

std::vector<std::string> AddressWatch::Check(bool* changed) {
  if (wanted_.empty()) {
    if (changed != nullptr) *changed = false;
    return {};
  }
  return Check(LocalIpv4Addresses(), changed);
}

std::vector<std::string> AddressWatch::Check(const std::vector<std::string>& local, bool* changed) {
  std::vector<std::string> missing = MissingAddresses(wanted_, local);
  if (changed != nullptr) *changed = missing != last_missing_;
  last_missing_ = missing;
  return missing;
}

bool AnnouncesHostAddresses(const eprosima::fastdds::dds::DomainParticipantQos& qos) {
  if (!qos.wire_protocol().builtin.metatrafficUnicastLocatorList.empty() ||
      !qos.wire_protocol().default_unicast_locator_list.empty()) {
    return false;
  }
  if (!WhitelistedAddresses(qos).empty()) return false;
  if (qos.transport().use_builtin_transports) return true;
  for (const auto& transport : qos.transport().user_transports) {
    if (std::dynamic_pointer_cast<eprosima::fastdds::rtps::UDPv4TransportDescriptor>(transport)) {
      return true;
    }
  }
  return false;
}

namespace {
bool IsLoopback(const std::string& address) { return address.rfind("127.", 0) == 0; }
bool Contains(const std::vector<std::string>& list, const std::string& value) {
  return std::find(list.begin(), list.end(), value) != list.end();
}
}  // namespace

bool AnnouncedAddressesStale(const std::vector<std::string>& announced,
                             const std::vector<std::string>& local) {
  for (const std::string& a : announced) {
    if (!IsLoopback(a) && Contains(local, a)) return false;  // still reachable there
  }
  for (const std::string& l : local) {
    if (!IsLoopback(l) && !Contains(announced, l)) return true;  // a new participant would be
  }
  return false;
}

bool ReaddressWatch::Check(const std::vector<std::string>& local, TimePoint now) {
  if (!AnnouncedAddressesStale(announced_, local)) {
    stale_since_.reset();
    return false;
  }
  if (!stale_since_) stale_since_ = now;
  return now - *stale_since_ >= hold_;
}

}  // namespace mostar::dds
