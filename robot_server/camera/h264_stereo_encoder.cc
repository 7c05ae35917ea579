#include "robot_server/camera/h264_stereo_encoder.h"

#include <algorithm>
#include <cmath>

#include "common/sync/thread_priority.h"
#include "robot_server/camera/camera_pipeline.h"

namespace mostar::camera {

bool H264StreamOptions::IsValid(std::string* error) const {
  h264::EncoderSettings settings;
  settings.preset = preset;
  settings.keyint_frames = keyint_frames;
  settings.intra_refresh = intra_refresh;
  settings.vbv_frames = vbv_frames;
  settings.threads = threads_per_eye;
  if (!settings.IsValid(error)) return false;
  if (!(unlimited_bits_per_s >= 100e3)) {
    *error = "the unlimited bitrate must be at least 100 kbit/s";
    return false;
  }
  return true;
}

H264StereoEncoder::H264StereoEncoder(const H264StreamOptions& options, int frame_rate_hz,
                                     bool parallel)
    : options_(options), frame_rate_hz_(std::clamp(frame_rate_hz, 1, 120)), parallel_(parallel) {
  if (parallel_) {
    worker_ = std::thread([this] {
      LowerCurrentThreadPriority();
      WorkerLoop();
    });
  }
}

H264StereoEncoder::~H264StereoEncoder() {
  if (worker_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    cv_.notify_all();
    worker_.join();
  }
}

void H264StereoEncoder::WorkerLoop() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    cv_.wait(lock, [this] { return stop_ || job_; });
    if (stop_) return;
    std::function<void()> job = std::move(job_);
    job_ = nullptr;
    lock.unlock();
    job();
    lock.lock();
    job_done_ = true;
    cv_.notify_all();
  }
}

bool H264StereoEncoder::EnsureEncoders(int width_px, int height_px, int eye_bits_per_s,
                                       std::string* error) {
  if (left_ && right_ && left_->settings().width_px == width_px &&
      left_->settings().height_px == height_px) {
    return true;
  }
  h264::EncoderSettings settings;
  settings.width_px = width_px;
  settings.height_px = height_px;
  settings.frame_rate_hz = frame_rate_hz_;
  settings.bitrate_bps = eye_bits_per_s;
  settings.vbv_frames = options_.vbv_frames;
  settings.keyint_frames = options_.keyint_frames;
  settings.intra_refresh = options_.intra_refresh;
  settings.preset = options_.preset;
  settings.threads = options_.threads_per_eye;
  left_ = h264::Encoder::Create(settings, error);
  right_ = left_ ? h264::Encoder::Create(settings, error) : nullptr;
  if (!left_ || !right_) {
    left_.reset();
    right_.reset();
    return false;
  }
  ++restarts_;
  eye_bitrate_bps_ = eye_bits_per_s;
  return true;
}

bool H264StereoEncoder::Encode(const StereoImagePair& pair, double bits_per_s,
                               StereoVideoFrame* out, std::string* error) {
  const uint64_t sequence = next_sequence_++;
  if (pair.left.size() != pair.right.size() || pair.left.empty()) {
    *error = "h264: both eyes must have the same non-empty size";
    force_idr_ = true;
    return false;
  }
  const double both = bits_per_s > 0 ? bits_per_s : options_.unlimited_bits_per_s;
  const int eye_bits_per_s =
      static_cast<int>(std::clamp(std::lround(both / 2), 50'000L, 1'000'000'000L));
  if (!EnsureEncoders(pair.left.cols, pair.left.rows, eye_bits_per_s, error)) {
    *error = "h264: " + *error;
    return false;
  }
  if (eye_bits_per_s != eye_bitrate_bps_) {
    left_->SetBitrate(eye_bits_per_s);
    right_->SetBitrate(eye_bits_per_s);
    eye_bitrate_bps_ = eye_bits_per_s;
  }
  if (force_idr_) {
    left_->ForceIdr();
    right_->ForceIdr();
    force_idr_ = false;
  }
  h264::EncodedFrame left_au;
  h264::EncodedFrame right_au;
  std::string left_error;
  std::string right_error;
  bool left_ok = false;
  if (parallel_) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      job_done_ = false;
      job_ = [&] { left_ok = left_->Encode(pair.left, &left_au, &left_error); };
    }
    cv_.notify_all();
  } else {
    left_ok = left_->Encode(pair.left, &left_au, &left_error);
  }
  const bool right_ok = right_->Encode(pair.right, &right_au, &right_error);
  if (parallel_) {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait(lock, [this] { return job_done_; });
  }
  if (!left_ok || !right_ok) {
    *error = "h264: " + (left_ok ? "right eye: " + right_error : "left eye: " + left_error);
    force_idr_ = true;
    return false;
  }
  if (left_au.idr != right_au.idr) {
    // One eye chose an IDR the other did not (cannot happen with equal settings): keep both
    // streams' IDRs together so that a waiting viewer resumes both eyes on one pair.
    force_idr_ = true;
  }
  out->sequence = sequence;
  out->stamp = pair.stamp;
  out->idr = left_au.idr && right_au.idr;
  out->width_px = pair.left.cols;
  out->height_px = pair.left.rows;
  out->format = "h264";
  out->left = std::move(left_au.data);
  out->right = std::move(right_au.data);
  return true;
}

}  // namespace mostar::camera
