#include "robot_server/camera/fake_stereo_camera.h"

#include <opencv2/imgproc.hpp>
#include <string>
#include <thread>
#include <utility>

namespace mostar::camera {

cv::Mat MakeSyntheticImage(int width_px, int height_px, uint64_t sequence, bool right_eye) {
  cv::Mat image(height_px, width_px, CV_8UC3);
  const int shift = static_cast<int>(sequence % 64) + (right_eye ? 12 : 0);
  for (int y = 0; y < height_px; ++y) {
    auto* row = image.ptr<cv::Vec3b>(y);
    for (int x = 0; x < width_px; ++x) {
      // Smooth gradients plus a deterministic texture (floor-like high frequencies).
      const int texture = ((x * 7 + y * 13 + shift * 3) ^ (x * y)) & 31;
      row[x] = cv::Vec3b(static_cast<uint8_t>((x + shift) * 200 / width_px + texture),
                         static_cast<uint8_t>(y * 200 / height_px + texture),
                         static_cast<uint8_t>(((x + y) / 4 + texture) & 0xff));
    }
  }
  const int cx = width_px / 2 + static_cast<int>(sequence % 40) - 20 - (right_eye ? 15 : 0);
  cv::circle(image, {cx, height_px / 2}, height_px / 6, {40, 60, 220}, cv::FILLED);
  cv::rectangle(image, {width_px / 8, height_px * 2 / 3},
                {width_px / 8 + width_px / 5, height_px * 2 / 3 + height_px / 6}, {200, 200, 40},
                3);
  cv::putText(image, "seq " + std::to_string(sequence), {width_px / 20, height_px / 8},
              cv::FONT_HERSHEY_SIMPLEX, height_px / 480.0 + 0.5, {255, 255, 255}, 2);
  return image;
}

FakeStereoCamera::FakeStereoCamera(const Options& options) : options_(options) {}

void FakeStereoCamera::QueuePairs(int count) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (int i = 0; i < count; ++i) script_.push_back({EventKind::kSynthetic, {}});
  }
  cv_.notify_all();
}

void FakeStereoCamera::QueuePair(StereoImagePair pair) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    script_.push_back({EventKind::kPair, std::move(pair)});
  }
  cv_.notify_all();
}

void FakeStereoCamera::QueueTimeout() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    script_.push_back({EventKind::kTimeout, {}});
  }
  cv_.notify_all();
}

void FakeStereoCamera::QueueDeviceLost() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    script_.push_back({EventKind::kDeviceLost, {}});
  }
  cv_.notify_all();
}

void FakeStereoCamera::QueueEndOfStream() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    script_.push_back({EventKind::kEndOfStream, {}});
  }
  cv_.notify_all();
}

void FakeStereoCamera::SetOpenFailures(int count) {
  std::lock_guard<std::mutex> lock(mutex_);
  open_failures_ = count;
}

void FakeStereoCamera::Unplug() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    unplugged_ = true;
  }
  cv_.notify_all();
}

void FakeStereoCamera::Replug() {
  std::lock_guard<std::mutex> lock(mutex_);
  unplugged_ = false;
}

int FakeStereoCamera::open_calls() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return open_calls_;
}

int FakeStereoCamera::close_calls() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return close_calls_;
}

uint64_t FakeStereoCamera::pairs_delivered() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return delivered_;
}

bool FakeStereoCamera::Open(std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++open_calls_;
  open_ = false;
  if (unplugged_) {
    *error = "fake camera unplugged";
    return false;
  }
  if (open_failures_ > 0) {
    --open_failures_;
    *error = "fake camera open failure (scripted)";
    return false;
  }
  open_ = true;
  next_paced_ = SteadyTime(std::chrono::steady_clock::now().time_since_epoch());
  return true;
}

StereoImagePair FakeStereoCamera::Synthesize() {
  StereoImagePair pair;
  pair.sequence = next_sequence_;
  constexpr size_t kCacheSize = 16;
  if (cache_.empty()) {
    for (size_t i = 0; i < kCacheSize; ++i) {
      cache_.emplace_back(MakeSyntheticImage(options_.width_px, options_.height_px, i, false),
                          MakeSyntheticImage(options_.width_px, options_.height_px, i, true));
    }
  }
  const auto& cached = cache_[next_sequence_ % kCacheSize];
  pair.left = cached.first.clone();
  pair.right = cached.second.clone();
  pair.stamp = options_.clock->Now();
  return pair;
}

GrabResult FakeStereoCamera::Grab(Duration timeout, StereoImagePair* pair) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (!open_) return GrabResult::Error(GrabStatus::kNotOpen, "fake camera not open");
  if (unplugged_) {
    open_ = false;
    return GrabResult::Error(GrabStatus::kDeviceLost, "fake camera unplugged");
  }
  if (script_.empty() && options_.free_run) {
    if (options_.paced && options_.frame_rate_hz > 0) {
      const auto period = FromSeconds(1.0 / options_.frame_rate_hz);
      next_paced_ += period;
      const SteadyTime now(std::chrono::steady_clock::now().time_since_epoch());
      if (next_paced_ < now - period) next_paced_ = now;  // fell behind: do not burst
      lock.unlock();
      std::this_thread::sleep_until(std::chrono::steady_clock::time_point(
          std::chrono::duration_cast<std::chrono::steady_clock::duration>(
              next_paced_.time_since_epoch())));
      lock.lock();
    }
    *pair = Synthesize();
    ++next_sequence_;
    ++delivered_;
    return GrabResult::Ok();
  }
  if (!cv_.wait_for(lock, timeout, [this] { return !script_.empty() || unplugged_; })) {
    return GrabResult::Error(GrabStatus::kTimeout, "fake camera: no frame within timeout");
  }
  if (unplugged_) {
    open_ = false;
    return GrabResult::Error(GrabStatus::kDeviceLost, "fake camera unplugged");
  }
  Event event = std::move(script_.front());
  script_.pop_front();
  switch (event.kind) {
    case EventKind::kSynthetic:
      *pair = Synthesize();
      ++next_sequence_;
      break;
    case EventKind::kPair:
      *pair = std::move(event.pair);
      next_sequence_ = pair->sequence + 1;
      break;
    case EventKind::kTimeout:
      return GrabResult::Error(GrabStatus::kTimeout, "fake camera: scripted timeout");
    case EventKind::kDeviceLost:
      open_ = false;
      return GrabResult::Error(GrabStatus::kDeviceLost, "fake camera: scripted device loss");
    case EventKind::kEndOfStream:
      return GrabResult::Error(GrabStatus::kEndOfStream, "fake camera: end of script");
  }
  ++delivered_;
  return GrabResult::Ok();
}

void FakeStereoCamera::Close() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (open_) ++close_calls_;
  open_ = false;
}

bool FakeStereoCamera::IsOpen() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return open_;
}

std::vector<std::pair<std::string, uint64_t>> FakeStereoCamera::Counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {{"fake_pairs_delivered", delivered_}};
}

StereoCameraInfo FakeStereoCamera::Info() const {
  StereoCameraInfo info;
  info.backend = "fake";
  info.left_device = "fake:left";
  info.right_device = "fake:right";
  info.width_px = options_.width_px;
  info.height_px = options_.height_px;
  info.frame_rate_hz = options_.frame_rate_hz;
  return info;
}

}  // namespace mostar::camera
