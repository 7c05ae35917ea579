#include "operator_client/ui/frame_picker.h"

#include <iterator>
#include <utility>

namespace mostar::ui {

void FramePicker::ShowUnprocessed(const std::optional<client::DecodedStereoPair>& latest) {
  shown_pair_ = latest;
  shown_result_.reset();
  in_flight_.clear();
}

bool FramePicker::TakeNew(const std::optional<client::DecodedStereoPair>& latest) {
  if (!latest || latest->sequence == submitted_) return false;
  submitted_ = latest->sequence;
  in_flight_[latest->sequence] = *latest;
  while (in_flight_.size() > kMaxInFlight) in_flight_.erase(in_flight_.begin());
  return true;
}

void FramePicker::OnResult(const std::shared_ptr<const vision::VisionResult>& result,
                           const std::optional<client::DecodedStereoPair>& latest) {
  if (result) {
    const auto it = in_flight_.find(result->sequence);
    if (it != in_flight_.end()) {
      shown_pair_ = it->second;
      shown_result_ = result->ok ? result : nullptr;
      result_sequence_ = result->sequence;
      in_flight_.erase(in_flight_.begin(), std::next(it));
    }
  }
  if (!shown_pair_) shown_pair_ = latest;  // nothing processed yet
}

FramePicker::DrawnScan FramePicker::ScanToDraw(std::optional<LaserScan> nearest) const {
  if (shown_result_ && shown_pair_ && shown_result_->sequence == shown_pair_->sequence &&
      !shown_result_->classification.corrected_scan.ranges_m.empty()) {
    return {shown_result_->classification.corrected_scan, shown_result_->placement};
  }
  return {std::move(nearest), std::nullopt};
}

}  // namespace mostar::ui
