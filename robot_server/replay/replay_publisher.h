// Publishes a recording on a RobotLink as the robot would, when the player says each record is
// due, with the recording's stamps: images one eye at a time, scans, odometry, health, lease.
// Recorded velocity commands, e-stops and requests are not acted on. Not thread-safe: one
// publishing thread (controls go to the thread-safe player).
#pragma once

#include <cstdint>
#include <istream>
#include <string>

#include "common/log/stamp_trace.h"
#include "common/record/replay_player.h"
#include "common/time/time.h"
#include "robot_server/node/robot_link.h"

namespace mostar::replay {

class ReplayPublisher {
 public:
  // All pointers outlive this; `trace` may be null.
  ReplayPublisher(record::ReplayPlayer* player, server::RobotLink* link, StampTrace* trace);
  // Publishes every record due now; returns how many were published.
  size_t PublishDue();
  uint64_t published() const { return published_; }

 private:
  record::ReplayPlayer* player_;
  server::RobotLink* link_;
  StampTrace* trace_;
  uint64_t published_ = 0;
};

struct ReplaySessionOptions {
  std::string path;                 // the recording
  record::ReplayOptions replay;     // rate, loop, start paused
  Duration duration = Duration{0};  // stop after this long; zero: at the end or on `stop`
};

// robot_server --replay: publishes the recording until its end (never with loop), a stop
// request (common/process/stop_signals.h: a signal, or the "q" control) or `duration`, reading
// controls (replay_control.h) line by line from `controls` on a detached thread (a blocked read
// cannot be interrupted; the stream must outlive the process, e.g. std::cin). Reports readiness and
// liveness to the service manager. Returns the process exit status: 0, or 2 with a message on
// stderr when the file or options are unusable.
int RunReplaySession(const ReplaySessionOptions& options, server::RobotLink* link,
                     StampTrace* trace, std::istream* controls);

}  // namespace mostar::replay
