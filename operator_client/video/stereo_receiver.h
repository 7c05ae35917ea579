// Pairs the two eyes' JPEG images by capture stamp and decodes them on a worker thread.
//
// Push() is called from DDS threads and never blocks for long: the newest complete pair
// replaces an undecoded one (counted as dropped). Latest() gives the most recent decoded pair to
// the render loop without waiting. Every image's JPEG header is read first: one that declares
// more pixels than its eye may have (the robot's CameraInfo size once known, else
// max_width_px x max_height_px) is refused and counted before anything is decoded. A broken
// JPEG is counted and dropped with its pair; nothing else is lost. Pairs are shown in capture
// order and a pair stamped in the future is refused (PairStampGate): a pair completed after a
// newer one (the robot keeps several pairs in flight) is dropped and counted. The decoder
// decodes only the eyes its DecodeTarget asks for, at the smallest DCT scale (1, 1/2, 1/4,
// 1/8) that still covers the target size, the same scale for both eyes.
//
// H.264 (PushVideo): every frame of the two streams is decoded, in order (they are predictive),
// both eyes whatever the DecodeTarget, at full size. In both formats the two eyes of a pair are
// decoded at the same time, the right one on a helper thread. A gap in the AU numbers, an
// undecodable AU or a picture with errors is never shown: Latest() keeps the last good pair while
// the receiver waits for an IDR (ReceiverStats::waiting_for_keyframe: the picture is stale), and
// asks the robot for one through the keyframe request callback, again every 200 ms until one
// comes (libwebrtc's kMaxWaitForKeyFrame). Frames the decoder cannot keep up with (more than
// kMaxQueuedVideoFrames waiting) are dropped together, counted, and an IDR is asked for.
// Thread-safe.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "common/sync/helper_thread.h"
#include "common/sync/wake_signal.h"
#include "common/time/rate_meter.h"
#include "common/time/time.h"
#include "common/timesync/clock_offset_estimator.h"
#include "common/types/stereo_frame.h"
#include "operator_client/video/arrival_report.h"
#include "operator_client/video/pair_stamp_gate.h"

namespace mostar::h264 {
class Decoder;
}  // namespace mostar::h264

namespace mostar::client {

struct DecodedStereoPair {
  uint64_t sequence = 0;      // decoded pair counter of this receiver
  Time stamp;                 // capture stamp shared by both eyes
  SteadyTime received;        // when the pair became complete here (monotonic)
  SteadyTime decode_started;  // when the decoder thread took it (monotonic): queued before
  SteadyTime decoded;         // when both eyes were decoded (monotonic)
  cv::Mat left;               // BGR8; empty when not asked for (DecodeTarget)
  cv::Mat right;              // BGR8; empty when not asked for, or when the robot sends one eye
  // The images are decoded at 1/scale_denominator (1, 2, 4 or 8) of the size sent, which is
  // source_width_px x source_height_px (the left eye's; both eyes have the same size). An
  // image pixel u maps to a sent pixel (u + 0.5) * scale - 0.5 (libjpeg's scaled size is
  // ceil(size / scale), exact when the size is a multiple of the scale).
  int scale_denominator = 1;
  int source_width_px = 0;
  int source_height_px = 0;
  size_t compressed_bytes = 0;
};

// What the decoder produces: which eyes, and the size they are shown at (an eye's viewport in
// the window, in framebuffer pixels), to which the decode scales down. width_px or height_px
// <= 0: full size.
struct DecodeTarget {
  bool left = true;
  bool right = true;
  int width_px = 0;
  int height_px = 0;
  bool operator==(const DecodeTarget& o) const {
    return left == o.left && right == o.right && width_px == o.width_px && height_px == o.height_px;
  }
};

struct ReceiverStats {
  uint64_t images = 0;  // JPEG images received (both eyes)
  uint64_t pairs_decoded = 0;
  uint64_t pairs_dropped = 0;     // replaced before decoding (render/decoder slower than input)
  uint64_t unpaired_dropped = 0;  // an eye whose partner never came
  uint64_t late_dropped = 0;      // a pair completed after a newer one (several writers in flight)
  uint64_t broken_images = 0;     // undecodable JPEG data (header or image)
  uint64_t oversized_images = 0;  // a header declaring more pixels than expected: not decoded
  uint64_t future_dropped = 0;    // a pair stamped in the future (PairStampGate)
  uint64_t stamp_resyncs = 0;     // the capture order restarted (PairStampGate)
  uint64_t bytes = 0;             // compressed bytes received
  uint64_t left_decodes = 0;      // JPEG decodes run for each eye (broken ones included)
  uint64_t right_decodes = 0;
  uint64_t scaled_decodes = 0;  // of those, decoded at a DCT scale below 1
  double pair_rate_hz = 0;
  double bitrate_bps = 0;
  // H.264 only.
  uint64_t video_frames = 0;          // StereoVideoFrames received
  uint64_t video_gaps = 0;            // jumps in the AU numbers (lost frames upstream)
  uint64_t video_errors = 0;          // undecodable AUs or pictures with errors
  uint64_t video_skipped = 0;         // frames not shown while waiting for an IDR
  uint64_t video_queue_dropped = 0;   // frames dropped because the decoder fell behind
  uint64_t keyframe_requests = 0;     // requests sent to the robot
  bool waiting_for_keyframe = false;  // the shown pair is stale until the next IDR
};

struct StereoReceiverOptions {
  // The largest image accepted before the robot's CameraInfo gives the eye's size. unit: px.
  int max_width_px = 4096;
  int max_height_px = 4096;
  PairStampGateOptions stamps;
};

class StereoReceiver {
 public:
  explicit StereoReceiver(const Clock* clock = &SystemClock::Instance(),
                          const StereoReceiverOptions& options = {});
  ~StereoReceiver();
  StereoReceiver(const StereoReceiver&) = delete;
  StereoReceiver& operator=(const StereoReceiver&) = delete;

  void Push(Eye eye, const CompressedImage& image);
  // Both eyes of one capture as H.264 access units (format "h264"; others are refused).
  void PushVideo(const StereoVideoFrame& frame);
  // How the receiver asks the robot for an IDR: called on the decoder thread, without the
  // receiver's lock, with the last AU number decoded and a reason ("join", "gap", "error",
  // "overrun"). When SetKeyframeRequester returns, no call of the previous function is running
  // or will start (set nullptr before what it uses goes away).
  using KeyframeRequestFn = std::function<void(uint64_t last_sequence, const std::string& reason)>;
  void SetKeyframeRequester(KeyframeRequestFn request);
  // How the receiver reports arrivals to the robot's rate control: every kFeedbackPeriod while
  // frames arrive (or when VideoFeedback::kMaxArrivals are pending), on the decoder thread,
  // under the same rule as the keyframe requester (set nullptr before what it uses goes away).
  using FeedbackFn = std::function<void(const std::vector<VideoFrameArrival>& arrivals)>;
  void SetFeedbackSender(FeedbackFn send);
  static constexpr Duration kFeedbackPeriod = std::chrono::milliseconds(50);
  static constexpr size_t kMaxQueuedVideoFrames = 30;
  static constexpr Duration kKeyframeReaskPeriod = std::chrono::milliseconds(200);
  // The size of one eye's images from the robot's CameraInfo; images that declare more are
  // refused. Zero or negative: unknown (the fixed limit applies).
  void SetExpectedSize(Eye eye, int width_px, int height_px);
  // Which eyes to decode and the size they are shown at; applies from the next pair decoded.
  void SetDecodeTarget(const DecodeTarget& target);
  // The robot's clock minus this machine's, for judging stamps from the future.
  void SetClockOffset(const timesync::ClockOffsetEstimate& robot_minus_local);
  // Notified each time a new decoded pair is there (Latest() changed), on the decoder thread:
  // the render loop sleeps on it. Not owned; must outlive the receiver or be reset to nullptr.
  void SetWakeSignal(WakeSignal* signal);
  // The newest decoded pair, if any (shares pixel memory; treat as read-only).
  std::optional<DecodedStereoPair> Latest() const;
  ReceiverStats Stats() const;

 private:
  void DecodeLoop();
  // Decodes one H.264 frame (decoder thread, lock not held); returns the pair when both eyes
  // gave a picture. `reason` is set when an IDR must be asked for.
  std::optional<DecodedStereoPair> DecodeVideo(const StereoVideoFrame& frame, std::string* reason);

  const Clock* clock_;
  const StereoReceiverOptions options_;
  mutable std::mutex mutex_;
  int expected_width_px_[2] = {0, 0};  // by Eye; 0 = unknown
  int expected_height_px_[2] = {0, 0};
  PairStampGate gate_;
  DecodeTarget target_;
  std::condition_variable cv_;
  bool stop_ = false;
  std::map<int64_t, CompressedImage> pending_left_;  // by stamp (ns), waiting for the partner
  std::map<int64_t, CompressedImage> pending_right_;
  std::optional<CompressedStereoPair> to_decode_;
  SteadyTime to_decode_received_;
  std::deque<std::pair<StereoVideoFrame, SteadyTime>> video_queue_;  // with arrival times
  bool video_overrun_ = false;  // frames were dropped from the queue: ask for an IDR
  std::mutex request_mutex_;    // held while keyframe_request_ or feedback_ is set or called
  KeyframeRequestFn keyframe_request_;
  FeedbackFn feedback_;
  ArrivalReport arrivals_{kFeedbackPeriod};  // mutex_
  std::optional<DecodedStereoPair> latest_;
  WakeSignal* wake_ = nullptr;  // mutex_
  ReceiverStats stats_;
  RateMeter pair_rate_;
  std::map<SteadyTime, size_t> bytes_window_;
  // Decoder thread only.
  std::unique_ptr<h264::Decoder> left_video_decoder_;
  std::unique_ptr<h264::Decoder> right_video_decoder_;
  uint64_t last_video_sequence_ = 0;             // last AU decoded into a picture
  std::optional<SteadyTime> last_keyframe_ask_;  // when an IDR was last asked for
  HelperThread right_eye_;                       // decodes the right eye beside the left
  std::thread thread_;
};

}  // namespace mostar::client
