#include "robot_server/camera/jpeg_compressor.h"

#include <algorithm>
#include <csetjmp>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "common/jpeg/jpeg_error.h"
#include "common/sync/thread_priority.h"
#include "robot_server/camera/camera_pipeline.h"

namespace mostar::camera {
namespace {

// Destination manager writing into a std::vector (grown by doubling; capacity reused).
struct VectorDestination {
  jpeg_destination_mgr base;
  std::vector<uint8_t>* out;
};

void InitDestination(j_compress_ptr cinfo) {
  auto* dest = reinterpret_cast<VectorDestination*>(cinfo->dest);
  if (dest->out->size() < 64 * 1024)
    dest->out->resize(std::max<size_t>(64 * 1024, dest->out->capacity()));
  dest->base.next_output_byte = dest->out->data();
  dest->base.free_in_buffer = dest->out->size();
}

boolean EmptyOutputBuffer(j_compress_ptr cinfo) {
  auto* dest = reinterpret_cast<VectorDestination*>(cinfo->dest);
  const size_t used = dest->out->size();
  dest->out->resize(used * 2);
  dest->base.next_output_byte = dest->out->data() + used;
  dest->base.free_in_buffer = dest->out->size() - used;
  return TRUE;
}

void TermDestination(j_compress_ptr cinfo) {
  auto* dest = reinterpret_cast<VectorDestination*>(cinfo->dest);
  dest->out->resize(dest->out->size() - dest->base.free_in_buffer);
}

}  // namespace

bool JpegSettings::IsValid(std::string* error) const {
  if (quality < 1 || quality > 100) {
    *error = "jpeg quality must be in 1..100, got " + std::to_string(quality);
    return false;
  }
  if (!(scale > 0.0 && scale <= 1.0)) {
    *error = "jpeg scale must be in (0, 1], got " + std::to_string(scale);
    return false;
  }
  return true;
}

struct JpegEncoder::State {
  jpeg_compress_struct cinfo;
  JpegErrorManager error;
  VectorDestination dest;
};

// The libjpeg part of JpegEncoder::Encode, alone in its function so that setjmp sees only
// values that do not change after it.
static bool RunCompress(JpegEncoder::State* state, const cv::Mat& source, int quality,
                        std::vector<uint8_t>* out, std::string* error) {
  jpeg_compress_struct* const cinfo = &state->cinfo;
  state->dest.out = out;
  state->error.warnings = 0;
  if (setjmp(state->error.jump)) {
    jpeg_abort_compress(cinfo);
    *error = std::string("jpeg encode: ") + state->error.message;
    out->clear();
    return false;
  }
  cinfo->image_width = static_cast<JDIMENSION>(source.cols);
  cinfo->image_height = static_cast<JDIMENSION>(source.rows);
  cinfo->input_components = source.channels();
  cinfo->in_color_space = source.channels() == 3 ? JCS_EXT_BGR : JCS_GRAYSCALE;
  jpeg_set_defaults(cinfo);
  jpeg_set_quality(cinfo, quality, TRUE);
  jpeg_start_compress(cinfo, TRUE);
  while (cinfo->next_scanline < cinfo->image_height) {
    JSAMPROW row =
        const_cast<JSAMPROW>(source.ptr<uint8_t>(static_cast<int>(cinfo->next_scanline)));
    jpeg_write_scanlines(cinfo, &row, 1);
  }
  jpeg_finish_compress(cinfo);
  return true;
}

JpegEncoder::JpegEncoder() : state_(std::make_unique<State>()) {
  state_->cinfo.err = InitJpegErrorManager(&state_->error);
  jpeg_create_compress(&state_->cinfo);
  state_->dest.base.init_destination = InitDestination;
  state_->dest.base.empty_output_buffer = EmptyOutputBuffer;
  state_->dest.base.term_destination = TermDestination;
  state_->dest.out = nullptr;
  state_->cinfo.dest = &state_->dest.base;
}

JpegEncoder::~JpegEncoder() { jpeg_destroy_compress(&state_->cinfo); }

bool JpegEncoder::Encode(const cv::Mat& bgr, const JpegSettings& settings,
                         std::vector<uint8_t>* out, std::string* error) {
  if (!settings.IsValid(error)) return false;
  if (bgr.empty() || bgr.depth() != CV_8U || (bgr.channels() != 3 && bgr.channels() != 1)) {
    *error = "jpeg encode: need a non-empty 8-bit BGR or grey image";
    return false;
  }
  const cv::Mat* source = &bgr;
  if (settings.scale < 1.0) {
    const int width = std::max(1, static_cast<int>(bgr.cols * settings.scale + 0.5));
    const int height = std::max(1, static_cast<int>(bgr.rows * settings.scale + 0.5));
    cv::resize(bgr, scaled_, cv::Size(width, height), 0, 0, cv::INTER_AREA);
    source = &scaled_;
  }
  return RunCompress(state_.get(), *source, settings.quality, out, error);
}

JpegCompressor::JpegCompressor(bool parallel) : parallel_(parallel) {
  if (parallel_) {
    worker_ = std::thread([this] {
      LowerCurrentThreadPriority();
      WorkerLoop();
    });
  }
}

JpegCompressor::~JpegCompressor() {
  if (worker_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    cv_.notify_all();
    worker_.join();
  }
}

void JpegCompressor::WorkerLoop() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    cv_.wait(lock, [this] { return stop_ || job_pending_; });
    if (stop_) return;
    job_pending_ = false;
    const cv::Mat* image = job_image_;
    const JpegSettings settings = job_settings_;
    std::vector<uint8_t>* out = job_out_;
    lock.unlock();
    std::string error;
    const bool ok = left_encoder_.Encode(*image, settings, out, &error);
    lock.lock();
    job_ok_ = ok;
    job_error_ = error;
    job_done_ = true;
    cv_.notify_all();
  }
}

bool JpegCompressor::Compress(const StereoImagePair& pair, const JpegSettings& settings,
                              CompressedStereoPair* out, std::string* error) {
  out->sequence = pair.sequence;
  out->left.stamp = pair.stamp;
  out->right.stamp = pair.stamp;
  out->left.frame_id = "camera_left";
  out->right.frame_id = "camera_right";
  out->left.format = "jpeg";
  out->right.format = "jpeg";
  bool left_ok = false;
  std::string left_error;
  if (parallel_) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      job_image_ = &pair.left;
      job_settings_ = settings;
      job_out_ = &out->left.data;
      job_done_ = false;
      job_pending_ = true;
    }
    cv_.notify_all();
  } else {
    left_ok = left_encoder_.Encode(pair.left, settings, &out->left.data, &left_error);
  }
  std::string right_error;
  const bool right_ok = right_encoder_.Encode(pair.right, settings, &out->right.data, &right_error);
  if (parallel_) {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait(lock, [this] { return job_done_; });
    left_ok = job_ok_;
    left_error = job_error_;
  }
  if (!left_ok) {
    *error = "left eye: " + left_error;
    return false;
  }
  if (!right_ok) {
    *error = "right eye: " + right_error;
    return false;
  }
  return true;
}

}  // namespace mostar::camera
