#include "robot_server/replay/replay_stereo_camera.h"

#include <opencv2/core.hpp>
#include <thread>

#include "common/jpeg/jpeg_decoder.h"
#include "common/log/log.h"

namespace mostar::replay {
namespace {

// BGR8 image of one recorded eye; empty when the bytes do not decode without a warning.
cv::Mat Decode(JpegDecoder* decoder, const CompressedImage& image) {
  cv::Mat bgr;
  if (!decoder->Decode(image.data, &bgr, nullptr)) return {};
  return bgr;
}

std::string DamageNote(const record::RecordingReader* reader) {
  if (reader == nullptr || !reader->damage()) return "";
  return " (damaged at byte " + std::to_string(reader->damage()->offset) + ": " +
         reader->damage()->reason + ")";
}

}  // namespace

ReplayStereoCamera::ReplayStereoCamera(Options options) : options_(std::move(options)) {}

ReplayStereoCamera::~ReplayStereoCamera() { Close(); }

void ReplayStereoCamera::SleepUntil(SteadyTime t) const {
  for (SteadyTime now = options_.clock->SteadyNow(); now < t; now = options_.clock->SteadyNow()) {
    options_.sleep(t - now);
  }
}

bool ReplayStereoCamera::Open(std::string* error) {
  Close();
  if (!options_.timeline) {
    *error = "replay camera without a timeline";
    return false;
  }
  auto reader = record::RecordingReader::Open(options_.path, error);
  if (!reader) return false;
  reader_ = reader.get();
  const float recorded_fps = reader->info().sensors.camera_frame_rate_hz;
  source_ = std::make_unique<record::ReplayFrameSource>(std::move(reader));
  frame_rate_hz_ = recorded_fps * options_.timeline->options().rate;
  // Start (or resume) where the timeline is now.
  ReplayTimeline& timeline = *options_.timeline;
  timeline.Start();
  uint64_t pass = 0;
  const Time now = timeline.RecordingNow(&pass);
  pass_ = pass;
  pairs_in_pass_ = 0;
  pass_from_begin_ = now <= timeline.begin();
  if (!pass_from_begin_) source_->SeekToTime(now);
  // The image size, from the first pair that decodes (once).
  std::string end;
  for (int tries = 0; width_px_ == 0 && tries < 8 && FillPending(&end); ++tries) {
    const cv::Mat left = Decode(&decoder_, pending_->pair.left);
    if (!left.empty()) {
      width_px_ = left.cols;
      height_px_ = left.rows;
    } else {
      pending_.reset();  // skipped as Grab() would skip it
      ++broken_jpegs_;
      ++sequence_;
      ++pairs_in_pass_;
    }
  }
  return true;
}

void ReplayStereoCamera::Close() {
  if (source_) orphan_eyes_before_ += source_->orphan_eyes();
  pending_.reset();
  source_.reset();
  reader_ = nullptr;
}

bool ReplayStereoCamera::FillPending(std::string* end) {
  if (pending_) return true;
  for (int attempt = 0; attempt < 2; ++attempt) {
    record::TimedStereoPair pair;
    if (source_->Next(&pair)) {
      pending_ = std::move(pair);
      return true;
    }
    const std::string damage = DamageNote(reader_);
    if (!damage.empty()) {
      MOSTAR_LOG_EVERY_SEC(WARNING, 10)
          << "camera replay: " << options_.path << damage << "; replayed the pairs before it";
    }
    if (!options_.timeline->options().loop) {
      *end = "end of recording " + options_.path + " after " + std::to_string(pairs_replayed_) +
             " pairs" + damage;
      return false;
    }
    if (pass_from_begin_ && pairs_in_pass_ == 0) break;
    ++pass_;
    pairs_in_pass_ = 0;
    pass_from_begin_ = true;
    source_->SeekToTime(Time::min());
  }
  *end = "no stereo pairs in " + options_.path + DamageNote(reader_);
  return false;
}

camera::GrabResult ReplayStereoCamera::Grab(Duration timeout, camera::StereoImagePair* out) {
  using camera::GrabResult;
  using camera::GrabStatus;
  if (!source_) return GrabResult::Error(GrabStatus::kNotOpen, "replay camera not open");
  const ReplayTimeline& timeline = *options_.timeline;
  const SteadyTime deadline = options_.clock->SteadyNow() + timeout;
  for (;;) {
    std::string end;
    if (!FillPending(&end)) {
      MOSTAR_LOG_EVERY_SEC(INFO, 10) << "camera replay: " << end;
      return GrabResult::Error(GrabStatus::kEndOfStream, end);
    }
    const SteadyTime due = timeline.DueTime(
        options_.due_at_stamp ? pending_->pair.left.stamp : pending_->log_time, pass_);
    if (due > deadline) {
      SleepUntil(deadline);
      return GrabResult::Error(
          GrabStatus::kTimeout,
          "next recorded pair due in " +
              std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(
                                 due - options_.clock->SteadyNow())
                                 .count()) +
              " ms");
    }
    SleepUntil(due);
    record::TimedStereoPair pair = std::move(*pending_);
    pending_.reset();
    ++sequence_;
    ++pairs_in_pass_;
    // Overdue pairs of this pass: only the newest is decoded.
    for (std::optional<Time> next = source_->PeekTime();
         next && timeline.DueTime(*next, pass_) <= options_.clock->SteadyNow();
         next = source_->PeekTime()) {
      source_->Next(&pair);
      ++sequence_;
      ++pairs_in_pass_;
      ++pairs_skipped_late_;
    }
    cv::Mat right;
    right_eye_.Run([&] { right = Decode(&right_decoder_, pair.pair.right); });
    cv::Mat left = Decode(&decoder_, pair.pair.left);
    right_eye_.Wait();
    if (left.empty() || right.empty()) {
      broken_jpegs_ += static_cast<uint64_t>(left.empty()) + static_cast<uint64_t>(right.empty());
      MOSTAR_LOG_EVERY_SEC(WARNING, 5)
          << "camera replay: undecodable JPEG in the pair stamped "
          << ToIso8601(pair.pair.left.stamp) << " (" << broken_jpegs_ << " so far); skipped";
      continue;
    }
    if (left.size() != right.size()) {
      ++size_mismatches_;
      MOSTAR_LOG_EVERY_SEC(WARNING, 5) << "camera replay: eyes of different sizes in the pair "
                                          "stamped "
                                       << ToIso8601(pair.pair.left.stamp) << "; skipped";
      continue;
    }
    if (width_px_ == 0) {
      width_px_ = left.cols;
      height_px_ = left.rows;
    }
    out->sequence = sequence_;
    out->stamp = timeline.Restamp(pair.pair.left.stamp, pass_);
    out->left = std::move(left);
    out->right = std::move(right);
    ++pairs_replayed_;
    return GrabResult::Ok();
  }
}

camera::StereoCameraInfo ReplayStereoCamera::Info() const {
  camera::StereoCameraInfo info;
  info.backend = "replay";
  info.left_device = options_.path;
  info.right_device = options_.path;
  info.width_px = width_px_;
  info.height_px = height_px_;
  info.frame_rate_hz = frame_rate_hz_;
  return info;
}

std::vector<std::pair<std::string, uint64_t>> ReplayStereoCamera::Counters() const {
  return {{"pairs_replayed", pairs_replayed_},
          {"broken_jpegs", broken_jpegs_},
          {"size_mismatches", size_mismatches_},
          {"pairs_skipped_late", pairs_skipped_late_},
          {"orphan_eyes", orphan_eyes_before_ + (source_ ? source_->orphan_eyes() : 0)},
          {"replay_loops", pass_}};
}

}  // namespace mostar::replay
