// The periodic network check of a running program (robot_server, mostar_relay,
// operator_client): at most once per period it logs each participant's whitelisted addresses
// gone and back (Participant::MissingProfileAddresses) and says whether one of them needs a new
// participant, which the program answers by ending in order and restarting in place
// (Participant::NeedsNewParticipant, common/process/restart_in_place.h). Not thread-safe.
#pragma once

#include <chrono>
#include <vector>

#include "common/dds/participant.h"

namespace mostar::dds {

class NetworkCheck {
 public:
  using TimePoint = std::chrono::steady_clock::time_point;
  // Null entries are skipped (an optional second participant).
  explicit NetworkCheck(std::vector<const Participant*> participants,
                        std::chrono::milliseconds period = std::chrono::milliseconds(250))
      : participants_(std::move(participants)), period_(period) {}
  // True when, at a check due at `now`, a participant needs to be made again.
  bool RestartNeeded(TimePoint now);
  // Checks made so far.
  int checks() const { return checks_; }

 private:
  std::vector<const Participant*> participants_;
  std::chrono::milliseconds period_;
  TimePoint next_{};
  bool started_ = false;
  int checks_ = 0;
};

}  // namespace mostar::dds
