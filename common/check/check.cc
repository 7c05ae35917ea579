#include "common/check/check.h"

#include <cstdio>
#include <cstdlib>
#include <string>

namespace mostar::internal {

CheckFailure::CheckFailure(const char* file, int line, const char* condition) {
  where_ << file << ":" << line << ": check failed: " << condition;
}

CheckFailure::~CheckFailure() {
  const std::string message = message_.str();
  const std::string text = where_.str() + (message.empty() ? "" : ": " + message);
  std::fprintf(stderr, "%s\n", text.c_str());
  std::fflush(stderr);
  std::abort();
}

}  // namespace mostar::internal
