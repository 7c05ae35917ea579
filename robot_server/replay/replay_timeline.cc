#include "robot_server/replay/replay_timeline.h"

#include <algorithm>
#include <cmath>
#include <thread>

#include "common/record/recording_reader.h"

namespace mostar::replay {

void RealSleep(Duration d) {
  if (d > Duration::zero()) std::this_thread::sleep_for(d);
}

bool ReplayTimelineOptions::IsValid(std::string* error) const {
  if (!(rate > 0) || !std::isfinite(rate)) {
    *error = "replay rate must be a positive number (got " + std::to_string(rate) + ")";
    return false;
  }
  if (loop_gap < Duration::zero()) {
    *error = "replay loop gap must not be negative";
    return false;
  }
  return true;
}

ReplayTimeline::ReplayTimeline(const Clock& clock, Time begin, Time end,
                               const ReplayTimelineOptions& options)
    : clock_(clock),
      begin_(begin),
      end_(std::max(begin, end)),
      options_(options),
      replay_clock_(clock, options.rate) {}

std::shared_ptr<ReplayTimeline> ReplayTimeline::ForRecording(const std::string& path,
                                                             const Clock& clock,
                                                             const ReplayTimelineOptions& options,
                                                             std::string* error) {
  if (!options.IsValid(error)) return nullptr;
  auto reader = record::RecordingReader::Open(path, error);
  if (!reader) return nullptr;
  record::RecordedMessage message;
  if (!reader->Next(&message)) {
    *error = path + ": no records" +
             (reader->damage() ? " (damaged at byte " + std::to_string(reader->damage()->offset) +
                                     ": " + reader->damage()->reason + ")"
                               : std::string());
    return nullptr;
  }
  const Time begin = message.log_time;
  Time end = begin;
  // The last log time: from the last index entry on, read to the end (or to damage).
  const std::vector<record::IndexEntry>& index = reader->index();
  if (!index.empty() && index.back().log_time > begin) reader->SeekToTime(index.back().log_time);
  while (reader->Next(&message)) end = std::max(end, message.log_time);
  return std::make_shared<ReplayTimeline>(clock, begin, end, options);
}

void ReplayTimeline::Start() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (started_) return;
  replay_clock_.JumpTo(begin_);
  wall_anchor_ = clock_.Now();
  started_ = true;
}

bool ReplayTimeline::started() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return started_;
}

Duration ReplayTimeline::Scaled(Duration d) const {
  return Duration(
      static_cast<int64_t>(std::llround(static_cast<double>(d.count()) / options_.rate)));
}

SteadyTime ReplayTimeline::DueTime(Time log_time, uint64_t pass) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return replay_clock_.DueTime(log_time + static_cast<int64_t>(pass) * loop_period());
}

Time ReplayTimeline::Restamp(Time stamp, uint64_t pass) const {
  if (options_.keep_stamps) return stamp;
  std::lock_guard<std::mutex> lock(mutex_);
  return wall_anchor_ + Scaled(stamp + static_cast<int64_t>(pass) * loop_period() - begin_);
}

Time ReplayTimeline::RecordingNow(uint64_t* pass) const {
  Time now;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    now = replay_clock_.RecordingNow();
  }
  *pass = 0;
  if (!options_.loop || now <= end_) return std::max(now, begin_);
  const Duration period = loop_period();
  if (period <= Duration::zero()) return begin_;  // a single instant, no gap: stay on it
  const Duration into = now - begin_;
  *pass = static_cast<uint64_t>(into / period);
  const Time position = begin_ + into % period;
  if (position <= end_) return position;
  ++*pass;  // in the gap after a pass: the next pass is next
  return begin_;
}

}  // namespace mostar::replay
