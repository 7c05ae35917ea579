// Per-topic views of a recording for replay backends: the laser replay backend reads scans,
// the camera replay backend reads stereo pairs, each from its own RecordStream (open the file
// once per backend) and each paced by its own ReplayClock.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>

#include "common/record/recording_format.h"

namespace mostar::record {

struct TimedScan {
  Time log_time;  // when it was recorded: pace replay with it
  LaserScan scan;
};

struct TimedStereoPair {
  Time log_time;  // the later of the two eyes' log times
  CompressedStereoPair pair;
};

// The scans of a recording, in file order. Not thread-safe.
class ReplayScanSource {
 public:
  explicit ReplayScanSource(std::unique_ptr<RecordStream> stream);

  // The next scan; false at the end of the stream.
  bool Next(TimedScan* scan);
  // The next scan if its log time is <= `until` (e.g. ReplayClock::RecordingNow()); false if
  // none is due yet (it stays next) or at the end.
  bool NextUntil(Time until, TimedScan* scan);
  // Log time of the next scan; nullopt at the end.
  std::optional<Time> PeekTime();
  // Positions before the first scan with log_time >= t (Time::min() = rewind).
  bool SeekToTime(Time t);

 private:
  bool Fill();

  std::unique_ptr<RecordStream> stream_;
  std::optional<TimedScan> next_;
};

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
