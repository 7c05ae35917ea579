// Capture -> latest-value slot -> compression (JPEG, or H.264) -> delivery, with health and
// reconnection.
//
// Two threads: the capture thread owns the StereoCamera (Open, Grab, Close, reopening it every
// `reopen_period` after a loss or after `max_consecutive_timeouts` timeouts in a row); the
// compression thread takes the newest pair from a LatestValueSlot (older pairs are dropped and
// counted, never queued), encodes both eyes in parallel at the BitrateController's settings and
// calls the delivery callback. The callback runs on the compression thread; it returns whether
// the transport sent the pair or skipped it at the source (ack-clock), which feeds the
// bitrate control. Start(), Stop(), Health() and the setters never block on the camera or the
// network (Stop() waits for the current Grab(), at most `grab_timeout`).
//
// With codec kH264 the compression thread encodes both eyes into two H.264 streams
// (H264StereoEncoder) and hands each StereoVideoFrame to the video delivery callback instead.
// Its target: the configured class x headroom (unlimited: the H.264 options' rate), lowered to
// what the viewers' links carry (VideoRateControl, from their receive reports, OnVideoFeedback);
// a frame that would only queue behind a drop in capacity is skipped at the source.
// Every pair taken from the slot is encoded: the streams are predictive, so a pair the
// transport skips shows as a gap to viewers, who then ask for an IDR (RequestKeyframe, at most
// one IDR per 300 ms: KeyframeRequestLimiter).
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "common/sync/latest_value_slot.h"
#include "common/time/rate_meter.h"
#include "common/time/time.h"
#include "common/types/health.h"
#include "common/types/stereo_frame.h"
#include "robot_server/camera/bitrate_controller.h"
#include "robot_server/camera/h264_stereo_encoder.h"
#include "robot_server/camera/jpeg_compressor.h"
#include "robot_server/camera/keyframe_request_limiter.h"
#include "robot_server/camera/stereo_camera.h"
#include "robot_server/camera/video_rate_control.h"

namespace mostar::camera {

enum class Delivery {
  kSent,     // the transport took the pair
  kSkipped,  // the transport skipped it at the source (previous pair not yet acknowledged)
};

enum class VideoCodec { kJpeg, kH264 };

struct CameraPipelineOptions {
  std::string name = "stereo_camera";  // DeviceHealth name
  Duration grab_timeout = std::chrono::milliseconds(500);
  int max_consecutive_timeouts = 4;  // then the camera is closed and reopened
  Duration reopen_period = std::chrono::seconds(1);
  bool parallel_compression = true;
  BitrateControllerOptions bitrate;
  // Named bitrate targets for SetBitrateClass(), bits/s, 0 = unlimited ("lan", "wan", ...).
  std::map<std::string, double> bitrate_classes = {{"lan", 0}, {"wan", 8e6}};
  VideoCodec codec = VideoCodec::kJpeg;
  H264StreamOptions h264;  // codec kH264
  int frame_rate_hz = 30;  // the camera's nominal rate (H.264 rate control time base)
  // Codec kH264: the rate control from the viewers' reports. Set link.repair_hold to the video
  // writers' repair period (dds.video_repair_period_ms).
  VideoRateControlOptions video_rate;
  bool IsValid(std::string* error) const;
};

class CameraPipeline {
 public:
  using DeliverFn = std::function<Delivery(const CompressedStereoPair&)>;
  using DeliverVideoFn = std::function<Delivery(const StereoVideoFrame&)>;

  // `camera` is owned; `deliver` is called on the compression thread; `clock` (not owned,
  // outlives the pipeline) gives the monotonic time for rates and the bitrate control.
  CameraPipeline(std::unique_ptr<StereoCamera> camera, const CameraPipelineOptions& options,
                 DeliverFn deliver, const Clock* clock = &SystemClock::Instance());
  ~CameraPipeline();  // Stop()
  CameraPipeline(const CameraPipeline&) = delete;
  CameraPipeline& operator=(const CameraPipeline&) = delete;

  // Where H.264 frames go (codec kH264; called on the compression thread). Before Start().
  void SetVideoDelivery(DeliverVideoFn deliver_video) { deliver_video_ = std::move(deliver_video); }
  // With options.video_rate.auto_repair_deadline: how the video writers' repair deadline is
  // changed (called on the compression thread, the one that delivers; returns false with
  // `error` when it could not be). Before Start().
  using RepairDeadlineFn = std::function<bool(Duration deadline, std::string* error)>;
  void SetRepairDeadlineSink(RepairDeadlineFn sink) { repair_deadline_sink_ = std::move(sink); }

  // Starts both threads. The camera need not be present: it is opened (and reopened) by the
  // capture thread, and its absence shows in Health(). Idempotent.
  void Start();
  // Stops both threads and closes the camera. Idempotent; the pipeline cannot be restarted.
  void Stop();

  // Health snapshot (any thread): state, message and counters frames, pairs_delivered,
  // pairs_skipped_at_source, slot_drops, divided (not encoded: frame-rate divisor), timeouts,
  // device_lost, reopen_attempts, open_failures, encode_errors, jpeg_quality,
  // jpeg_scale_percent, frame_rate_divisor, bitrate_bps, target_bitrate_bps; with H.264 also
  // h264_idrs, keyframe_requests, keyframe_requests_deferred, h264_encoder_restarts,
  // link_viewers, link_target_bps, link_queue_ms, skipped_for_link; then the
  // camera's own StereoCamera::Counters(); rate_hz is the delivered pair rate.
  DeviceHealth Health() const;
  BitrateStats bitrate_stats() const;

  // Any thread; applied from the next encoded pair.
  void SetTargetBitsPerSecond(double bits_per_s);
  // Applies a configured class; false (unchanged) when the name is unknown.
  bool SetBitrateClass(const std::string& name);
  // A viewer's receive report (any thread; H.264 only, ignored with JPEG).
  void OnVideoFeedback(const VideoFeedback& feedback);
  // A viewer asked for an IDR (any thread; H.264 only, ignored with JPEG): the next pair is one,
  // at most one per 300 ms (KeyframeRequestLimiter).
  void RequestKeyframe();

 private:
  void CaptureLoop();
  void CompressLoop();
  void EncodeH264Loop();
  // The next pair taken from the slot, after applying a pending target; nullopt when closed.
  std::optional<StereoImagePair> NextPair(BitrateController* controller, double* h264_target);
  // Counts a delivered or skipped pair and takes the controller's statistics; mutex_ held.
  void CountDelivery(Delivery delivery, SteadyTime now, const BitrateController& controller);
  void SetState(DeviceState state, const std::string& message);
  bool WaitForStop(Duration duration);  // true when stopping

  std::unique_ptr<StereoCamera> camera_;
  const CameraPipelineOptions options_;
  const DeliverFn deliver_;
  DeliverVideoFn deliver_video_;
  RepairDeadlineFn repair_deadline_sink_;
  const Clock* clock_;
  LatestValueSlot<StereoImagePair> slot_;

  std::mutex stop_mutex_;
  std::condition_variable stop_cv_;
  bool stopping_ = false;
  bool started_ = false;
  std::thread capture_thread_;
  std::thread compress_thread_;

  mutable std::mutex mutex_;  // guards everything below
  DeviceState state_ = DeviceState::kOff;
  std::string message_ = "not started";
  uint64_t frames_ = 0;
  uint64_t delivered_ = 0;
  uint64_t skipped_ = 0;
  uint64_t divided_ = 0;
  uint64_t timeouts_ = 0;
  uint64_t device_lost_ = 0;
  uint64_t reopen_attempts_ = 0;
  uint64_t open_failures_ = 0;
  uint64_t encode_errors_ = 0;
  int frame_rate_divisor_ = 1;
  double pending_target_bits_per_s_ = -1;  // < 0: no change requested
  BitrateStats bitrate_stats_;
  KeyframeRequestLimiter keyframes_;
  uint64_t h264_idrs_ = 0;
  uint64_t h264_restarts_ = 0;
  uint64_t skipped_for_link_ = 0;
  mutable VideoRateControl rate_control_;  // thread-safe itself (its lock is taken after mutex_)
  std::vector<std::pair<std::string, uint64_t>> camera_counters_;
  mutable RateMeter delivered_rate_;
};

}  // namespace mostar::camera
