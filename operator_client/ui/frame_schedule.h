// When the console draws a frame and what the frame is: a new pair, the shown pair again with
// its edge result that came late, a capture render, or (in a visible window) a refresh; and
// whether a presented frame counts for the latency trace (after the warm-up, timed from the
// first new pair presented). Pure: the caller passes the picker's state and the times in.
#pragma once

#include <cstdint>
#include <optional>

#include "common/time/time.h"

namespace mostar::ui {

class FrameSchedule {
 public:
  struct Decision {
    bool draw = false;
    bool new_pair = false;    // the shown pair was not drawn before
    bool new_result = false;  // the shown pair again: its edge result changed since
  };

  // `shown_sequence`: the shown pair's (nullopt without one); `shown_version`:
  // FramePicker::shown_version(). Headless, a frame is drawn only for a new pair, a new result
  // or a capture render; a visible window draws every frame. A drawn decision is remembered:
  // the same state asks for no new pair or result again.
  Decision Next(std::optional<uint64_t> shown_sequence, uint64_t shown_version, bool headless,
                bool capture_render);

  // A frame showing a new pair was presented at `presented`: true when it counts for the trace
  // (at least `warmup` after the first such frame).
  bool CountsForTrace(SteadyTime presented, Duration warmup);

 private:
  uint64_t last_sequence_ = 0;
  uint64_t last_version_ = 0;
  std::optional<SteadyTime> first_presented_;
};

}  // namespace mostar::ui
