// Dear ImGui on a GLFW window with the OpenGL 3 backend (backends compiled from the sources
// that libimgui-dev ships). One per window; render thread only.
#pragma once

struct GLFWwindow;

namespace mostar::ui {

class ImGuiLayer {
 public:
  explicit ImGuiLayer(GLFWwindow* window);
  ~ImGuiLayer();
  ImGuiLayer(const ImGuiLayer&) = delete;
  ImGuiLayer& operator=(const ImGuiLayer&) = delete;

  void BeginFrame();
  void EndFrame();  // renders the draw data into the current framebuffer
  // True when ImGui wants the keyboard (a text field has focus): driving keys are ignored then.
  bool WantsKeyboard() const;
};

}  // namespace mostar::ui
