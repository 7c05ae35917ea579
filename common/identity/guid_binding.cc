#include "common/identity/guid_binding.h"

namespace mostar::identity {

GuidPrefix AdjustGuidPrefix(const GuidPrefix& candidate, const Sha256& hash) {
  GuidPrefix out = candidate;
  out[0] = static_cast<uint8_t>(0x80 | (hash[0] >> 1));
  for (int i = 1; i < 6; ++i) {
    out[i] = static_cast<uint8_t>((hash[i - 1] << 7) | (hash[i] >> 1));
  }
  return out;
}

bool GuidPrefixDerivesFromSubject(const GuidPrefix& prefix, const Sha256& hash) {
  if ((prefix[0] & 0x80) == 0) return false;
  // Bits 1..47 of the prefix, shifted left by one, against bits 0..46 of the hash.
  for (int i = 0; i < 6; ++i) {
    const uint8_t next = i < 5 ? static_cast<uint8_t>(prefix[i + 1] >> 7) : 0;
    const uint8_t bits = static_cast<uint8_t>((prefix[i] << 1) | next);
    const uint8_t expected = i < 5 ? hash[i] : static_cast<uint8_t>(hash[5] & 0xFE);
    if (bits != expected) return false;
  }
  return true;
}

}  // namespace mostar::identity
