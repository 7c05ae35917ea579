#include "common/testing/dds_profiles.h"

#include <fstream>

namespace mostar::testing {

std::string WriteLoopbackUdpProfile(const std::string& dir, const std::string& profile_name) {
  const std::string path = dir + "/" + profile_name + ".xml";
  std::ofstream out(path);
  out << R"(<?xml version="1.0" encoding="UTF-8" ?>
<profiles xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <transport_descriptors><transport_descriptor>
    <transport_id>)"
      << profile_name << R"(_udp</transport_id><type>UDPv4</type>
    <interfaceWhiteList><address>127.0.0.1</address></interfaceWhiteList>
  </transport_descriptor></transport_descriptors>
  <participant profile_name=")"
      << profile_name << R"("><rtps>
    <useBuiltinTransports>false</useBuiltinTransports>
    <userTransports><transport_id>)"
      << profile_name << R"(_udp</transport_id></userTransports>
  </rtps></participant>
</profiles>
)";
  out.close();
  return out ? path : std::string();
}

}  // namespace mostar::testing
