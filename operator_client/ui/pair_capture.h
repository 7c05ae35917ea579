// Deterministic capture of one stereo pair (operator_client --capture-stamp, --capture-after):
// the pair is latched when it arrives, held back until its nearest scan is settled (a scan
// stamped at or after it has arrived) and so is the odometry that moves that scan to the pair's
// time (a sample stamped kOdometryAfter past the pair, when the robot sends odometry), or
// kScanWait has passed; then it is shown until kRenders renders
// with everything in (its edge result too, with edge processing), and then done. What arrives
// when no longer matters, so a replay of a session renders the same picture as the live
// session did. Pure: the caller passes the latest pair, the latest scan stamp and the time.
#pragma once

#include <cstdint>
#include <optional>

#include "common/time/time.h"
#include "operator_client/video/stereo_receiver.h"

namespace mostar::ui {

// The stamp of an optional message (anything with a `stamp`), nullopt when there is none.
template <typename Message>
std::optional<Time> StampOf(const std::optional<Message>& message) {
  return message ? std::optional<Time>(message->stamp) : std::nullopt;
}

class PairCapture {
 public:
  static constexpr int kRenders = 3;  // ImGui windows settle over a few frames
  static constexpr Duration kScanWait = std::chrono::seconds(2);
  // Motion compensation reads odometry up to the nearest scan's end (a scan after the pair is
  // nearest only within half a scan period) plus the heading smoothing window (60 ms): every
  // sample it can use is in once one this far past the pair is.
  static constexpr Duration kOdometryAfter = std::chrono::milliseconds(150);

  // Captures the pair stamped `stamp` (robot clock), or with nullopt the first pair whose
  // sequence is above `after_sequence` (the latest pair decoded when the capture starts).
  PairCapture(std::optional<Time> stamp, uint64_t after_sequence);

  // What the console may show instead of `latest`: nothing until the pair to capture has been
  // latched and its scans and odometry are in, then always that pair. `latest_scan_stamp`: stamp
  // of the newest scan received (nullopt: none); `now`: steady time; `latest_odometry_stamp`:
  // stamp of the newest odometry received (nullopt: none, then there is none to wait for).
  std::optional<client::DecodedStereoPair> Filter(
      const std::optional<client::DecodedStereoPair>& latest, std::optional<Time> latest_scan_stamp,
      SteadyTime now, std::optional<Time> latest_odometry_stamp = std::nullopt);

  // The frame about to be rendered shows the captured pair with everything in: `shown` is the
  // pair on screen, `result_sequence` the pair of the last edge result (FramePicker).
  bool IsCaptureRender(const std::optional<client::DecodedStereoPair>& shown, bool vision_enabled,
                       uint64_t result_sequence) const;
  // Counts a capture render; true when it is the kRenders-th (read that frame back: the
  // capture is then done), false before and after.
  bool CountRender();

  bool done() const { return done_; }
  // Stamp of the latched pair; nullopt before it arrived.
  std::optional<Time> latched_stamp() const;

 private:
  const std::optional<Time> stamp_;
  const uint64_t after_sequence_;
  std::optional<client::DecodedStereoPair> pair_;  // latched
  SteadyTime latched_at_;
  bool ready_ = false;  // its scans have arrived: it may be shown
  int renders_ = 0;     // renders of it with everything in
  bool done_ = false;
};

}  // namespace mostar::ui
