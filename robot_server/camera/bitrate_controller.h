// Adapts the JPEG quality, resolution scale and frame-rate divisor so that the compressed
// stereo stream fits a target bitrate and the link it goes over, instead of queueing.
//
// Inputs: the size of every encoded pair and whether the transport sent it or skipped it at
// the source (ack-clock: a pair is skipped while the previous one is not yet acknowledged),
// with the monotonic time. Targets: a configured bitrate (per subscriber class, e.g. LAN
// unlimited, WAN 8 Mbit/s) and, when the transport skips more than `congested_skip_fraction`
// of the pairs, the bitrate the link actually carried (the ack-clock estimate), probed upward
// again once skips stop.
//
// Control: every `control_interval_pairs` pairs, the offered bitrate (recent pair size x pair
// rate) is compared with `headroom` x target. Quality falls fast (up to 10 steps) and rises
// slowly (up to 3). At minimum quality the controller steps down a ladder: the resolution
// scales in order, then frame-rate divisors 2..max; at maximum quality it steps back up when
// the predicted bitrate one level up fits. Ladder steps are at least `level_hold` apart, and a
// step down needs its condition for half of that.
//
// Limitation: with a long round trip the ack-clock caps the pair rate near 1/RTT whatever the
// size; skips then do not fall with the quality, and the link estimate stops at
// `min_link_bits_per_s`.
// Not thread-safe: the pipeline's compression thread owns it; Stats() copies are for health.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "common/time/time.h"
#include "robot_server/camera/jpeg_compressor.h"

namespace mostar::camera {

struct BitrateControllerOptions {
  double target_bits_per_s = 0;  // 0 = unlimited (LAN)
  int min_quality = 30;          // 1..max_quality
  int max_quality = 90;          // min_quality..100
  int initial_quality = 80;      // min_quality..max_quality
  // Resolution ladder, decreasing, in (0, 1]; DefaultScaleLadder(width) for the camera's width.
  std::vector<double> scales = {1.0, 0.75, 0.5};
  int max_frame_rate_divisor = 4;                 // >= 1; 1 = never reduce the frame rate
  double headroom = 0.9;                          // aim at this fraction of the target, (0, 1]
  int control_interval_pairs = 3;                 // >= 1
  Duration level_hold = std::chrono::seconds(1);  // between ladder steps
  Duration window = std::chrono::seconds(1);      // for rates and the skip fraction
  double congested_skip_fraction = 0.2;           // (0, 1]
  double min_link_bits_per_s = 500e3;             // floor of the ack-clock estimate, > 0
  bool IsValid(std::string* error) const;
};

// The resolution ladder for images `width_px` wide when none is configured: 1, 0.75, then each
// further halving and the 3/4 step before it, down to no less than 320 px wide (so that every
// camera ends its ladder at about 320x240): 640 -> 1, 0.75, 0.5; 1280 (the native 1280x960) ->
// 1, 0.75, 0.5, 0.375, 0.25. At least {1} for any width.
std::vector<double> DefaultScaleLadder(int width_px);

struct EncodeSettings {
  JpegSettings jpeg;
  int frame_rate_divisor = 1;  // encode one captured pair in this many
};

struct BitrateStats {
  double target_bits_per_s = 0;    // configured; 0 = unlimited
  double link_bits_per_s = 0;      // ack-clock estimate; 0 = no congestion seen
  double offered_bits_per_s = 0;   // encoded pairs, sent or not
  double achieved_bits_per_s = 0;  // sent pairs only
  double skipped_fraction = 0;     // of the encoded pairs in the window
  double pair_rate_hz = 0;         // encoded pairs per second
  int quality = 0;
  double scale = 1.0;
  int frame_rate_divisor = 1;
  int level = 0;  // ladder position, 0 = full resolution and rate
};

class BitrateController {
 public:
  explicit BitrateController(const BitrateControllerOptions& options = {});

  // Changes the configured target (0 = unlimited); the link estimate is kept.
  void SetTargetBitsPerSecond(double bits_per_s);
  // One encoded pair of `bytes` (both eyes) at the settings Current() gave, `sent` or skipped
  // at the source by the transport. `now` is monotonic and non-decreasing.
  void OnPairEncoded(SteadyTime now, size_t bytes, bool sent);

  EncodeSettings Current() const;
  BitrateStats Stats() const;

 private:
  struct Sample {
    SteadyTime time;
    size_t bytes;
    bool sent;
  };
  void Control(SteadyTime now);
  int LevelCount() const;
  double LevelScale(int level) const;
  int LevelDivisor(int level) const;
  double EffectiveTarget() const;  // 0 = unlimited

  BitrateControllerOptions options_;
  std::deque<Sample> window_;
  int quality_;
  int level_ = 0;
  int pairs_since_control_ = 0;
  SteadyTime last_level_change_;
  bool has_level_change_ = false;
  double link_bits_per_s_ = 0;            // 0 = no estimate (no congestion seen)
  double mean_pair_bytes_ = 0;            // EWMA of encoded pair sizes; 0 = none yet
  std::optional<SteadyTime> down_since_;  // since when a step down is wanted
  BitrateStats stats_;
};

}  // namespace mostar::camera
