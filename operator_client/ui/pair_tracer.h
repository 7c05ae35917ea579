// Stamps the path of each shown stereo pair through this client on the robot's clock, for the
// LatencyTrace: received and decoded (from the receiver), picked (when the render loop first
// took it), vision, drawn and presented (from the frame that showed it). Pure: the clocks come in
// as arguments.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <utility>

#include "common/time/time.h"
#include "common/timesync/clock_offset_estimator.h"
#include "common/types/stereo_frame.h"
#include "operator_client/ui/latency_trace.h"

namespace mostar::ui {

// Maps instants of this machine's monotonic clock to the robot's clock: through this machine's
// wall clock read at one moment (`now` and `steady_now` read together), then the estimated
// offset to the robot when it is known (else this machine's wall clock is used as is).
class RobotTimeMapper {
 public:
  RobotTimeMapper(Time now, SteadyTime steady_now, const timesync::ClockOffsetEstimate& offset)
      : now_(now), steady_now_(steady_now), offset_(offset) {}
  Time operator()(SteadyTime t) const;

 private:
  Time now_;
  SteadyTime steady_now_;
  timesync::ClockOffsetEstimate offset_;
};

// What the client knows of a shown pair.
struct ShownPairStamps {
  uint64_t sequence = 0;      // the receiver's decoded-pair counter
  Time capture;               // robot clock
  SteadyTime received;        // both eyes here (this machine)
  SteadyTime decode_started;  // the decoder thread took it (this machine)
  SteadyTime decoded;         // both eyes decoded (this machine)
};

// The frame that showed the pair, on this machine's monotonic clock.
struct ShowingFrame {
  // With edge processing on: when the pair could be shown (its result published, or its result
  // wait ran out: FramePicker::shown_ready_at).
  SteadyTime ready;
  SteadyTime start;      // the frame began drawing
  SteadyTime drawn;      // images, overlay and panels drawn
  SteadyTime presented;  // swapped and finished
};

class PairTracer {
 public:
  // The render loop took pair `sequence` from the receiver at `at`; only the first time counts.
  // Remembers the last kRemembered pairs.
  void Picked(uint64_t sequence, SteadyTime at);
  static constexpr size_t kRemembered = 16;

  // The timeline of `pair` shown by `frame`. `robot_side`: the robot's encode and write stamps
  // when known. With edge processing off the vision stage takes no time (it ends when the pair
  // was picked); with it on, it ends at `frame.ready`, never before the pick.
  PairTimeline Timeline(const ShownPairStamps& pair, const std::optional<FrameTiming>& robot_side,
                        const ShowingFrame& frame, bool vision_enabled,
                        const RobotTimeMapper& to_robot) const;

 private:
  std::deque<std::pair<uint64_t, SteadyTime>> picked_;  // (sequence, first taken), oldest first
};

}  // namespace mostar::ui
