// Pairs the two eyes' JPEG images by capture stamp without decoding them: mostar_web forwards
// the robot's JPEG bytes unchanged. Pure: no DDS, no sockets, no threads.
//
// An image waits for its partner (same stamp) among the last kMaxPending of its eye; older ones
// are dropped and counted as unpaired. A pair older than the last one emitted is refused as late
// (the robot keeps several pairs in flight), so pairs come out in capture order.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>

#include "common/types/stereo_frame.h"

namespace mostar::web {

struct EyePairerStats {
  uint64_t images = 0;    // images pushed (both eyes)
  uint64_t pairs = 0;     // pairs emitted
  uint64_t unpaired = 0;  // images whose partner never came (pushed out of the window)
  uint64_t late = 0;      // pairs completed after a newer one was emitted: dropped
};

class EyePairer {
 public:
  static constexpr size_t kMaxPending = 4;  // per eye

  // The completed pair when `image` finds its partner, else nullopt. `sequence` of the pair
  // counts the pairs emitted (1, 2, ...).
  std::optional<CompressedStereoPair> Push(Eye eye, CompressedImage image);
  const EyePairerStats& stats() const { return stats_; }

 private:
  std::deque<CompressedImage> pending_[2];  // by Eye, oldest first
  std::optional<Time> last_emitted_;
  EyePairerStats stats_;
};

}  // namespace mostar::web
