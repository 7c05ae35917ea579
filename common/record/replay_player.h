// Replay scheduling: when each recorded message is due, at real speed, faster or slower,
// paused, single-stepped, looping. Pure logic over an injected Clock: it never sleeps. The
// caller (robot_server --replay) polls, publishes what is due and sleeps until NextDueTime().
//
// Time mapping: recording time r (a record's log_time) is due at steady time
//   anchor_steady + (r - anchor_recording) / rate.
// Pausing freezes the recording position; resuming or changing the rate re-anchors there, so
// the position is continuous.
#pragma once

#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "common/record/recording_format.h"
#include "common/time/time.h"

namespace mostar::record {

// Maps recording time to the clock's steady time. Not thread-safe (ReplayPlayer locks).
class ReplayClock {
 public:
  // `clock` must outlive this object. rate > 0 (2 = twice as fast).
  explicit ReplayClock(const Clock& clock, double rate = 1.0);

  // Makes `recording_time` the position now (running or paused state unchanged).
  void JumpTo(Time recording_time);
  // The recording position now: advances with the clock times the rate, frozen while paused.
  Time RecordingNow() const;
  // Steady time when `recording_time` is due; SteadyTime::max() while paused.
  SteadyTime DueTime(Time recording_time) const;

  void Pause();
  void Resume();
  bool paused() const { return paused_; }
  // Ignored unless rate > 0.
  void SetRate(double rate);
  double rate() const { return rate_; }

 private:
  const Clock& clock_;
  double rate_;
  bool paused_ = false;
  SteadyTime anchor_steady_;
  Time anchor_recording_;
};

struct ReplayOptions {
  double rate = 1.0;  // playback speed factor, > 0
  bool loop = false;  // restart from the beginning at the end (or at damage)
  bool start_paused = false;

  bool IsValid(std::string* error) const;
};

// Delivers the records of a RecordStream when they are due. Thread-safe (controls may come from
// a UI or command thread while the publishing thread polls).
class ReplayPlayer {
 public:
  // `stream` and `clock` must outlive the player. The first record is due immediately (unless
  // start_paused). An invalid rate is replaced by 1 (check ReplayOptions::IsValid first).
  ReplayPlayer(RecordStream* stream, const Clock& clock, const ReplayOptions& options);

  ReplayPlayer(const ReplayPlayer&) = delete;
  ReplayPlayer& operator=(const ReplayPlayer&) = delete;

  // The records due now, in file order, at most `max_records`. While paused, only records
  // requested by Step(). At the end of a looping replay, restarts from the beginning (at most
  // once per call) with the first record due now.
  std::vector<RecordedMessage> PollDue(size_t max_records = 1000);
  // When the next record is due (steady time of the injected clock); nullopt when paused with
  // no step pending, or finished. Due in the past = call PollDue() now.
  std::optional<SteadyTime> NextDueTime() const;

  void Pause();
  void Resume();
  bool paused() const;
  // While paused: the next `count` records become due now; the position moves to the last.
  void Step(int count = 1);
  // Changes the speed from the current position on (ignored unless rate > 0).
  void SetRate(double rate);
  // Jumps to the first record with log_time >= t. False if there is none (then finished()).
  bool SeekToTime(Time t);

  // True when a non-looping replay has delivered its last record (or the stream is empty).
  bool finished() const;
  // Recording time of the last delivered record (Time{} before the first).
  Time position() const;
  uint64_t loops_completed() const;
  uint64_t records_delivered() const;

 private:
  // Reads the next record into next_; at the end, loops if asked. Locked.
  void Advance(bool allow_loop);

  mutable std::mutex mutex_;
  RecordStream* const stream_;
  const Clock& clock_;
  const ReplayOptions options_;
  ReplayClock replay_clock_;
  std::optional<RecordedMessage> next_;
  int steps_pending_ = 0;
  Time position_;
  uint64_t loops_completed_ = 0;
  uint64_t records_delivered_ = 0;
};

}  // namespace mostar::record
