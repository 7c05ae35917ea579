// The edge view (V, thesis fig. 29): the left eye's contrast-stretched grey image and its
// edges from the shown edge result, the edge thresholds and the edge processing switch.
// ImGui and OpenGL (owns the two textures); render thread.
#pragma once

#include <optional>

#include "operator_client/render/texture.h"
#include "operator_client/vision/vision_pipeline.h"

namespace mostar::ui {

class EdgeViewPanel {
 public:
  // Draws the panel. `result`: the shown pair's edge result (null: none). `options`: the
  // options in force; the integer thresholds are edited in place. `open` is cleared when the
  // operator closes the panel; `vision_enabled` is the processing switch. Returns the options
  // to hand to the edge worker when a threshold moved (the caller keeps them if it accepts).
  std::optional<vision::VisionOptions> Draw(const vision::VisionResult* result,
                                            vision::VisionOptions* options, bool* open,
                                            bool* vision_enabled);

 private:
  render::Texture grey_;
  render::Texture edges_;
};

}  // namespace mostar::ui
