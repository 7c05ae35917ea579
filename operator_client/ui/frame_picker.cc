#include "operator_client/ui/frame_picker.h"

#include <iterator>
#include <utility>

namespace mostar::ui {

const char* ResultStateName(FramePicker::ResultState state) {
  switch (state) {
    case FramePicker::ResultState::kNone:
      return "none";
    case FramePicker::ResultState::kInTime:
      return "in time";
    case FramePicker::ResultState::kWaiting:
      return "waiting";
    case FramePicker::ResultState::kAddedLate:
      return "added late";
  }
  return "?";
}

const char* ResultNote(FramePicker::ResultState state) {
  switch (state) {
    case FramePicker::ResultState::kWaiting:
      return "edges: not ready in time, shown without dots (they follow)";
    case FramePicker::ResultState::kAddedLate:
      return "edges: dots added after the image";
    case FramePicker::ResultState::kNone:
    case FramePicker::ResultState::kInTime:
      break;
  }
  return "";
}

void FramePicker::Show(const client::DecodedStereoPair& pair,
                       std::shared_ptr<const vision::VisionResult> result, ResultState state,
                       SteadyTime ready_at) {
  shown_pair_ = pair;
  shown_result_ = std::move(result);
  result_state_ = state;
  shown_ready_at_ = ready_at;
  ++shown_version_;
}

void FramePicker::ShowUnprocessed(const std::optional<client::DecodedStereoPair>& latest) {
  in_flight_.clear();
  if (!latest) {
    if (shown_pair_) ++shown_version_;
    shown_pair_.reset();
    shown_result_.reset();
    result_state_ = ResultState::kNone;
    return;
  }
  if (shown_pair_ && shown_pair_->sequence == latest->sequence && !shown_result_) return;
  Show(*latest, nullptr, ResultState::kNone, latest->decoded);
}

bool FramePicker::TakeNew(const std::optional<client::DecodedStereoPair>& latest, SteadyTime now) {
  if (!latest || latest->sequence == submitted_) return false;
  submitted_ = latest->sequence;
  in_flight_[latest->sequence] = {*latest, now};
  while (in_flight_.size() > kMaxInFlight) in_flight_.erase(in_flight_.begin());
  return true;
}

void FramePicker::OnResult(const std::shared_ptr<const vision::VisionResult>& result,
                           const std::optional<client::DecodedStereoPair>& latest, SteadyTime now,
                           Duration result_wait) {
  if (result) {
    const auto it = in_flight_.find(result->sequence);
    if (it != in_flight_.end()) {
      const uint64_t shown = shown_sequence();
      if (result->sequence > shown) {
        ++counts_.in_time;
        Show(it->second.pair, result->ok ? result : nullptr, ResultState::kInTime,
             result->published);
        result_sequence_ = result->sequence;
      } else if (result->sequence == shown) {
        // Shown when its wait ran out: its dots and correction are added now.
        ++counts_.added_late;
        Show(it->second.pair, result->ok ? result : nullptr, ResultState::kAddedLate,
             shown_ready_at_);
        result_sequence_ = result->sequence;
      } else {
        ++counts_.missed;  // a newer pair is on screen: going back would show an older image
      }
      in_flight_.erase(in_flight_.begin(), std::next(it));
    }
  }
  if (!in_flight_.empty()) {
    const auto& [sequence, newest] = *in_flight_.rbegin();
    if (sequence > shown_sequence() && now - newest.taken >= result_wait) {
      ++counts_.without_result;
      Show(newest.pair, nullptr, ResultState::kWaiting, newest.taken + result_wait);
    }
  }
  if (!shown_pair_ && latest) {
    // Nothing on screen yet: the first picture matters more than its dots.
    const bool awaited = in_flight_.count(latest->sequence) > 0;
    if (awaited) ++counts_.without_result;
    Show(*latest, nullptr, awaited ? ResultState::kWaiting : ResultState::kNone, now);
  }
}

std::optional<SteadyTime> FramePicker::NextWaitEnd(Duration result_wait) const {
  if (in_flight_.empty()) return std::nullopt;
  const auto& [sequence, newest] = *in_flight_.rbegin();
  if (sequence <= shown_sequence()) return std::nullopt;
  return newest.taken + result_wait;
}

FramePicker::DrawnScan FramePicker::ScanToDraw(std::optional<LaserScan> nearest) const {
  if (shown_result_ && shown_pair_ && shown_result_->sequence == shown_pair_->sequence &&
      !shown_result_->classification.corrected_scan.ranges_m.empty()) {
    return {shown_result_->classification.corrected_scan, shown_result_->placement};
  }
  return {std::move(nearest), std::nullopt};
}

}  // namespace mostar::ui
