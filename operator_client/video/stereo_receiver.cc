#include "operator_client/video/stereo_receiver.h"

#include <algorithm>
#include <opencv2/imgcodecs.hpp>

#include "common/log/log.h"
#include "operator_client/video/jpeg_header.h"

namespace mostar::client {

namespace {
constexpr size_t kMaxPending = 8;  // per eye; older unpaired images are dropped

cv::Mat Decode(const CompressedImage& image) {
  if (image.data.empty()) return {};
  try {
    return cv::imdecode(cv::Mat(1, static_cast<int>(image.data.size()), CV_8UC1,
                                const_cast<uint8_t*>(image.data.data())),
                        cv::IMREAD_COLOR);
  } catch (const cv::Exception&) {
    return {};
  }
}
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

void StereoReceiver::DecodeLoop() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    cv_.wait(lock, [this] { return stop_ || to_decode_.has_value(); });
    if (stop_) return;
    CompressedStereoPair pair = std::move(*to_decode_);
    const SteadyTime received = to_decode_received_;
    to_decode_.reset();
    lock.unlock();
    DecodedStereoPair decoded;
    decoded.stamp = pair.left.stamp;
    decoded.received = received;
    decoded.left = Decode(pair.left);
    decoded.right = Decode(pair.right);
    decoded.compressed_bytes = pair.left.data.size() + pair.right.data.size();
    const bool broken = decoded.left.empty() || decoded.right.empty();
    decoded.decoded = clock_->SteadyNow();
    lock.lock();
    if (broken) {
      ++stats_.broken_images;
      MOSTAR_LOG_EVERY_SEC(WARNING, 5) << "undecodable JPEG in the pair stamped "
                                       << ToIso8601(pair.left.stamp) << ": pair dropped";
      continue;
    }
    decoded.sequence = ++stats_.pairs_decoded;
    pair_rate_.Tick(clock_->SteadyNow());
    latest_ = std::move(decoded);
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
