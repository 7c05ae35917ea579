// Pairs the two eyes' JPEG images by capture stamp and decodes them on a worker thread.
//
// Push() is called from DDS threads and never blocks for long: the newest complete pair
// replaces an undecoded one (counted as dropped). Latest() gives the most recent decoded pair to
// the render loop without waiting. A broken JPEG is counted and dropped with its pair; nothing
// else is lost. Pairs are shown in capture order: a pair completed after a newer one (the robot
// keeps several pairs in flight) is dropped and counted. Thread-safe.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <thread>

#include "common/time/rate_meter.h"
#include "common/time/time.h"
#include "common/types/stereo_frame.h"

namespace mostar::client {

struct DecodedStereoPair {
  uint64_t sequence = 0;  // decoded pair counter of this receiver
  Time stamp;             // capture stamp shared by both eyes
  SteadyTime received;    // when the pair became complete here (monotonic)
  cv::Mat left;           // BGR8
  cv::Mat right;          // BGR8; may be empty when the robot sends one eye only
  size_t compressed_bytes = 0;
};

struct ReceiverStats {
  uint64_t images = 0;  // JPEG images received (both eyes)
  uint64_t pairs_decoded = 0;
  uint64_t pairs_dropped = 0;     // replaced before decoding (render/decoder slower than input)
  uint64_t unpaired_dropped = 0;  // an eye whose partner never came
  uint64_t late_dropped = 0;      // a pair completed after a newer one (several writers in flight)
  uint64_t broken_images = 0;     // undecodable JPEG data
  uint64_t bytes = 0;             // compressed bytes received
  double pair_rate_hz = 0;
  double bitrate_bps = 0;
};

class StereoReceiver {
 public:
  explicit StereoReceiver(const Clock* clock = &SystemClock::Instance());
  ~StereoReceiver();
  StereoReceiver(const StereoReceiver&) = delete;
  StereoReceiver& operator=(const StereoReceiver&) = delete;

  void Push(Eye eye, const CompressedImage& image);
  // The newest decoded pair, if any (shares pixel memory; treat as read-only).
  std::optional<DecodedStereoPair> Latest() const;
  ReceiverStats Stats() const;

 private:
  void DecodeLoop();

  const Clock* clock_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  bool stop_ = false;
  std::map<int64_t, CompressedImage> pending_left_;  // by stamp (ns), waiting for the partner
  std::map<int64_t, CompressedImage> pending_right_;
  int64_t newest_pair_ns_ = 0;  // capture stamp of the newest pair completed so far
  std::optional<CompressedStereoPair> to_decode_;
  SteadyTime to_decode_received_;
  std::optional<DecodedStereoPair> latest_;
  ReceiverStats stats_;
  RateMeter pair_rate_;
  std::map<SteadyTime, size_t> bytes_window_;
  std::thread thread_;
};

}  // namespace mostar::client
