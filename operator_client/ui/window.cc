#include "operator_client/ui/window.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>

#include "common/log/log.h"
#include "operator_client/render/gl.h"

namespace mostar::ui {

namespace {
std::string g_last_glfw_error;
void OnGlfwError(int code, const char* description) {
  g_last_glfw_error = std::string(description) + " (GLFW error " + std::to_string(code) + ")";
}

GLFWwindow* TryCreate(const WindowOptions& options, bool stereo) {
  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_STEREO, stereo ? GLFW_TRUE : GLFW_FALSE);
  return glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
}
}  // namespace

std::unique_ptr<Window> Window::Create(const WindowOptions& options, std::string* error) {
  glfwSetErrorCallback(OnGlfwError);
  if (!glfwInit()) {
    *error = "cannot initialise GLFW: " + g_last_glfw_error +
             " (no display? run under xvfb-run, or use a machine with X11)";
    return nullptr;
  }
  std::unique_ptr<Window> window(new Window());
  if (options.request_quad_buffer) {
    window->window_ = TryCreate(options, true);
    if (window->window_ != nullptr) {
      window->quad_buffer_ = true;
    } else {
      MOSTAR_LOG(WARNING) << "quad-buffer stereo is not offered by this OpenGL driver ("
                          << g_last_glfw_error << "); falling back to a mono framebuffer";
    }
  }
  if (window->window_ == nullptr) window->window_ = TryCreate(options, false);
  if (window->window_ == nullptr) {
    *error = "cannot create an OpenGL 3.3 core window: " + g_last_glfw_error;
    glfwTerminate();
    return nullptr;
  }
  glfwMakeContextCurrent(window->window_);
  // A visible window never tears while frames are in time: adaptive vertical sync where the
  // driver offers it (a late frame is shown at once), else plain vertical sync.
  const bool adaptive = glfwExtensionSupported("GLX_EXT_swap_control_tear") == GLFW_TRUE ||
                        glfwExtensionSupported("WGL_EXT_swap_control_tear") == GLFW_TRUE;
  window->swap_interval_ = !options.visible ? 0 : adaptive ? -1 : 1;
  glfwSwapInterval(window->swap_interval_);
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  window->renderer_ =
      std::string(renderer ? renderer : "?") + ", OpenGL " + (version ? version : "?");
  return window;
}

Window::~Window() {
  if (window_ != nullptr) glfwDestroyWindow(window_);
  glfwTerminate();
}

bool Window::ShouldClose() const { return glfwWindowShouldClose(window_); }
void Window::RequestClose() { glfwSetWindowShouldClose(window_, GLFW_TRUE); }
void Window::SwapBuffers() { glfwSwapBuffers(window_); }
void Window::PollEvents() { glfwPollEvents(); }
void Window::WaitEvents(Duration timeout) {
  glfwWaitEventsTimeout(std::max(ToSeconds(timeout), 0.0));
}
void Window::WakeUp() { glfwPostEmptyEvent(); }
bool Window::GamepadPresent() { return glfwJoystickIsGamepad(GLFW_JOYSTICK_1) == GLFW_TRUE; }
void Window::FramebufferSize(int* width, int* height) const {
  glfwGetFramebufferSize(window_, width, height);
}
void Window::SetSize(int width, int height) { glfwSetWindowSize(window_, width, height); }

}  // namespace mostar::ui
