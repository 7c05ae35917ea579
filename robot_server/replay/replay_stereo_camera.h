// A recording as the StereoCamera: the stereo pairs of a recording (robot_server --record,
// operator_client --record), decoded to BGR8 as the interface requires, each delivered when its
// log time is due on a ReplayTimeline (real speed times the rate), so the live pipeline
// (CameraPipeline compression and bitrate control) runs on recorded images.
//
// - Pairs: left and right eyes paired by capture stamp (record::ReplayFrameSource); stamps are
//   the timeline's (ReplayTimeline::Restamp), the sequence counts pairs delivered and skipped,
//   so a gap is a dropped pair.
// - Pacing: each pair when its log time is due, or with Options::due_at_stamp when its capture
//   stamp is (the recording's capture-to-log time left out).
// - Decoding: only pairs that are delivered, both eyes at once (the right one on a helper
//   thread, as a camera reads its two sensors out together). When several pairs are overdue
//   (the capture thread was late, or Open() resumes mid-recording), only the newest is
//   decoded; the others are counted as pairs_skipped_late. A JPEG that does not decode (or eyes of
//   different sizes) is counted in broken_jpegs, logged, and its pair skipped; nothing crashes.
// - End: kEndOfStream "end of recording <file> after N pairs", or with the timeline's loop the
//   first pair again in the next pass. Damage in the file ends a pass early (logged).
// - Open() after Close() resumes at the timeline's current position, not at the beginning.
// Not thread-safe (one capture thread), as every StereoCamera.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/jpeg/jpeg_decoder.h"
#include "common/record/recording_reader.h"
#include "common/record/replay_sources.h"
#include "common/sync/helper_thread.h"
#include "robot_server/camera/stereo_camera.h"
#include "robot_server/replay/replay_timeline.h"

namespace mostar::replay {

class ReplayStereoCamera final : public camera::StereoCamera {
 public:
  using Options = ReplayDeviceOptions;

  explicit ReplayStereoCamera(Options options);
  ~ReplayStereoCamera() override;

  bool Open(std::string* error) override;
  camera::GrabResult Grab(Duration timeout, camera::StereoImagePair* pair) override;
  void Close() override;
  bool IsOpen() const override { return source_ != nullptr; }
  camera::StereoCameraInfo Info() const override;
  // pairs_replayed, broken_jpegs, size_mismatches, pairs_skipped_late, orphan_eyes,
  // replay_loops (passes completed).
  std::vector<std::pair<std::string, uint64_t>> Counters() const override;

  uint64_t pairs_replayed() const { return pairs_replayed_; }
  uint64_t broken_jpegs() const { return broken_jpegs_; }
  uint64_t pairs_skipped_late() const { return pairs_skipped_late_; }
  uint64_t size_mismatches() const { return size_mismatches_; }
  uint64_t pass() const { return pass_; }

 private:
  // Makes pending_ the next pair, starting the next pass at the end when looping. False at the
  // end of the recording (message in `end`).
  bool FillPending(std::string* end);
  void SleepUntil(SteadyTime t) const;

  const Options options_;
  std::unique_ptr<record::ReplayFrameSource> source_;  // null while closed
  record::RecordingReader* reader_ = nullptr;          // read by source_
  std::optional<record::TimedStereoPair> pending_;
  JpegDecoder decoder_;        // every libjpeg warning is a broken JPEG; the left eye
  JpegDecoder right_decoder_;  // the right eye, on right_eye_ while decoder_ does the left
  HelperThread right_eye_;
  uint64_t pass_ = 0;
  uint64_t pairs_in_pass_ = 0;    // taken from the source in this pass
  bool pass_from_begin_ = false;  // this pass started at the beginning of the recording
  uint64_t sequence_ = 0;
  uint64_t pairs_replayed_ = 0;
  uint64_t broken_jpegs_ = 0;
  uint64_t size_mismatches_ = 0;
  uint64_t pairs_skipped_late_ = 0;
  uint64_t orphan_eyes_before_ = 0;  // of previous sources (reopen)
  int width_px_ = 0;
  int height_px_ = 0;
  double frame_rate_hz_ = 0;
};

}  // namespace mostar::replay
