// When the console's render loop ends by itself, and what the end of a run writes: pure rules
// behind operator_client's --frames, --duration, --capture-stamp/--capture-after and
// --screenshot (the loop's other ends, a signal, the window closed, a new address, are events).
#pragma once

#include <cstdint>
#include <string>

#include "common/time/time.h"

namespace mostar::ui {

struct RunLimits {
  uint64_t max_frames = 0;  // rendered pairs; 0: no limit
  Duration max_duration{};  // since the loop started; zero: no limit
};

enum class RunEnd { kRunning, kCaptured, kFrames, kDuration };

// kCaptured once the pair to capture is rendered, else the first limit reached, else kRunning.
RunEnd CheckRunEnd(const RunLimits& limits, bool captured, uint64_t rendered_pairs,
                   Duration elapsed);

// --capture-after N (negative: not asked): due once N pairs are decoded and no capture is armed.
bool CaptureAfterDue(int capture_after, bool capturing, uint64_t pairs_decoded);

// The screenshot at the end of a run: written when a path is given and there is a frame, and,
// when a capture was asked for, only if its pair was rendered (else the run fails: status 1).
struct ScreenshotPlan {
  bool write = false;
  std::string problem;  // for stderr when not writing for a reason the user should know
  int exit_status = 0;
};
ScreenshotPlan PlanScreenshot(const std::string& path, bool capture, bool captured,
                              bool capture_stamp_latched, bool have_frame);

}  // namespace mostar::ui
