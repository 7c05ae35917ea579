// Fast DDS XML profile files for tests.
#pragma once

#include <string>

namespace mostar::testing {

// Writes `dir`/`profile_name`.xml: one participant profile `profile_name` on UDPv4 restricted
// to 127.0.0.1 (nothing leaves this machine) and without DDS Security, so the programs count it
// as a network profile that needs --insecure. Returns the file's path, "" when it cannot be
// written.
std::string WriteLoopbackUdpProfile(const std::string& dir, const std::string& profile_name);

}  // namespace mostar::testing
