// The edge view (V, thesis fig. 29): either eye's contrast-stretched grey image and its edges
// from the shown edge result, the edge thresholds (edgeTh with stereoTh following it as
// edgeTh / 2 unless set on its own, VisionSettings), their save/load beside the calibration
// profile, and the edge processing switch. ImGui and OpenGL (owns the two textures); render
// thread.
#pragma once

#include <optional>
#include <string>

#include "common/types/eye.h"
#include "operator_client/render/texture.h"
#include "operator_client/ui/vision_settings.h"
#include "operator_client/vision/vision_pipeline.h"

namespace mostar::ui {

class EdgeViewPanel {
 public:
  // Draws the panel. `result`: the shown pair's edge result (null: none). `settings`: the
  // settings in force (not changed here). `settings_path`: where Save writes and Load reads.
  // `open` is cleared when the operator closes the panel; `vision_enabled` is the processing
  // switch; `status_line` gets save/load outcomes and refused edits. Returns the settings to hand
  // to the edge worker when a threshold moved or a file was loaded (the caller keeps them if
  // the worker accepts them).
  std::optional<VisionSettings> Draw(const vision::VisionResult* result,
                                     const VisionSettings& settings,
                                     const std::string& settings_path, bool* open,
                                     bool* vision_enabled, std::string* status_line);

 private:
  render::Texture grey_;
  render::Texture edges_;
  Eye eye_ = Eye::kLeft;
};

}  // namespace mostar::ui
