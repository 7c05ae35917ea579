// Which stereo pair the console shows while edge processing runs on another thread
// (vision::EdgeWorker): each new pair is submitted and kept in flight (at most kMaxInFlight,
// oldest dropped). A pair is shown with its own result when the result comes within the wait
// (`result_wait`, counted from when the pair was taken); past the wait the newest pair in flight
// is shown without its result (no dots, the scan moved by the caller), and its result is added
// when it comes, unless a newer pair is on screen by then (the result is then missed). So
// overlay corrections and image always match, and no pair waits for vision longer than the wait.
// Nothing older than the shown pair is ever shown. Until something is shown, the latest pair is
// shown at once (without its result, which is added when it comes). Pure: the caller submits
// and polls the worker, and passes the time in.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>

#include "common/time/time.h"
#include "operator_client/video/stereo_receiver.h"
#include "operator_client/vision/vision_pipeline.h"

namespace mostar::ui {

class FramePicker {
 public:
  static constexpr size_t kMaxInFlight = 4;

  // How the shown pair's overlay relates to its edge result (the HUD says it).
  enum class ResultState {
    kNone,       // edge processing off, or nothing processed yet
    kInTime,     // shown with its result, which came within the wait
    kWaiting,    // shown without its result: the wait ran out, the result is still awaited
    kAddedLate,  // shown first without its result, which was added when it came
  };
  // Pairs by what became of their results (edge processing on).
  struct Counts {
    uint64_t in_time = 0;         // shown with their result
    uint64_t without_result = 0;  // shown when the wait ran out
    uint64_t added_late = 0;      // of those, the result came while the pair was on screen
    uint64_t missed = 0;          // results that came when a newer pair was on screen
  };

  // Edge processing off: `latest` is shown as it is, with no result; nothing stays in flight.
  void ShowUnprocessed(const std::optional<client::DecodedStereoPair>& latest);
  // True when `latest` has not been submitted yet: the caller submits it now, and it is in
  // flight from `now` on.
  bool TakeNew(const std::optional<client::DecodedStereoPair>& latest, SteadyTime now);
  // With the worker's newest result (null before the first): shows the pair it belongs to if
  // that pair is in flight and not older than the shown one (it and older pairs leave the
  // flight); else, when the newest pair in flight has waited `result_wait` by `now`, shows it
  // without a result; else keeps what is shown (`latest` when nothing is shown yet).
  void OnResult(const std::shared_ptr<const vision::VisionResult>& result,
                const std::optional<client::DecodedStereoPair>& latest, SteadyTime now,
                Duration result_wait);
  // When the newest pair in flight is to be shown without its result (its wait runs out);
  // nullopt when no pair in flight is newer than the shown one.
  std::optional<SteadyTime> NextWaitEnd(Duration result_wait) const;

  const std::optional<client::DecodedStereoPair>& shown_pair() const { return shown_pair_; }
  // The shown pair's edge result when it succeeded; null without one or when it failed.
  const std::shared_ptr<const vision::VisionResult>& shown_result() const { return shown_result_; }
  // Sequence of the pair of the last result shown, ok or not (0 before the first).
  uint64_t result_sequence() const { return result_sequence_; }
  // Changes whenever the shown pair or its result changes: a new frame is due.
  uint64_t shown_version() const { return shown_version_; }
  ResultState result_state() const { return result_state_; }
  // When the shown pair could first be shown: its result's publication (in time), the end of
  // its wait (shown without its result), or when it was taken (nothing processed yet).
  SteadyTime shown_ready_at() const { return shown_ready_at_; }
  const Counts& counts() const { return counts_; }

  // The scan to draw over the shown pair. With a successful edge result for this very pair: its
  // corrected scan (NEP-corrected points, confirmed outliers removed) and the result's placement:
  // the scan is where edge processing had it, to be drawn without moving it again. Else `nearest`
  // (the scan nearest in time to the pair, or the latest one without a pair) and no placement.
  struct DrawnScan {
    std::optional<LaserScan> scan;
    std::optional<vision::ScanPlacement> placement;
  };
  DrawnScan ScanToDraw(std::optional<LaserScan> nearest) const;
  size_t in_flight() const { return in_flight_.size(); }

 private:
  struct InFlight {
    client::DecodedStereoPair pair;
    SteadyTime taken;
  };
  void Show(const client::DecodedStereoPair& pair,
            std::shared_ptr<const vision::VisionResult> result, ResultState state,
            SteadyTime ready_at);
  uint64_t shown_sequence() const { return shown_pair_ ? shown_pair_->sequence : 0; }

  uint64_t submitted_ = 0;                  // sequence of the last pair taken
  std::map<uint64_t, InFlight> in_flight_;  // by sequence
  std::optional<client::DecodedStereoPair> shown_pair_;
  std::shared_ptr<const vision::VisionResult> shown_result_;
  uint64_t result_sequence_ = 0;
  uint64_t shown_version_ = 0;
  ResultState result_state_ = ResultState::kNone;
  SteadyTime shown_ready_at_{};
  Counts counts_;
};

const char* ResultStateName(FramePicker::ResultState state);
// The HUD's line for the shown pair: empty when its result is in (or edge processing is off).
const char* ResultNote(FramePicker::ResultState state);

}  // namespace mostar::ui
