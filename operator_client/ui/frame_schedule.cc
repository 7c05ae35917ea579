#include "operator_client/ui/frame_schedule.h"

namespace mostar::ui {

FrameSchedule::Decision FrameSchedule::Next(std::optional<uint64_t> shown_sequence,
                                            uint64_t shown_version, bool headless,
                                            bool capture_render) {
  Decision decision;
  decision.new_pair = shown_sequence && *shown_sequence != last_sequence_;
  decision.new_result = shown_sequence && !decision.new_pair && shown_version != last_version_;
  decision.draw = !headless || decision.new_pair || decision.new_result || capture_render;
  if (!decision.draw) return decision;
  last_version_ = shown_version;
  if (shown_sequence) last_sequence_ = *shown_sequence;
  return decision;
}

bool FrameSchedule::CountsForTrace(SteadyTime presented, Duration warmup) {
  if (!first_presented_) first_presented_ = presented;
  return presented - *first_presented_ >= warmup;
}

}  // namespace mostar::ui
