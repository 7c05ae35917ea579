#include "common/dds/domain.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cstdlib>
#include <optional>
#include <string>

namespace mostar::dds {

int DomainIdFromEnvironment(int fallback) {
  const char* env = std::getenv("MOSTAR_DDS_DOMAIN");
  if (env == nullptr || *env == '\0') return fallback;
  char* end = nullptr;
  const long value = std::strtol(env, &end, 10);
  if (*end != '\0' || value < 0 || value > 232) return fallback;
  return static_cast<int>(value);
}

std::optional<int> AcquireUnusedDomainId(int first, int count, int start) {
  for (int i = 0; i < count; ++i) {
    const int candidate = first + (start + i) % count;
    const std::string path = "/tmp/mostar_dds_domain_" + std::to_string(candidate) + ".lock";
    const int fd = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0) continue;
    if (flock(fd, LOCK_EX | LOCK_NB) == 0) return candidate;  // fd kept open: held until exit
    close(fd);
  }
  return std::nullopt;
}

int PerProcessDomainId() {
  constexpr int kFirst = 100;
  constexpr int kCount = 132;
  static const int domain = [] {
    const int start = static_cast<int>(getpid() % kCount);
    return AcquireUnusedDomainId(kFirst, kCount, start).value_or(kFirst + start);
  }();
  return domain;
}

}  // namespace mostar::dds
