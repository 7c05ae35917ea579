// Pairs independently captured left and right frames by nearest capture stamp. Pure logic: no
// threads, no devices, no clock (stamps come with the frames).
//
// Contract: stamps of one eye arrive in non-decreasing order. A left and a right frame form a
// pair when their stamps differ by at most `max_skew`, and neither has a closer partner among
// the frames already received. A frame that can no longer be paired (its partner eye is
// already past it by more than `max_skew`) is dropped and counted; so is the oldest frame when
// one eye runs more than `max_pending` frames ahead (the other eye stalled).
// The pair's stamp is the midpoint of the two frames' stamps.
//
// Drift: the skew (left stamp - right stamp) of matched pairs is fitted against time over the
// last `drift_window_pairs` pairs; the slope (ns of skew per s) tells two free-running cameras
// slide against each other, and `mean_skew` how far they are apart.
// Not thread-safe: one owner.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <string>

#include "common/time/time.h"
#include "robot_server/camera/stereo_camera.h"

namespace mostar::camera {

struct StereoPairerOptions {
  Duration max_skew = std::chrono::milliseconds(10);  // > 0; usually < half a frame period
  size_t max_pending = 4;                             // frames kept per eye, >= 1
  size_t drift_window_pairs = 64;                     // pairs in the drift fit, >= 2
  bool IsValid(std::string* error) const;
};

struct TimedImage {
  Time stamp;
  cv::Mat image;
};

struct StereoPairerStats {
  uint64_t pairs = 0;
  uint64_t dropped_left = 0;   // left frames never paired
  uint64_t dropped_right = 0;  // right frames never paired
  uint64_t dropped_pairs = 0;  // complete pairs replaced before PopPair() (more than max_pending)
  Duration last_skew{0};       // left - right of the last pair
  Duration mean_skew{0};       // mean left - right over the drift window
  double drift_ns_per_s = 0;   // slope of the skew over the drift window; 0 with < 2 pairs
};

class StereoPairer {
 public:
  explicit StereoPairer(const StereoPairerOptions& options = {});

  // Adds one frame. A frame older than the last one of the same eye is dropped and counted.
  void AddLeft(TimedImage frame);
  void AddRight(TimedImage frame);

  // The oldest complete pair, if any (sequence is the pairer's own counter, from 0).
  std::optional<StereoImagePair> PopPair();

  const StereoPairerStats& stats() const { return stats_; }
  // Frames waiting for a partner.
  size_t pending_left() const { return left_.size(); }
  size_t pending_right() const { return right_.size(); }
  // Forgets pending frames (not counted as drops) and the drift history; keeps the counters.
  void Reset();

 private:
  void Add(TimedImage frame, std::deque<TimedImage>* queue, uint64_t* dropped);
  void Match();
  void RecordSkew(Time pair_stamp, Duration skew);

  StereoPairerOptions options_;
  std::deque<TimedImage> left_;
  std::deque<TimedImage> right_;
  std::deque<StereoImagePair> ready_;
  std::deque<std::pair<Time, Duration>> skews_;  // (pair stamp, left - right)
  std::optional<Time> last_left_;
  std::optional<Time> last_right_;
  uint64_t next_sequence_ = 0;
  StereoPairerStats stats_;
};

}  // namespace mostar::camera
