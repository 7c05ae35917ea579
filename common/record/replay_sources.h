// Per-topic views of a recording for replay backends: the laser, sonar and bumper replay
// backends read their records, the camera replay backend reads stereo pairs, each from its own
// RecordStream (open the file once per backend) and each paced by its own ReplayClock.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <utility>
#include <variant>

#include "common/record/recording_format.h"

namespace mostar::record {

struct TimedStereoPair {
  Time log_time;  // the later of the two eyes' log times
  CompressedStereoPair pair;
};

// One record of a recording with the time it was recorded.
template <typename T>
struct Timed {
  Time log_time;  // when it was recorded: pace replay with it
  T value;
};

// The records of one kind (LaserScan, SonarRanges, BumperState, ...: a RecordPayload
// alternative) of a recording, in file order; the others are skipped. Not thread-safe.
template <typename T>
class ReplayTopicSource {
 public:
  explicit ReplayTopicSource(std::unique_ptr<RecordStream> stream) : stream_(std::move(stream)) {}

  // The next record; false at the end of the stream.
  bool Next(Timed<T>* out) {
    if (!Fill()) return false;
    *out = std::move(*next_);
    next_.reset();
    return true;
  }
  // The next record if its log time is <= `until` (e.g. ReplayClock::RecordingNow()); false if
  // none is due yet (it stays next) or at the end.
  bool NextUntil(Time until, Timed<T>* out) {
    if (!Fill() || next_->log_time > until) return false;
    return Next(out);
  }
  // Log time of the next record; nullopt at the end.
  std::optional<Time> PeekTime() {
    if (!Fill()) return std::nullopt;
    return next_->log_time;
  }
  // Positions before the first record with log_time >= t (Time::min() = rewind).
  bool SeekToTime(Time t) {
    next_.reset();
    return stream_->SeekToTime(t) && Fill();
  }

 private:
  bool Fill() {
    if (next_.has_value()) return true;
    RecordedMessage message;
    while (stream_->Next(&message)) {
      if (T* value = std::get_if<T>(&message.payload)) {
        next_ = Timed<T>{message.log_time, std::move(*value)};
        return true;
      }
    }
    return false;
  }

  std::unique_ptr<RecordStream> stream_;
  std::optional<Timed<T>> next_;
};

using TimedScan = Timed<LaserScan>;
using ReplayScanSource = ReplayTopicSource<LaserScan>;

// The stereo pairs of a recording, in file order. Left and right eyes are paired by identical
// capture stamp; an eye whose partner does not follow within kMaxPendingEyes image records is
// dropped and counted (the recorder dropped it, or the capture was mono). Not thread-safe.
class ReplayFrameSource {
 public:
  static constexpr size_t kMaxPendingEyes = 8;

  explicit ReplayFrameSource(std::unique_ptr<RecordStream> stream);

  bool Next(TimedStereoPair* pair);
  bool NextUntil(Time until, TimedStereoPair* pair);
  std::optional<Time> PeekTime();
  bool SeekToTime(Time t);

  uint64_t orphan_eyes() const { return orphan_eyes_; }

 private:
  struct Eyed {
    Time log_time;
    RecordedImage image;
  };
  bool Fill();

  std::unique_ptr<RecordStream> stream_;
  std::deque<Eyed> pending_;  // eyes waiting for their partner, in file order
  std::optional<TimedStereoPair> next_;
  uint64_t orphan_eyes_ = 0;
};

}  // namespace mostar::record
