// When the console should leave DDS and join again as a new participant. Fast DDS 2.9.1 can
// leave a secure participant unauthenticated for good (docs/networking.md, Known limits): the
// robot and the console discover each other, the handshake never ends, and nothing of the robot
// ever matches. Joining again (a new participant, a new GUID, a new handshake) is what an
// operator would do by restarting the console.
//
// The console cannot tell that from a robot that is simply not there (not started yet, out of
// reach): in both, none of the robot's writers match. So it joins again after `first` without
// the robot, then after twice as long each time (at most `longest`), and starts over once the
// robot is seen. A join costs a participant's creation and discovery, nothing the robot keeps:
// its deadman and lease rules do not depend on the console's participant. Not thread-safe.
#pragma once

#include <optional>
#include <string>

#include "common/time/time.h"

namespace mostar::client {

struct RejoinOptions {
  Duration first = std::chrono::seconds(15);     // without the robot, then join again
  Duration longest = std::chrono::seconds(120);  // the wait doubles up to this
  bool IsValid(std::string* error) const;
};

// `first_s` (> 0) seconds first, at most max(first_s, 120 s).
RejoinOptions RejoinOptionsAfter(double first_s);

class RejoinPolicy {
 public:
  explicit RejoinPolicy(const RejoinOptions& options = {})
      : options_(options), wait_(options.first) {}

  // `robot_seen`: some writer of the robot's matched this console's readers now. True when the
  // console should join again now; then call Rejoined.
  bool Update(bool robot_seen, SteadyTime now);
  // The console joined again at `now`: the next join waits twice as long.
  void Rejoined(SteadyTime now);
  int rejoins() const { return rejoins_; }
  Duration wait() const { return wait_; }

 private:
  RejoinOptions options_;
  Duration wait_;
  std::optional<SteadyTime> unseen_since_;
  int rejoins_ = 0;
};

}  // namespace mostar::client
