// DDS domain id conventions.
//
// Programs take `--domain N`; when absent they use the MOSTAR_DDS_DOMAIN environment variable,
// and then 0. Each test process takes a domain id of its own (PerProcessDomainId) so that test
// processes can run in parallel without hearing each other. Test scripts on loopback use
// [10, 99]; scripts in their own network namespaces may use any id.
#pragma once

#include <optional>
#include <string>

namespace mostar::dds {

// MOSTAR_DDS_DOMAIN if set and valid, else `fallback`.
int DomainIdFromEnvironment(int fallback = 0);
// For tests: a domain id in [100, 231] that no other running process took. The first call locks
// /tmp/mostar_dds_domain_<id>.lock (flock, released when the process ends), starting from the
// process id; later calls return the same id.
int PerProcessDomainId();
// Locks and returns the first id of [first, first + count) from first + start on (wrapping)
// whose lock file no process holds; nullopt when all are held. The lock lasts until exit.
std::optional<int> AcquireUnusedDomainId(int first, int count, int start);

}  // namespace mostar::dds
