#include "robot_server/camera/camera_pipeline.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <utility>

#include "common/log/log.h"
#include "common/sync/thread_priority.h"

namespace mostar::camera {

bool CameraPipelineOptions::IsValid(std::string* error) const {
  if (grab_timeout <= Duration::zero()) {
    *error = "grab_timeout must be > 0";
    return false;
  }
  if (max_consecutive_timeouts < 1) {
    *error = "max_consecutive_timeouts must be >= 1";
    return false;
  }
  if (reopen_period < Duration::zero()) {
    *error = "reopen_period must be >= 0";
    return false;
  }
  for (const auto& [class_name, bits_per_s] : bitrate_classes) {
    if (bits_per_s < 0) {
      *error = "bitrate class '" + class_name + "' must have a target >= 0 (0 = unlimited)";
      return false;
    }
  }
  if (codec == VideoCodec::kH264) {
    if (!h264.IsValid(error)) return false;
    if (!video_rate.link.IsValid(error)) return false;
    if (frame_rate_hz < 1) {
      *error = "frame_rate_hz must be >= 1";
      return false;
    }
  }
  return bitrate.IsValid(error);
}

CameraPipeline::CameraPipeline(std::unique_ptr<StereoCamera> camera,
                               const CameraPipelineOptions& options, DeliverFn deliver,
                               const Clock* clock)
    : camera_(std::move(camera)),
      options_(options),
      deliver_(std::move(deliver)),
      clock_(clock),
      bitrate_stats_(BitrateController(options.bitrate).Stats()),
      rate_control_(options.video_rate) {}

CameraPipeline::~CameraPipeline() { Stop(); }

void CameraPipeline::Start() {
  std::lock_guard<std::mutex> lock(stop_mutex_);
  if (started_ || stopping_) return;
  started_ = true;
  {
    std::lock_guard<std::mutex> state_lock(mutex_);
    state_ = DeviceState::kWarn;
    message_ = "opening camera";
  }
  capture_thread_ = std::thread([this] { CaptureLoop(); });
  compress_thread_ = std::thread([this] { CompressLoop(); });
}

void CameraPipeline::Stop() {
  {
    std::lock_guard<std::mutex> lock(stop_mutex_);
    if (stopping_) return;
    stopping_ = true;
  }
  stop_cv_.notify_all();
  if (capture_thread_.joinable()) capture_thread_.join();
  slot_.Close();
  if (compress_thread_.joinable()) compress_thread_.join();
  camera_->Close();
  SetState(DeviceState::kOff, "stopped");
}

bool CameraPipeline::WaitForStop(Duration duration) {
  std::unique_lock<std::mutex> lock(stop_mutex_);
  return stop_cv_.wait_for(lock, duration, [this] { return stopping_; });
}

void CameraPipeline::SetState(DeviceState state, const std::string& message) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (state_ != state || message_ != message) {
    if (state == DeviceState::kError || state == DeviceState::kWarn) {
      MOSTAR_LOG_EVERY_SEC(WARNING, 5) << options_.name << ": " << message;
    } else {
      MOSTAR_LOG(INFO) << options_.name << ": " << message;
    }
  }
  state_ = state;
  message_ = message;
}

void CameraPipeline::CaptureLoop() {
  LowerCurrentThreadPriority();
  bool opened_before = false;
  int consecutive_timeouts = 0;
  uint64_t captured = 0;
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(stop_mutex_);
      if (stopping_) break;
    }
    if (!camera_->IsOpen()) {
      std::string error;
      const bool reopening = opened_before;
      if (reopening) {
        std::lock_guard<std::mutex> lock(mutex_);
        ++reopen_attempts_;
      }
      opened_before = true;
      if (!camera_->Open(&error)) {
        {
          std::lock_guard<std::mutex> lock(mutex_);
          ++open_failures_;
        }
        SetState(DeviceState::kError, "camera not available: " + error);
        if (WaitForStop(options_.reopen_period)) break;
        continue;
      }
      consecutive_timeouts = 0;
      const StereoCameraInfo info = camera_->Info();
      std::ostringstream message;
      message << "capturing " << info.backend << " " << info.width_px << "x" << info.height_px;
      SetState(DeviceState::kOk, message.str());
    }

    StereoImagePair pair;
    const GrabResult result = camera_->Grab(options_.grab_timeout, &pair);
    {
      std::vector<std::pair<std::string, uint64_t>> counters = camera_->Counters();
      std::lock_guard<std::mutex> lock(mutex_);
      camera_counters_ = std::move(counters);
    }
    switch (result.status) {
      case GrabStatus::kOk: {
        consecutive_timeouts = 0;
        int divisor = 1;
        {
          std::lock_guard<std::mutex> lock(mutex_);
          ++frames_;
          divisor = frame_rate_divisor_;
          if (state_ != DeviceState::kOk) {
            state_ = DeviceState::kOk;
            message_ = "capturing";
          }
        }
        if (captured++ % static_cast<uint64_t>(divisor) != 0) {
          std::lock_guard<std::mutex> lock(mutex_);
          ++divided_;
          break;
        }
        slot_.Put(std::move(pair));
        break;
      }
      case GrabStatus::kTimeout: {
        ++consecutive_timeouts;
        {
          std::lock_guard<std::mutex> lock(mutex_);
          ++timeouts_;
        }
        if (consecutive_timeouts >= options_.max_consecutive_timeouts) {
          camera_->Close();
          SetState(DeviceState::kError, "no frames after " + std::to_string(consecutive_timeouts) +
                                            " timeouts; reopening (" + result.message + ")");
        } else {
          SetState(DeviceState::kWarn, "grab timeout: " + result.message);
        }
        break;
      }
      case GrabStatus::kDeviceLost:
      case GrabStatus::kNotOpen: {
        {
          std::lock_guard<std::mutex> lock(mutex_);
          ++device_lost_;
        }
        camera_->Close();
        SetState(DeviceState::kError, "camera lost: " + result.message);
        if (WaitForStop(options_.reopen_period)) return;
        break;
      }
      case GrabStatus::kEndOfStream: {
        camera_->Close();
        SetState(DeviceState::kOff, "end of stream: " + result.message);
        std::unique_lock<std::mutex> lock(stop_mutex_);
        stop_cv_.wait(lock, [this] { return stopping_; });
        return;
      }
    }
  }
}

std::optional<StereoImagePair> CameraPipeline::NextPair(BitrateController* controller,
                                                        double* h264_target) {
  for (;;) {
    std::optional<StereoImagePair> pair = slot_.Take(std::chrono::milliseconds(100));
    if (!pair) {
      if (slot_.closed()) return std::nullopt;
      continue;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    if (pending_target_bits_per_s_ >= 0) {
      controller->SetTargetBitsPerSecond(pending_target_bits_per_s_);
      *h264_target = pending_target_bits_per_s_;
      pending_target_bits_per_s_ = -1;
    }
    return pair;
  }
}

void CameraPipeline::CountDelivery(Delivery delivery, SteadyTime now,
                                   const BitrateController& controller) {
  if (delivery == Delivery::kSent) {
    ++delivered_;
    delivered_rate_.Tick(now);
  } else {
    ++skipped_;
  }
  bitrate_stats_ = controller.Stats();
}

void CameraPipeline::EncodeH264Loop() {
  BitrateController controller(options_.bitrate);  // for its statistics only
  double target = options_.bitrate.target_bits_per_s;
  H264StereoEncoder encoder(options_.h264, options_.frame_rate_hz, options_.parallel_compression);
  StereoVideoFrame out;
  double class_target = -1;
  for (;;) {
    std::optional<StereoImagePair> pair = NextPair(&controller, &target);
    if (!pair) return;
    const SteadyTime start = clock_->SteadyNow();
    const double configured = target > 0 ? target : options_.h264.unlimited_bits_per_s;
    if (configured != class_target) {
      class_target = configured;
      rate_control_.SetClassTarget(class_target);
    }
    if (rate_control_.ShouldSkipFrame(start)) {
      std::lock_guard<std::mutex> lock(mutex_);
      ++skipped_for_link_;
      continue;
    }
    const double bits_per_s = std::min(class_target * options_.bitrate.headroom,
                                       rate_control_.Target(class_target, start));
    {
      const VideoRateStats link = rate_control_.Stats(start);
      MOSTAR_LOG_EVERY_SEC(INFO, 5)
          << options_.name << ": h264 at " << bits_per_s / 1e6 << " Mbit/s (class "
          << class_target / 1e6 << ", " << link.viewers << " viewers reporting, queue "
          << link.queue_ms << " ms)" << (link.viewers > 0 ? " " : "")
          << (link.viewers > 0 ? rate_control_.Describe(start) : std::string());
      if (link.viewers > 0 && !options_.video_rate.auto_repair_deadline &&
          options_.video_rate.repair_deadline > Duration::zero()) {
        const std::string warning = rate_control_.RepairDeadlineWarning(start);
        if (!warning.empty()) MOSTAR_LOG_EVERY_SEC(WARNING, 60) << options_.name << ": " << warning;
      }
      MOSTAR_LOG_EVERY_SEC(DEBUG, 0.1) << options_.name << ": h264 at " << bits_per_s / 1e6
                                       << " Mbit/s " << rate_control_.Describe(start);
    }
    if (repair_deadline_sink_) {
      if (const std::optional<Duration> deadline = rate_control_.RepairDeadlineUpdate(start)) {
        std::string error;
        const VideoRateStats link = rate_control_.Stats(start);
        if (repair_deadline_sink_(*deadline, &error)) {
          MOSTAR_LOG(INFO) << options_.name << ": video repair deadline now "
                           << ToSeconds(*deadline) * 1e3 << " ms (viewers' round trip about "
                           << link.report_lag_ms << " ms)";
        } else {
          MOSTAR_LOG_EVERY_SEC(WARNING, 60) << options_.name << ": " << error;
        }
      }
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (keyframes_.ShouldSendIdr(start)) encoder.ForceIdr();
    }
    std::string error;
    const bool ok = encoder.Encode(*pair, bits_per_s, &out, &error);
    if (!ok) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        ++encode_errors_;
      }
      MOSTAR_LOG_EVERY_SEC(WARNING, 5) << options_.name << ": " << error;
      continue;
    }
    out.encoded = clock_->Now();
    const Delivery delivery = deliver_video_ ? deliver_video_(out) : Delivery::kSkipped;
    const SteadyTime now = clock_->SteadyNow();
    const size_t bytes = out.left.size() + out.right.size();
    controller.OnPairEncoded(now, bytes, delivery == Delivery::kSent);
    if (delivery == Delivery::kSent) {
      rate_control_.OnFrameSent(out.sequence, now, static_cast<uint32_t>(bytes));
    }
    std::lock_guard<std::mutex> lock(mutex_);
    if (out.idr) {
      keyframes_.OnIdrSent(start);
      ++h264_idrs_;
    }
    h264_restarts_ = encoder.restarts();
    CountDelivery(delivery, now, controller);
    bitrate_stats_.quality = 0;  // no JPEG quality in H.264
  }
}

void CameraPipeline::CompressLoop() {
  LowerCurrentThreadPriority();
  if (options_.codec == VideoCodec::kH264) {
    EncodeH264Loop();
    return;
  }
  BitrateController controller(options_.bitrate);
  double unused_target = 0;
  JpegCompressor compressor(options_.parallel_compression);
  CompressedStereoPair out;
  for (;;) {
    std::optional<StereoImagePair> pair = NextPair(&controller, &unused_target);
    if (!pair) return;
    const EncodeSettings settings = controller.Current();
    std::string error;
    if (!compressor.Compress(*pair, settings.jpeg, &out, &error)) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        ++encode_errors_;
      }
      MOSTAR_LOG_EVERY_SEC(WARNING, 5) << options_.name << ": jpeg compression failed: " << error;
      continue;
    }
    out.encoded = clock_->Now();
    const Delivery delivery = deliver_(out);
    const SteadyTime now = clock_->SteadyNow();
    controller.OnPairEncoded(now, out.left.data.size() + out.right.data.size(),
                             delivery == Delivery::kSent);
    std::lock_guard<std::mutex> lock(mutex_);
    CountDelivery(delivery, now, controller);
    frame_rate_divisor_ = controller.Current().frame_rate_divisor;
  }
}

DeviceHealth CameraPipeline::Health() const {
  const LatestValueSlot<StereoImagePair>::Counters slot = slot_.counters();
  std::lock_guard<std::mutex> lock(mutex_);
  DeviceHealth health;
  health.name = options_.name;
  health.state = state_;
  health.message = message_;
  health.rate_hz = static_cast<float>(delivered_rate_.RateHz(clock_->SteadyNow()));
  const auto rounded = [](double value) {
    return static_cast<uint64_t>(std::llround(std::max(0.0, value)));
  };
  health.counters = {
      {"frames", frames_},
      {"pairs_delivered", delivered_},
      {"pairs_skipped_at_source", skipped_},
      {"slot_drops", slot.drops},
      {"divided", divided_},
      {"timeouts", timeouts_},
      {"device_lost", device_lost_},
      {"reopen_attempts", reopen_attempts_},
      {"open_failures", open_failures_},
      {"encode_errors", encode_errors_},
      {"jpeg_quality", static_cast<uint64_t>(bitrate_stats_.quality)},
      {"jpeg_scale_percent", rounded(bitrate_stats_.scale * 100)},
      {"frame_rate_divisor", static_cast<uint64_t>(bitrate_stats_.frame_rate_divisor)},
      {"bitrate_bps", rounded(bitrate_stats_.achieved_bits_per_s)},
      {"target_bitrate_bps", rounded(bitrate_stats_.target_bits_per_s)},
  };
  if (options_.codec == VideoCodec::kH264) {
    const KeyframeRequestCounters& keyframes = keyframes_.counters();
    health.counters.emplace_back("h264_idrs", h264_idrs_);
    health.counters.emplace_back("keyframe_requests", keyframes.requests);
    health.counters.emplace_back("keyframe_requests_deferred", keyframes.deferred);
    health.counters.emplace_back("h264_encoder_restarts", h264_restarts_);
    const VideoRateStats link = rate_control_.Stats(clock_->SteadyNow());
    health.counters.emplace_back("link_viewers", static_cast<uint64_t>(link.viewers));
    health.counters.emplace_back("link_target_bps", rounded(link.target_bits_per_s));
    health.counters.emplace_back("link_queue_ms", rounded(link.queue_ms));
    health.counters.emplace_back("link_repair_deadline_ms", rounded(link.repair_deadline_ms));
    health.counters.emplace_back("skipped_for_link", skipped_for_link_);
  }
  health.counters.insert(health.counters.end(), camera_counters_.begin(), camera_counters_.end());
  return health;
}

BitrateStats CameraPipeline::bitrate_stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return bitrate_stats_;
}

void CameraPipeline::SetTargetBitsPerSecond(double bits_per_s) {
  std::lock_guard<std::mutex> lock(mutex_);
  pending_target_bits_per_s_ = std::max(0.0, bits_per_s);
}

void CameraPipeline::OnVideoFeedback(const VideoFeedback& feedback) {
  if (options_.codec != VideoCodec::kH264) return;
  rate_control_.OnFeedback(feedback, clock_->SteadyNow());
}

void CameraPipeline::RequestKeyframe() {
  if (options_.codec != VideoCodec::kH264) return;
  const SteadyTime now = clock_->SteadyNow();
  std::lock_guard<std::mutex> lock(mutex_);
  keyframes_.Request(now);
}

bool CameraPipeline::SetBitrateClass(const std::string& name) {
  const auto it = options_.bitrate_classes.find(name);
  if (it == options_.bitrate_classes.end()) return false;
  SetTargetBitsPerSecond(it->second);
  return true;
}

}  // namespace mostar::camera
