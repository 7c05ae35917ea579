// DDS domain id conventions.
//
// Programs take `--domain N`; when absent they use the MOSTAR_DDS_DOMAIN environment variable,
// and then 0. Tests use a domain id derived from their process id so that test processes can run
// in parallel without hearing each other.
#pragma once

#include <string>

namespace mostar::dds {

// MOSTAR_DDS_DOMAIN if set and valid, else `fallback`.
int DomainIdFromEnvironment(int fallback = 0);
// A domain id in [100, 231] derived from the process id: for tests.
int PerProcessDomainId();

}  // namespace mostar::dds
