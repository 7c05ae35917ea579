// A GLFW window with an OpenGL 3.3 core context. Hidden windows serve the headless mode (they
// still need an X server: run under xvfb-run where no display exists).
#pragma once

#include <memory>
#include <string>

#include "common/time/time.h"

struct GLFWwindow;

namespace mostar::ui {

struct WindowOptions {
  int width = 640;
  int height = 480;
  std::string title = "mostar operator";
  bool visible = true;
  bool request_quad_buffer = false;  // ask for a stereo (quad-buffer) framebuffer
};

class Window {
 public:
  // Null with a clear message when GLFW or the context cannot be created (no display, no
  // OpenGL 3.3). When a quad-buffer context is refused, a normal one is created and
  // quad_buffer() is false.
  static std::unique_ptr<Window> Create(const WindowOptions& options, std::string* error);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  bool ShouldClose() const;
  void RequestClose();
  void SwapBuffers();
  static void PollEvents();
  // Waits for an input event, WakeUp() or `timeout`, then handles the events that came.
  static void WaitEvents(Duration timeout);
  // Ends a WaitEvents() at once; callable from any thread.
  static void WakeUp();
  // A gamepad is connected (it is polled: its sticks send no events).
  static bool GamepadPresent();
  // 1: swaps wait for the display's vertical blank; -1: adaptive (they wait unless the frame
  // is late, then tear once rather than wait a whole refresh); 0: never wait (hidden window).
  int swap_interval() const { return swap_interval_; }
  void FramebufferSize(int* width, int* height) const;
  void SetSize(int width, int height);
  bool quad_buffer() const { return quad_buffer_; }
  std::string renderer() const { return renderer_; }
  GLFWwindow* get() const { return window_; }

 private:
  Window() = default;
  GLFWwindow* window_ = nullptr;
  bool quad_buffer_ = false;
  int swap_interval_ = 0;
  std::string renderer_;
};

}  // namespace mostar::ui
