// Which stereo pair the console shows while edge processing runs on another thread
// (vision::EdgeWorker): each new pair is submitted and kept in flight (at most kMaxInFlight,
// oldest dropped); when the worker's newest result belongs to a pair in flight, that pair is
// shown with it, so overlay corrections and image always match. Until the first match the
// latest pair is shown unprocessed. Pure: the caller submits and polls the worker.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>

#include "operator_client/video/stereo_receiver.h"
#include "operator_client/vision/vision_pipeline.h"

namespace mostar::ui {

class FramePicker {
 public:
  static constexpr size_t kMaxInFlight = 4;

  // Edge processing off: `latest` is shown as it is, with no result; nothing stays in flight.
  void ShowUnprocessed(const std::optional<client::DecodedStereoPair>& latest);
  // True when `latest` has not been submitted yet: the caller submits it now, and it is in
  // flight from here on.
  bool TakeNew(const std::optional<client::DecodedStereoPair>& latest);
  // With the worker's newest result (null before the first): shows the pair it belongs to if
  // that pair is in flight (it and older pairs leave the flight), else keeps what is shown
  // (`latest` when nothing is shown yet).
  void OnResult(const std::shared_ptr<const vision::VisionResult>& result,
                const std::optional<client::DecodedStereoPair>& latest);

  const std::optional<client::DecodedStereoPair>& shown_pair() const { return shown_pair_; }
  // The shown pair's edge result when it succeeded; null without one or when it failed.
  const std::shared_ptr<const vision::VisionResult>& shown_result() const { return shown_result_; }
  // Sequence of the pair of the last matched result, ok or not (0 before the first).
  uint64_t result_sequence() const { return result_sequence_; }
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
  uint64_t submitted_ = 0;                                   // sequence of the last pair taken
  std::map<uint64_t, client::DecodedStereoPair> in_flight_;  // by sequence
  std::optional<client::DecodedStereoPair> shown_pair_;
  std::shared_ptr<const vision::VisionResult> shown_result_;
  uint64_t result_sequence_ = 0;
};

}  // namespace mostar::ui
