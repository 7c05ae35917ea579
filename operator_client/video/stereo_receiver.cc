#include "operator_client/video/stereo_receiver.h"

#include <algorithm>
#include <cstdint>

#include "common/h264/h264_decoder.h"
#include "common/jpeg/jpeg_decoder.h"
#include "common/log/log.h"
#include "operator_client/video/jpeg_header.h"

namespace mostar::client {

namespace {
constexpr size_t kMaxPending = 8;  // per eye; older unpaired images are dropped
}  // namespace

StereoReceiver::StereoReceiver(const Clock* clock, const StereoReceiverOptions& options)
    : clock_(clock), options_(options), gate_(options.stamps) {
  thread_ = std::thread([this] { DecodeLoop(); });
}

StereoReceiver::~StereoReceiver() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

void StereoReceiver::SetExpectedSize(Eye eye, int width_px, int height_px) {
  std::lock_guard<std::mutex> lock(mutex_);
  const int e = eye == Eye::kLeft ? 0 : 1;
  expected_width_px_[e] = std::max(width_px, 0);
  expected_height_px_[e] = std::max(height_px, 0);
}

void StereoReceiver::SetDecodeTarget(const DecodeTarget& target) {
  std::lock_guard<std::mutex> lock(mutex_);
  target_ = target;
}

void StereoReceiver::SetWakeSignal(WakeSignal* signal) {
  std::lock_guard<std::mutex> lock(mutex_);
  wake_ = signal;
}

void StereoReceiver::SetClockOffset(const timesync::ClockOffsetEstimate& robot_minus_local) {
  std::lock_guard<std::mutex> lock(mutex_);
  gate_.SetClockOffset(robot_minus_local);
}

void StereoReceiver::Push(Eye eye, const CompressedImage& image) {
  // The header is read before the lock: it costs microseconds and touches only `image`.
  JpegHeader header;
  std::string header_error;
  const bool header_ok =
      ReadJpegHeader(image.data.data(), image.data.size(), &header, &header_error);
  std::lock_guard<std::mutex> lock(mutex_);
  ++stats_.images;
  stats_.bytes += image.data.size();
  const SteadyTime now = clock_->SteadyNow();
  bytes_window_[now] += image.data.size();
  while (!bytes_window_.empty() && now - bytes_window_.begin()->first > std::chrono::seconds(2)) {
    bytes_window_.erase(bytes_window_.begin());
  }
  if (!header_ok) {
    ++stats_.broken_images;
    MOSTAR_LOG_EVERY_SEC(WARNING, 5)
        << "unreadable JPEG header (" << header_error << "): " << EyeName(eye) << " image dropped";
    return;
  }
  const int e = eye == Eye::kLeft ? 0 : 1;
  const bool known = expected_width_px_[e] > 0 && expected_height_px_[e] > 0;
  std::string why;
  if (!FitsExpectedSize(header, known ? expected_width_px_[e] : options_.max_width_px,
                        known ? expected_height_px_[e] : options_.max_height_px, &why)) {
    ++stats_.oversized_images;
    MOSTAR_LOG_EVERY_SEC(WARNING, 5) << EyeName(eye) << " image " << why
                                     << (known ? " (camera info)" : " (limit)") << ": not decoded";
    return;
  }
  const int64_t key = ToUnixNanos(image.stamp);
  auto& mine = eye == Eye::kLeft ? pending_left_ : pending_right_;
  auto& other = eye == Eye::kLeft ? pending_right_ : pending_left_;
  auto partner = other.find(key);
  if (partner == other.end()) {
    mine[key] = image;
    while (mine.size() > kMaxPending) {
      mine.erase(mine.begin());
      ++stats_.unpaired_dropped;
    }
    return;
  }
  const PairVerdict verdict = gate_.Check(image.stamp, clock_->Now(), now);
  if (verdict == PairVerdict::kFuture || verdict == PairVerdict::kLate) {
    other.erase(partner);
    if (verdict == PairVerdict::kLate) ++stats_.late_dropped;
    if (verdict == PairVerdict::kFuture) {
      ++stats_.future_dropped;
      MOSTAR_LOG_EVERY_SEC(WARNING, 5)
          << "stereo pair stamped " << ToIso8601(image.stamp) << " is in the future: dropped";
    }
    return;
  }
  if (verdict == PairVerdict::kResync) {
    ++stats_.stamp_resyncs;
    MOSTAR_LOG_EVERY_SEC(WARNING, 5)
        << "stereo pair order restarted at the pair stamped " << ToIso8601(image.stamp);
  }
  CompressedStereoPair pair;
  pair.left = eye == Eye::kLeft ? image : partner->second;
  pair.right = eye == Eye::kLeft ? partner->second : image;
  // Everything older than this pair will never be shown: drop it.
  for (auto* pending : {&pending_left_, &pending_right_}) {
    while (!pending->empty() && pending->begin()->first <= key) {
      if (pending->begin()->first != key) ++stats_.unpaired_dropped;
      pending->erase(pending->begin());
    }
  }
  if (to_decode_) ++stats_.pairs_dropped;
  to_decode_ = std::move(pair);
  to_decode_received_ = now;
  cv_.notify_one();
}

void StereoReceiver::SetKeyframeRequester(KeyframeRequestFn request) {
  std::lock_guard<std::mutex> lock(request_mutex_);
  keyframe_request_ = std::move(request);
}

void StereoReceiver::SetFeedbackSender(FeedbackFn send) {
  std::lock_guard<std::mutex> lock(request_mutex_);
  feedback_ = std::move(send);
}

void StereoReceiver::PushVideo(const StereoVideoFrame& frame) {
  std::lock_guard<std::mutex> lock(mutex_);
  const size_t bytes = frame.left.size() + frame.right.size();
  // Arrival on this machine's monotonic clock, before any check: the robot's rate control
  // judges the link, whatever becomes of the frame here.
  arrivals_.Add(frame.sequence, clock_->SteadyNow(), bytes);
  ++stats_.video_frames;
  stats_.images += 2;
  stats_.bytes += bytes;
  const SteadyTime now = clock_->SteadyNow();
  bytes_window_[now] += bytes;
  while (!bytes_window_.empty() && now - bytes_window_.begin()->first > std::chrono::seconds(2)) {
    bytes_window_.erase(bytes_window_.begin());
  }
  if (frame.format != "h264") {
    ++stats_.broken_images;
    MOSTAR_LOG_EVERY_SEC(WARNING, 5)
        << "video frame of format '" << frame.format << "' (not h264): dropped";
    return;
  }
  const PairVerdict verdict = gate_.Check(frame.stamp, clock_->Now(), now);
  if (verdict == PairVerdict::kFuture) {
    // Not decoded: the next frame shows as a gap and an IDR is asked for.
    ++stats_.future_dropped;
    MOSTAR_LOG_EVERY_SEC(WARNING, 5)
        << "video frame stamped " << ToIso8601(frame.stamp) << " is in the future: dropped";
    return;
  }
  if (verdict == PairVerdict::kResync) ++stats_.stamp_resyncs;
  if (video_queue_.size() >= kMaxQueuedVideoFrames) {
    stats_.video_queue_dropped += video_queue_.size();
    video_queue_.clear();
    video_overrun_ = true;
    MOSTAR_LOG_EVERY_SEC(WARNING, 5) << "video decoding fell " << kMaxQueuedVideoFrames
                                     << " frames behind: frames dropped, waiting for an IDR";
  }
  video_queue_.emplace_back(frame, now);
  cv_.notify_one();
}

std::optional<DecodedStereoPair> StereoReceiver::DecodeVideo(const StereoVideoFrame& frame,
                                                             std::string* reason) {
  std::string error;
  if (!left_video_decoder_) left_video_decoder_ = h264::Decoder::Create(&error);
  if (!right_video_decoder_) right_video_decoder_ = h264::Decoder::Create(&error);
  if (!left_video_decoder_ || !right_video_decoder_) {
    MOSTAR_LOG_EVERY_SEC(ERROR, 10) << "no H.264 decoder: " << error;
    return std::nullopt;
  }
  const uint64_t gaps_before =
      left_video_decoder_->counters().gaps + right_video_decoder_->counters().gaps;
  const uint64_t errors_before =
      left_video_decoder_->counters().errors + right_video_decoder_->counters().errors;
  DecodedStereoPair decoded;
  std::string left_error;
  std::string right_error;
  h264::DecodeStatus right = h264::DecodeStatus::kError;
  right_eye_.Run([&] {
    right = right_video_decoder_->Decode(frame.right.data(), frame.right.size(), frame.sequence,
                                         &decoded.right, &right_error);
  });
  const h264::DecodeStatus left = left_video_decoder_->Decode(
      frame.left.data(), frame.left.size(), frame.sequence, &decoded.left, &left_error);
  right_eye_.Wait();
  const uint64_t gaps =
      left_video_decoder_->counters().gaps + right_video_decoder_->counters().gaps - gaps_before;
  const uint64_t errors = left_video_decoder_->counters().errors +
                          right_video_decoder_->counters().errors - errors_before;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.video_gaps += gaps > 0 ? 1 : 0;
    stats_.video_errors += errors;
    ++stats_.left_decodes;
    ++stats_.right_decodes;
  }
  if (errors > 0) {
    MOSTAR_LOG_EVERY_SEC(WARNING, 5)
        << "undecodable H.264 frame " << frame.sequence << " ("
        << (left_error.empty() ? right_error : left_error) << "): waiting for an IDR";
  }
  if (left == h264::DecodeStatus::kPicture && right == h264::DecodeStatus::kPicture) {
    last_video_sequence_ = frame.sequence;
    decoded.stamp = frame.stamp;
    decoded.source_width_px = decoded.left.cols;
    decoded.source_height_px = decoded.left.rows;
    decoded.scale_denominator = 1;
    decoded.compressed_bytes = frame.left.size() + frame.right.size();
    return decoded;
  }
  // One eye without a picture: the other's is not shown either (a stereo pair or nothing).
  if (left == h264::DecodeStatus::kPicture) left_video_decoder_->RequireIdr();
  if (right == h264::DecodeStatus::kPicture) right_video_decoder_->RequireIdr();
  *reason = errors > 0 ? "error" : gaps > 0 ? "gap" : last_video_sequence_ == 0 ? "join" : "gap";
  return std::nullopt;
}

void StereoReceiver::DecodeLoop() {
  JpegDecoder decoder;        // the left eye, on this thread
  JpegDecoder right_decoder;  // the right eye, on right_eye_
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    cv_.wait(lock, [this] { return stop_ || to_decode_.has_value() || !video_queue_.empty(); });
    if (stop_) return;
    if (!video_queue_.empty()) {
      StereoVideoFrame frame = std::move(video_queue_.front().first);
      const SteadyTime received = video_queue_.front().second;
      video_queue_.pop_front();
      std::string reason;
      if (video_overrun_) {
        // The frames dropped from the queue leave a gap: the decoders notice it themselves.
        video_overrun_ = false;
        reason = "overrun";
      }
      lock.unlock();
      const SteadyTime decode_started = clock_->SteadyNow();
      std::optional<DecodedStereoPair> decoded = DecodeVideo(frame, &reason);
      const SteadyTime now = clock_->SteadyNow();
      const bool waiting = left_video_decoder_ && right_video_decoder_ &&
                           (left_video_decoder_->NeedsIdr() || right_video_decoder_->NeedsIdr());
      bool ask = false;
      if (waiting && (!last_keyframe_ask_ || now - *last_keyframe_ask_ >= kKeyframeReaskPeriod)) {
        ask = true;
        last_keyframe_ask_ = now;
        if (reason.empty()) reason = "gap";
      }
      if (!waiting) last_keyframe_ask_.reset();
      lock.lock();
      stats_.waiting_for_keyframe = waiting;
      if (decoded) {
        decoded->received = received;
        decoded->decode_started = decode_started;
        decoded->decoded = now;
        decoded->sequence = ++stats_.pairs_decoded;
        pair_rate_.Tick(now);
        latest_ = std::move(*decoded);
        if (wake_) wake_->Notify();
      } else {
        ++stats_.video_skipped;
      }
      const std::vector<VideoFrameArrival> report = arrivals_.TakeDue(now);
      if (!report.empty()) {
        lock.unlock();
        {
          std::lock_guard<std::mutex> request_lock(request_mutex_);
          if (feedback_) feedback_(report);
        }
        lock.lock();
      }
      if (ask) {
        lock.unlock();
        bool sent = false;
        {
          std::lock_guard<std::mutex> request_lock(request_mutex_);
          if (keyframe_request_) {
            keyframe_request_(last_video_sequence_, reason);
            sent = true;
          }
        }
        lock.lock();
        if (sent) ++stats_.keyframe_requests;
      }
      continue;
    }
    CompressedStereoPair pair = std::move(*to_decode_);
    const SteadyTime received = to_decode_received_;
    const DecodeTarget target = target_;
    to_decode_.reset();
    lock.unlock();
    DecodedStereoPair decoded;
    decoded.stamp = pair.left.stamp;
    decoded.received = received;
    decoded.decode_started = clock_->SteadyNow();
    decoded.compressed_bytes = pair.left.data.size() + pair.right.data.size();
    // Push() read both headers: these reads succeed unless the data is broken.
    JpegHeader header;
    bool broken = !ReadJpegHeader(pair.left.data.data(), pair.left.data.size(), &header, nullptr);
    if (!broken) {
      decoded.source_width_px = header.width_px;
      decoded.source_height_px = header.height_px;
      decoded.scale_denominator = DecodeScaleDenominator(header.width_px, header.height_px,
                                                         target.width_px, target.height_px);
    }
    int decodes[2] = {0, 0};
    std::string why[2];
    bool eye_broken[2] = {false, false};
    // The right eye on the helper thread while this one decodes the left: both at once.
    const auto decode_eye = [&](int e, JpegDecoder* eye_decoder) {
      const CompressedImage& image = e == 0 ? pair.left : pair.right;
      if (!(e == 0 ? target.left : target.right) || image.data.empty()) return;
      ++decodes[e];
      eye_broken[e] =
          !eye_decoder->Decode(image.data.data(), image.data.size(), decoded.scale_denominator,
                               e == 0 ? &decoded.left : &decoded.right, &why[e]);
    };
    if (!broken) {
      right_eye_.Run([&] { decode_eye(1, &right_decoder); });
      decode_eye(0, &decoder);
      right_eye_.Wait();
      broken = eye_broken[0] || eye_broken[1];
    }
    decoded.decoded = clock_->SteadyNow();
    lock.lock();
    stats_.left_decodes += static_cast<uint64_t>(decodes[0]);
    stats_.right_decodes += static_cast<uint64_t>(decodes[1]);
    if (decoded.scale_denominator > 1) {
      stats_.scaled_decodes += static_cast<uint64_t>(decodes[0] + decodes[1]);
    }
    if (broken) {
      ++stats_.broken_images;
      MOSTAR_LOG_EVERY_SEC(WARNING, 5)
          << "undecodable JPEG (" << (eye_broken[0] ? why[0] : why[1]) << ") in the pair stamped "
          << ToIso8601(pair.left.stamp) << ": pair dropped";
      continue;
    }
    decoded.sequence = ++stats_.pairs_decoded;
    pair_rate_.Tick(clock_->SteadyNow());
    latest_ = std::move(decoded);
    if (wake_) wake_->Notify();
  }
}

std::optional<DecodedStereoPair> StereoReceiver::Latest() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return latest_;
}

ReceiverStats StereoReceiver::Stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  ReceiverStats stats = stats_;
  const SteadyTime now = clock_->SteadyNow();
  stats.pair_rate_hz = const_cast<RateMeter&>(pair_rate_).RateHz(now);
  size_t bytes = 0;
  for (const auto& [t, b] : bytes_window_) {
    if (now - t <= std::chrono::seconds(2)) bytes += b;
  }
  stats.bitrate_bps = static_cast<double>(bytes) * 8.0 / 2.0;
  return stats;
}

}  // namespace mostar::client
