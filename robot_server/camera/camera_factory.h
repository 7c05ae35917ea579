// Builds cameras and pipeline options from CameraConfig (camera_config.proto). For wiring code
// (server main); the SIM and REPLAY backends are not built here (the simulator and
// robot_server/replay provide them).
#pragma once

#include <memory>
#include <string>

#include "common/time/time.h"
#include "robot_server/camera/camera_config.pb.h"
#include "robot_server/camera/camera_pipeline.h"
#include "robot_server/camera/stereo_camera.h"

namespace mostar::camera {

// Checks what ranges cannot: consistent qualities and scales, a source for FILE, a file for
// REPLAY, known bitrate class names. False with "<key>: <reason>".
bool ValidateCameraConfig(const CameraConfig& config, std::string* error);

// The camera of `config.backend()`; null with a reason for SIM and REPLAY, for DC1394 when the
// build has no libdc1394, or for an invalid config. `clock` stamps frames (not owned).
std::unique_ptr<StereoCamera> MakeStereoCamera(const CameraConfig& config, const Clock* clock,
                                               std::string* error);

// Pipeline options (timeouts, JPEG, bitrate classes; the initial target is the target of
// `bitrate.initial_class`).
CameraPipelineOptions MakePipelineOptions(const CameraConfig& config);

}  // namespace mostar::camera
