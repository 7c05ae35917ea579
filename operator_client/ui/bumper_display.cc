#include "operator_client/ui/bumper_display.h"

#include <cmath>

namespace mostar::ui {
namespace {

// "front (0), front-left (2)" for the set bits of `mask`.
std::string SegmentList(uint32_t mask, int count) {
  std::string out;
  for (int i = 0; i < count; ++i) {
    if ((mask & (1u << i)) == 0) continue;
    if (!out.empty()) out += ", ";
    out += std::string(SegmentDirection(i, count)) + " (" + std::to_string(i) + ")";
  }
  return out;
}

}  // namespace

const char* SegmentDirection(int i, int count) {
  static const char* const kNames[8] = {"front", "front-left", "left",  "rear-left",
                                        "rear",  "rear-right", "right", "front-right"};
  if (count <= 0) return kNames[0];
  const double eighths = 8.0 * static_cast<double>(i) / count;  // counter-clockwise from ahead
  const int k = static_cast<int>(std::lround(eighths)) % 8;
  return kNames[(k + 8) % 8];
}

BumperView ViewBumpers(const std::optional<BumperState>& state, SteadyTime received,
                       SteadyTime now) {
  BumperView view;
  if (!state || state->segment_count <= 0) return view;
  const int count = std::min(state->segment_count, 32);
  const uint32_t mask = count == 32 ? ~0u : ((1u << count) - 1);
  const uint32_t pressed = state->pressed & mask;
  const uint32_t latched = state->latched & mask;
  view.segments.resize(count, SegmentLook::kIdle);
  for (int i = 0; i < count; ++i) {
    if (pressed & (1u << i)) {
      view.segments[i] = SegmentLook::kPressed;
    } else if (latched & (1u << i)) {
      view.segments[i] = SegmentLook::kLatched;
    }
  }
  view.stale = now - received > kBumperStaleAfter;
  view.alert = pressed != 0 || latched != 0 || !state->readable;
  view.flash_on = (now.time_since_epoch() / std::chrono::milliseconds(250)) % 2 == 0;
  if (!state->readable) {
    view.status = "BUMPERS UNREADABLE: the robot stays stopped";
  } else if (pressed != 0) {
    view.status = "BUMPER CONTACT: " + SegmentList(pressed, count) + " - robot stopped";
  } else if (latched != 0) {
    view.status = "BUMPER HIT: " + SegmentList(latched, count) +
                  " - stopped until the pilot re-arms (deadman up, then down)";
  }
  if (view.stale && !view.status.empty()) view.status += " (no bumper state for 3 s)";
  return view;
}

}  // namespace mostar::ui
