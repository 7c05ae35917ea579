#include "common/identity/client_id.h"

namespace mostar::identity {

bool IsValidClientId(std::string_view id, std::string* why) {
  auto fail = [why](const std::string& reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (id.empty()) return fail("empty client id");
  if (id.size() > kMaxClientIdBytes) {
    return fail("client id longer than " + std::to_string(kMaxClientIdBytes) + " bytes");
  }
  for (const char c : id) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '.' || c == '-';
    if (!ok) return fail("client id has a character outside [A-Za-z0-9_.-]");
  }
  return true;
}

}  // namespace mostar::identity
