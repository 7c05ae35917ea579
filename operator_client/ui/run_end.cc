#include "operator_client/ui/run_end.h"

namespace mostar::ui {

RunEnd CheckRunEnd(const RunLimits& limits, bool captured, uint64_t rendered_pairs,
                   Duration elapsed) {
  if (captured) return RunEnd::kCaptured;
  if (limits.max_frames > 0 && rendered_pairs >= limits.max_frames) return RunEnd::kFrames;
  if (limits.max_duration > Duration::zero() && elapsed > limits.max_duration) {
    return RunEnd::kDuration;
  }
  return RunEnd::kRunning;
}

bool CaptureAfterDue(int capture_after, bool capturing, uint64_t pairs_decoded) {
  return capture_after >= 0 && !capturing && pairs_decoded >= static_cast<uint64_t>(capture_after);
}

ScreenshotPlan PlanScreenshot(const std::string& path, bool capture, bool captured,
                              bool capture_stamp_latched, bool have_frame) {
  ScreenshotPlan plan;
  if (capture && !captured) {
    plan.problem = std::string("the pair to capture was not rendered") +
                   (capture_stamp_latched ? " (its scans or edge result did not arrive)"
                                          : " (it did not arrive)") +
                   "; no screenshot written";
    plan.exit_status = 1;
    return plan;
  }
  if (path.empty()) return plan;
  if (!have_frame) {
    plan.problem = "no video frame was rendered; no screenshot written";
    return plan;
  }
  plan.write = true;
  return plan;
}

}  // namespace mostar::ui
