#include "common/record/replay_player.h"

#include <cmath>
#include <utility>

namespace mostar::record {
namespace {

Duration Scale(Duration d, double factor) {
  return Duration(static_cast<int64_t>(std::llround(static_cast<double>(d.count()) * factor)));
}

// Steady time between the last record of a loop and the first of the next.
constexpr Duration kLoopGap = std::chrono::milliseconds(100);

}  // namespace

ReplayClock::ReplayClock(const Clock& clock, double rate)
    : clock_(clock), rate_(rate > 0 ? rate : 1.0), anchor_steady_(clock.SteadyNow()) {}

void ReplayClock::JumpTo(Time recording_time) {
  anchor_recording_ = recording_time;
  anchor_steady_ = clock_.SteadyNow();
}

Time ReplayClock::RecordingNow() const {
  if (paused_) return anchor_recording_;
  return anchor_recording_ + Scale(clock_.SteadyNow() - anchor_steady_, rate_);
}

SteadyTime ReplayClock::DueTime(Time recording_time) const {
  if (paused_) return SteadyTime::max();
  return anchor_steady_ + Scale(recording_time - anchor_recording_, 1.0 / rate_);
}

void ReplayClock::Pause() {
  if (paused_) return;
  anchor_recording_ = RecordingNow();
  anchor_steady_ = clock_.SteadyNow();
  paused_ = true;
}

void ReplayClock::Resume() {
  if (!paused_) return;
  anchor_steady_ = clock_.SteadyNow();
  paused_ = false;
}

void ReplayClock::SetRate(double rate) {
  if (!(rate > 0) || !std::isfinite(rate)) return;
  anchor_recording_ = RecordingNow();
  anchor_steady_ = clock_.SteadyNow();
  rate_ = rate;
}

bool ReplayOptions::IsValid(std::string* error) const {
  if (!(rate > 0) || !std::isfinite(rate)) {
    *error = "replay rate must be a positive number (got " + std::to_string(rate) + ")";
    return false;
  }
  return true;
}

ReplayPlayer::ReplayPlayer(RecordStream* stream, const Clock& clock, const ReplayOptions& options)
    : stream_(stream), clock_(clock), options_(options), replay_clock_(clock, options.rate) {
  if (options_.start_paused) replay_clock_.Pause();
  if (stream_->SeekToTime(Time::min())) {
    RecordedMessage first;
    if (stream_->Next(&first)) {
      replay_clock_.JumpTo(first.log_time);
      next_ = std::move(first);
    }
  }
}

void ReplayPlayer::Advance(bool allow_loop) {
  RecordedMessage message;
  if (stream_->Next(&message)) {
    next_ = std::move(message);
    return;
  }
  next_.reset();
  if (!allow_loop || !options_.loop || !stream_->SeekToTime(Time::min()) ||
      !stream_->Next(&message)) {
    return;
  }
  ++loops_completed_;
  // The first record of the new loop is due kLoopGap (steady time) from now.
  replay_clock_.JumpTo(message.log_time - Scale(kLoopGap, replay_clock_.rate()));
  next_ = std::move(message);
}

std::vector<RecordedMessage> ReplayPlayer::PollDue(size_t max_records) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<RecordedMessage> due;
  bool looped = false;
  const SteadyTime now = clock_.SteadyNow();
  while (next_.has_value() && due.size() < max_records) {
    if (steps_pending_ > 0) {
      --steps_pending_;
      replay_clock_.JumpTo(next_->log_time);
    } else if (replay_clock_.paused() || replay_clock_.DueTime(next_->log_time) > now) {
      break;
    }
    position_ = next_->log_time;
    due.push_back(std::move(*next_));
    ++records_delivered_;
    const uint64_t loops_before = loops_completed_;
    Advance(!looped);
    looped = looped || loops_completed_ != loops_before;
  }
  return due;
}

std::optional<SteadyTime> ReplayPlayer::NextDueTime() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!next_.has_value()) return std::nullopt;
  if (steps_pending_ > 0) return clock_.SteadyNow();
  if (replay_clock_.paused()) return std::nullopt;
  return replay_clock_.DueTime(next_->log_time);
}

void ReplayPlayer::Pause() {
  std::lock_guard<std::mutex> lock(mutex_);
  replay_clock_.Pause();
}

void ReplayPlayer::Resume() {
  std::lock_guard<std::mutex> lock(mutex_);
  steps_pending_ = 0;
  replay_clock_.Resume();
}

bool ReplayPlayer::paused() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return replay_clock_.paused();
}

void ReplayPlayer::Step(int count) {
  std::lock_guard<std::mutex> lock(mutex_);
  replay_clock_.Pause();
  if (count > 0) steps_pending_ += count;
}

void ReplayPlayer::SetRate(double rate) {
  std::lock_guard<std::mutex> lock(mutex_);
  replay_clock_.SetRate(rate);
}

bool ReplayPlayer::SeekToTime(Time t) {
  std::lock_guard<std::mutex> lock(mutex_);
  steps_pending_ = 0;
  next_.reset();
  RecordedMessage message;
  if (!stream_->SeekToTime(t) || !stream_->Next(&message)) return false;
  replay_clock_.JumpTo(message.log_time);
  next_ = std::move(message);
  return true;
}

bool ReplayPlayer::finished() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return !next_.has_value();
}

Time ReplayPlayer::position() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return position_;
}

uint64_t ReplayPlayer::loops_completed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return loops_completed_;
}

uint64_t ReplayPlayer::records_delivered() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return records_delivered_;
}

}  // namespace mostar::record
