// A scan as the laser would have measured it from where the robot stood at an image's capture
// time (issue 36, "vision on the image's time"): the beams moved by MoveScanToImageTime are
// resampled on the scan's own beam grid, so that code working per beam (edge processing's
// virtual rays, its laser double-check, the self-calibration) sees the scene from the camera's
// pose and can keep its per-beam caches.
//
// Frames and units as in motion_compensation.h: metres, radians counter-clockwise; the result is
// in the base frame at the image time (the laser frame there: in the scan plane they coincide).
#pragma once

#include "common/types/laser_scan.h"
#include "operator_client/fusion/motion_compensation.h"

namespace mostar::fusion {

// Two neighbouring moved points belong to one surface when they are at most
// max(kSurfaceGapMinM, kSurfaceGapPerRad * range * azimuth step) apart (range: the nearer
// point's). The second term admits walls seen at up to about 76 degrees of incidence; beyond
// that neighbouring points are taken for an occlusion edge and are not joined.
inline constexpr double kSurfaceGapMinM = 0.10;
inline constexpr double kSurfaceGapPerRad = 4.0;
// The smallest beam step resampled (no laser has finer steps than 0.25 degree).
inline constexpr double kMinIncrementRad = 1e-4;

// Resamples `scan`, moved into `moved` (MoveScanToImageTime's output for this scan with
// moved.moved true), onto the scan's beam grid seen from the base's origin at the image time.
// Target beam j (angle angle_min_rad + j * angle_increment_rad) takes:
//  1. the nearest crossing of its ray with a segment joining two neighbouring moved points of
//     one surface (exact for flat surfaces between them); else
//  2. the value of the moved beam whose azimuth is nearest to it, within half an increment:
//     that beam's distance from the new origin, or its NaN / +Inf (free or unknown space
//     keeps its direction, moved.azimuths_rad); else
//  3. NaN: no beam of the scan looked that way (the ends of the field of view after a turn).
// Intensities, when present, come from the beam nearest in azimuth (0 where none).
// `out` keeps the scan's grid, sequence, range limits and scan time; its stamp is the image's
// (scan.stamp + moved.image_minus_scan) and time_increment_s is 0: every beam is at that time.
// Returns false, and `out` holds `scan` unchanged, when `moved` is not moved or does not match
// the scan, or the scan's angle_min_rad is not finite or its increment not finite and at least
// kMinIncrementRad. Non-finite moved points (NaN odometry) place nothing.
bool ResampleAtImageTime(const LaserScan& scan, const MovedScan& moved, LaserScan* out);

}  // namespace mostar::fusion
