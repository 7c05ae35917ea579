#include "common/dds/network_check.h"

namespace mostar::dds {

bool NetworkCheck::RestartNeeded(TimePoint now) {
  if (started_ && now < next_) return false;
  started_ = true;
  next_ = now + period_;
  ++checks_;
  bool needed = false;
  for (const Participant* p : participants_) {
    if (p == nullptr) continue;
    p->MissingProfileAddresses();  // logs changes
    needed = p->NeedsNewParticipant() || needed;
  }
  return needed;
}

}  // namespace mostar::dds
