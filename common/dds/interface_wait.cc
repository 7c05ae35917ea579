#include "common/dds/interface_wait.h"

#include <arpa/inet.h>
#include <fastdds/rtps/transport/SocketTransportDescriptor.h>
#include <ifaddrs.h>
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

std::vector<std::string> LocalIpv4Addresses() {
  std::vector<std::string> out;
  ifaddrs* list = nullptr;
  if (getifaddrs(&list) != 0) return out;
  for (const ifaddrs* i = list; i != nullptr; i = i->ifa_next) {
    if (i->ifa_addr == nullptr || i->ifa_addr->sa_family != AF_INET) continue;
    char text[INET_ADDRSTRLEN] = {};
    const auto* in = reinterpret_cast<const sockaddr_in*>(i->ifa_addr);
    if (inet_ntop(AF_INET, &in->sin_addr, text, sizeof(text)) != nullptr) out.emplace_back(text);
  }
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

}  // namespace mostar::dds
