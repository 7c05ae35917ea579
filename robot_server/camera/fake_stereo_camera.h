// A scripted StereoCamera for unit tests and benchmarks.
//
// Synthetic pairs cycle through 16 precomputed images (cheap to deliver in benchmarks).
// Grab() plays a script of events (a pair, a timeout, a device loss); when the script is empty
// it either synthesises pairs (`free_run`, paced at `frame_rate_hz` in real time when
// `paced`) or waits up to the timeout for the test to script more. Open() fails while
// `SetOpenFailures()` has failures left or the device is "unplugged".
//
// Threading: the StereoCamera methods are called by one capture thread; the scripting methods
// (Queue*, SetOpenFailures, Unplug, Replug, counters) may be called from any thread.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "common/time/time.h"
#include "robot_server/camera/stereo_camera.h"

namespace mostar::camera {

// A BGR image with gradients, shapes and text that moves with `sequence`, so that its JPEG
// size depends on the quality like a camera image does. Deterministic.
cv::Mat MakeSyntheticImage(int width_px, int height_px, uint64_t sequence, bool right_eye);

class FakeStereoCamera final : public StereoCamera {
 public:
  struct Options {
    int width_px = 640;
    int height_px = 480;
    double frame_rate_hz = 30;
    bool free_run = false;                          // synthesise pairs when the script is empty
    bool paced = false;                             // free_run pairs at frame_rate_hz in real time
    const Clock* clock = &SystemClock::Instance();  // stamps pairs; not owned
  };

  explicit FakeStereoCamera(const Options& options);
  FakeStereoCamera() : FakeStereoCamera(Options()) {}

  // Script (thread-safe).
  void QueuePairs(int count);            // synthetic pairs, stamped at Grab() time
  void QueuePair(StereoImagePair pair);  // exactly this pair (sequence/stamp kept)
  void QueueTimeout();                   // one Grab() returns kTimeout at once
  void QueueDeviceLost();                // one Grab() returns kDeviceLost and closes
  void QueueEndOfStream();
  void SetOpenFailures(int count);  // the next `count` Open() calls fail
  void Unplug();                    // Grab() reports loss; Open() fails until Replug()
  void Replug();

  int open_calls() const;
  int close_calls() const;
  uint64_t pairs_delivered() const;

  // StereoCamera (capture thread).
  bool Open(std::string* error) override;
  GrabResult Grab(Duration timeout, StereoImagePair* pair) override;
  void Close() override;
  bool IsOpen() const override;
  StereoCameraInfo Info() const override;
  // fake_pairs_delivered.
  std::vector<std::pair<std::string, uint64_t>> Counters() const override;

 private:
  enum class EventKind { kSynthetic, kPair, kTimeout, kDeviceLost, kEndOfStream };
  struct Event {
    EventKind kind;
    StereoImagePair pair;
  };
  StereoImagePair Synthesize();

  const Options options_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Event> script_;
  bool open_ = false;
  bool unplugged_ = false;
  int open_failures_ = 0;
  int open_calls_ = 0;
  int close_calls_ = 0;
  uint64_t next_sequence_ = 0;
  uint64_t delivered_ = 0;
  SteadyTime next_paced_;
  std::vector<std::pair<cv::Mat, cv::Mat>> cache_;  // synthetic images, by sequence % size
};

}  // namespace mostar::camera
