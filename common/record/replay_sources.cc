#include "common/record/replay_sources.h"

#include <algorithm>
#include <utility>

namespace mostar::record {

ReplayFrameSource::ReplayFrameSource(std::unique_ptr<RecordStream> stream)
    : stream_(std::move(stream)) {}

bool ReplayFrameSource::Fill() {
  if (next_.has_value()) return true;
  RecordedMessage message;
  while (stream_->Next(&message)) {
    auto* image = std::get_if<RecordedImage>(&message.payload);
    if (image == nullptr) continue;
    // A partner already waiting?
    for (auto it = pending_.begin(); it != pending_.end(); ++it) {
      if (it->image.image.stamp != image->image.stamp || it->image.eye == image->eye) continue;
      TimedStereoPair pair;
      pair.log_time = std::max(it->log_time, message.log_time);
      const bool waiting_is_left = it->image.eye == Eye::kLeft;
      RecordedImage& left = waiting_is_left ? it->image : *image;
      RecordedImage& right = waiting_is_left ? *image : it->image;
      pair.pair.sequence = left.pair_sequence != 0 ? left.pair_sequence : right.pair_sequence;
      pair.pair.left = std::move(left.image);
      pair.pair.right = std::move(right.image);
      // Eyes older than this pair's will never be completed in order: drop them.
      orphan_eyes_ += static_cast<uint64_t>(it - pending_.begin());
      pending_.erase(pending_.begin(), it + 1);
      next_ = std::move(pair);
      return true;
    }
    pending_.push_back(Eyed{message.log_time, std::move(*image)});
    if (pending_.size() > kMaxPendingEyes) {
      pending_.pop_front();
      ++orphan_eyes_;
    }
  }
  return false;
}

bool ReplayFrameSource::Next(TimedStereoPair* pair) {
  if (!Fill()) return false;
  *pair = std::move(*next_);
  next_.reset();
  return true;
}

bool ReplayFrameSource::NextUntil(Time until, TimedStereoPair* pair) {
  if (!Fill() || next_->log_time > until) return false;
  return Next(pair);
}

std::optional<Time> ReplayFrameSource::PeekTime() {
  if (!Fill()) return std::nullopt;
  return next_->log_time;
}

bool ReplayFrameSource::SeekToTime(Time t) {
  next_.reset();
  pending_.clear();
  return stream_->SeekToTime(t) && Fill();
}

}  // namespace mostar::record
