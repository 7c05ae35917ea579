// The control protocol of a published replay (robot_server --replay), one command per line on
// standard input:
//   p        pause / resume
//   s [N]    while paused, deliver the next N records (N >= 1, default 1)
//   r RATE   playback speed factor (> 0)
//   q        stop the replay
// Blank lines are ignored. Pure: parsing knows nothing of the player or the stream.
#pragma once

#include <string>

#include "common/record/replay_player.h"

namespace mostar::replay {

struct ReplayControl {
  enum class Kind { kNone, kTogglePause, kStep, kSetRate, kQuit };
  Kind kind = Kind::kNone;
  int steps = 1;      // kStep
  double rate = 1.0;  // kSetRate
};

// False with a message (naming the line and the accepted commands) for an unknown or malformed
// line; a blank line is kNone.
bool ParseReplayControl(const std::string& line, ReplayControl* control, std::string* error);

// Applies a control to the player. Returns false when it asks to stop (kQuit).
bool ApplyReplayControl(const ReplayControl& control, record::ReplayPlayer* player);

}  // namespace mostar::replay
