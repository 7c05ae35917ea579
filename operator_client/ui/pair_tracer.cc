#include "operator_client/ui/pair_tracer.h"

#include <algorithm>

namespace mostar::ui {

Time RobotTimeMapper::operator()(SteadyTime t) const {
  const Time local = now_ - (steady_now_ - t);
  return offset_.known ? offset_.ToResponderTime(local) : local;
}

void PairTracer::Picked(uint64_t sequence, SteadyTime at) {
  for (const auto& [seen, when] : picked_) {
    if (seen == sequence) return;
  }
  picked_.emplace_back(sequence, at);
  while (picked_.size() > kRemembered) picked_.pop_front();
}

PairTimeline PairTracer::Timeline(const ShownPairStamps& pair,
                                  const std::optional<FrameTiming>& robot_side,
                                  const ShowingFrame& frame, bool vision_enabled,
                                  const RobotTimeMapper& to_robot) const {
  PairTimeline timeline;
  timeline.capture = pair.capture;
  if (robot_side) {
    timeline.Set(LatencyStage::kEncoded, robot_side->encoded);
    timeline.Set(LatencyStage::kWritten, robot_side->written);
  }
  timeline.Set(LatencyStage::kReceived, to_robot(pair.received));
  timeline.Set(LatencyStage::kQueued, to_robot(pair.decode_started));
  timeline.Set(LatencyStage::kDecoded, to_robot(pair.decoded));
  std::optional<Time> picked;
  for (const auto& [sequence, at] : picked_) {
    if (sequence == pair.sequence) picked = to_robot(at);
  }
  if (picked) timeline.Set(LatencyStage::kPicked, *picked);
  // With edge processing on, the pair waits for its result or for the end of its result wait.
  if (vision_enabled) {
    const Time ready = to_robot(frame.ready);
    timeline.Set(LatencyStage::kVision, picked ? std::max(*picked, ready) : ready);
  } else if (picked) {
    timeline.Set(LatencyStage::kVision, *picked);
  }
  timeline.Set(LatencyStage::kStarted, to_robot(frame.start));
  timeline.Set(LatencyStage::kDrawn, to_robot(frame.drawn));
  timeline.Set(LatencyStage::kPresented, to_robot(frame.presented));
  return timeline;
}

}  // namespace mostar::ui
