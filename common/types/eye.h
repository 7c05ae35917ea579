// The two eyes of the stereo rig: the one Eye enum of the code base (images, camera models,
// viewports, intrinsics).
#pragma once

namespace mostar {

enum class Eye { kLeft = 0, kRight = 1 };

inline const char* EyeName(Eye eye) { return eye == Eye::kLeft ? "left" : "right"; }

}  // namespace mostar
