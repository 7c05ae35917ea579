#include "operator_client/web/edge_runner.h"

#include <chrono>
#include <string>

#include "common/jpeg/jpeg_decoder.h"
#include "operator_client/video/jpeg_header.h"

namespace mostar::web {
namespace {

// Grey pixels of `jpeg` (edge processing works on intensity), empty when it is not a readable
// JPEG or declares a size other than the camera's.
cv::Mat DecodeGrey(JpegDecoder* decoder, const std::vector<uint8_t>& jpeg,
                   const math::CameraModel& camera) {
  client::JpegHeader header;
  std::string why;
  if (jpeg.empty() || !client::ReadJpegHeader(jpeg.data(), jpeg.size(), &header, &why) ||
      !client::FitsExpectedSize(header, camera.width_px(), camera.height_px(), &why)) {
    return {};
  }
  cv::Mat grey;
  if (!decoder->Decode(jpeg.data(), jpeg.size(), 1, &grey, nullptr, JpegPixels::kGrey)) return {};
  return grey;
}

}  // namespace

EdgeRunner::EdgeRunner(const vision::VisionOptions& options) : pipeline_(options) {
  thread_ = std::thread([this] { Run(); });
}

EdgeRunner::~EdgeRunner() {
  pending_.Close();
  thread_.join();
}

void EdgeRunner::Submit(EdgeJob job) {
  const bool replaced = !pending_.Put(std::move(job));
  std::lock_guard<std::mutex> lock(mutex_);
  ++stats_.submitted;
  if (replaced) ++stats_.replaced;
}

std::shared_ptr<const vision::VisionResult> EdgeRunner::LatestResult() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return latest_;
}

EdgeRunner::Stats EdgeRunner::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

void EdgeRunner::Run() {
  JpegDecoder decoder;
  while (!pending_.closed()) {
    std::optional<EdgeJob> job = pending_.Take(std::chrono::milliseconds(100));
    if (!job) continue;
    const auto start = std::chrono::steady_clock::now();
    vision::VisionInput input;
    input.stamp = job->pair.left.stamp;
    input.sequence = job->sequence;
    bool decoded = job->left_camera != nullptr;
    if (decoded) input.left = DecodeGrey(&decoder, job->pair.left.data, *job->left_camera);
    decoded = decoded && !input.left.empty();
    if (decoded && pipeline_.options().stereo) {
      decoded = job->right_camera != nullptr;
      if (decoded) input.right = DecodeGrey(&decoder, job->pair.right.data, *job->right_camera);
      decoded = decoded && !input.right.empty();
    }
    const Duration decode_time = std::chrono::steady_clock::now() - start;
    if (!decoded) {
      std::lock_guard<std::mutex> lock(mutex_);
      ++stats_.broken;
      stats_.decode_time = decode_time;
      continue;
    }
    input.scan = std::move(job->scan);
    input.placement = std::move(job->placement);
    input.potential_outliers = std::move(job->potential_outliers);
    input.left_camera = std::move(job->left_camera);
    input.right_camera = std::move(job->right_camera);
    auto result = std::make_shared<vision::VisionResult>();
    pipeline_.Process(input, result.get());
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.processed;
    if (!result->ok) ++stats_.failed;
    stats_.decode_time = decode_time;
    stats_.processing_time = result->processing_time;
    latest_ = std::move(result);
  }
}

}  // namespace mostar::web
