#include "operator_client/ui/motion_overlay.h"

#include <cmath>
#include <cstdio>

#include "operator_client/fusion/scan_resampling.h"

namespace mostar::ui {
namespace {

void ScaleAlpha(float scale, fusion::VertexArray* array) {
  for (size_t i = 3; i < array->colors.size(); i += 4) array->colors[i] *= scale;
}

}  // namespace

bool MotionOverlayOptions::IsValid(std::string* error) const {
  if (!(faded_alpha_scale > 0.f && faded_alpha_scale <= 1.f)) {
    *error = "faded_alpha_scale must be in (0, 1]";
    return false;
  }
  return compensation.IsValid(error);
}

MotionOverlayStatus BuildOverlayFeatures(const fusion::ArFeatureBuilder& builder,
                                         const LaserScan& scan, const fusion::MovedScan* moved,
                                         const MotionOverlayOptions& options,
                                         fusion::ArFeatures* features) {
  MotionOverlayStatus status;
  if (moved == nullptr) {
    builder.Build(scan, features);
    return status;
  }
  status.scan_age_ms = ToSeconds(moved->image_minus_scan) * 1e3;
  if (moved->moved && moved->points.size() == scan.ranges_m.size()) {
    builder.Build(scan, moved->points, features);
    status.moved = true;
    return status;
  }
  builder.Build(scan, features);
  FadeScanFeatures(options.faded_alpha_scale, features);
  status.faded = true;
  status.reason = moved->moved ? "scan and motion disagree" : moved->reason;
  return status;
}

vision::ScanPlacement PlaceScanForVision(const LaserScan& nearest, const fusion::MovedScan* moved,
                                         LaserScan* out) {
  vision::ScanPlacement placement;
  placement.measured_stamp = nearest.stamp;
  if (moved == nullptr) {
    *out = nearest;
    return placement;
  }
  if (!moved->moved) {
    *out = nearest;
    placement.reason = moved->reason;
    return placement;
  }
  if (!fusion::ResampleAtImageTime(nearest, *moved, out)) {
    placement.reason = "scan beams cannot be resampled";  // out: nearest as measured
    return placement;
  }
  placement.at_image_time = true;
  placement.extrapolated = moved->extrapolated;
  return placement;
}

MotionOverlayStatus BuildPlacedOverlayFeatures(const fusion::ArFeatureBuilder& builder,
                                               const LaserScan& scan,
                                               const vision::ScanPlacement& placement,
                                               Time image_stamp, bool compensate,
                                               const MotionOverlayOptions& options,
                                               fusion::ArFeatures* features) {
  MotionOverlayStatus status;
  builder.Build(scan, features);
  if (!compensate) return status;
  status.scan_age_ms = ToSeconds(image_stamp - placement.measured_stamp) * 1e3;
  if (placement.at_image_time) {
    status.moved = true;
    return status;
  }
  FadeScanFeatures(options.faded_alpha_scale, features);
  status.faded = true;
  status.reason =
      placement.reason.empty() ? "scan not moved to the image's time" : placement.reason;
  return status;
}

void FadeScanFeatures(float scale, fusion::ArFeatures* features) {
  ScaleAlpha(scale, &features->walls);
  ScaleAlpha(scale, &features->rays);
  ScaleAlpha(scale, &features->vertical_lines);
  ScaleAlpha(scale, &features->laser_points);
  for (fusion::DistanceLabel& label : features->labels) label.color.a *= scale;
}

std::string MotionOverlayNote(const MotionOverlayStatus& status) {
  if (!status.faded) return {};
  char text[200];
  std::snprintf(text, sizeof(text), "overlay faded: %s (scan %.0f ms %s the image)",
                status.reason.c_str(), std::abs(status.scan_age_ms),
                status.scan_age_ms >= 0 ? "before" : "after");
  return text;
}

}  // namespace mostar::ui
