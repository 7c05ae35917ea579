#include "common/dds/domain.h"

#include <unistd.h>

#include <cstdlib>

namespace mostar::dds {

int DomainIdFromEnvironment(int fallback) {
  const char* env = std::getenv("MOSTAR_DDS_DOMAIN");
  if (env == nullptr || *env == '\0') return fallback;
  char* end = nullptr;
  const long value = std::strtol(env, &end, 10);
  if (*end != '\0' || value < 0 || value > 232) return fallback;
  return static_cast<int>(value);
}

int PerProcessDomainId() { return 100 + static_cast<int>(getpid() % 132); }

}  // namespace mostar::dds
