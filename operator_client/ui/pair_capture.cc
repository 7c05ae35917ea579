#include "operator_client/ui/pair_capture.h"

#include "common/log/log.h"

namespace mostar::ui {

PairCapture::PairCapture(std::optional<Time> stamp, uint64_t after_sequence)
    : stamp_(stamp), after_sequence_(after_sequence) {}

std::optional<client::DecodedStereoPair> PairCapture::Filter(
    const std::optional<client::DecodedStereoPair>& latest, std::optional<Time> latest_scan_stamp,
    SteadyTime now, std::optional<Time> latest_odometry_stamp) {
  if (!pair_ && latest &&
      (stamp_ ? latest->stamp == *stamp_ : latest->sequence > after_sequence_)) {
    pair_ = latest;
    latched_at_ = now;
  }
  if (!pair_) return std::nullopt;
  if (!ready_) {
    const bool scan_in = latest_scan_stamp && *latest_scan_stamp >= pair_->stamp;
    const bool odometry_in =
        !latest_odometry_stamp || *latest_odometry_stamp >= pair_->stamp + kOdometryAfter;
    if (scan_in && odometry_in) {
      ready_ = true;
    } else if (now - latched_at_ > kScanWait) {
      ready_ = true;
      MOSTAR_LOG(WARNING) << "capture: no " << (scan_in ? "odometry" : "scan")
                          << " stamped after the pair within " << ToSeconds(kScanWait)
                          << " s; rendering with what is here";
    }
  }
  if (!ready_) return std::nullopt;
  return pair_;
}

bool PairCapture::IsCaptureRender(const std::optional<client::DecodedStereoPair>& shown,
                                  bool vision_enabled, uint64_t result_sequence) const {
  return !done_ && ready_ && shown && shown->sequence == pair_->sequence &&
         (!vision_enabled || result_sequence == shown->sequence);
}

bool PairCapture::CountRender() {
  if (done_) return false;
  done_ = ++renders_ >= kRenders;
  return done_;
}

std::optional<Time> PairCapture::latched_stamp() const {
  if (!pair_) return std::nullopt;
  return pair_->stamp;
}

}  // namespace mostar::ui
