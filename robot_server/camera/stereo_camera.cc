#include "robot_server/camera/stereo_camera.h"

namespace mostar::camera {

const char* GrabStatusName(GrabStatus status) {
  switch (status) {
    case GrabStatus::kOk:
      return "ok";
    case GrabStatus::kTimeout:
      return "timeout";
    case GrabStatus::kDeviceLost:
      return "device lost";
    case GrabStatus::kEndOfStream:
      return "end of stream";
    case GrabStatus::kNotOpen:
      return "not open";
  }
  return "?";
}

}  // namespace mostar::camera
