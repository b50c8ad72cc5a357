#pragma once
/// @file gl_window.h
/// The preview's one window and OpenGL context (GLFW, OpenGL 3.3+ core, functions loaded with glad).
/// This is the only class that knows GLFW; input reaches the application as InputEvent values.
#include <memory>
#include <stdexcept>
#include <string>

namespace firstshot {

/// No display: glfwInit or window creation failed. The message carries GLFW's reason.
class DisplayError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One input event. Keys are reported as characters: 'A'..'Z' and '0'..'9' for those keys
/// (whatever the modifiers), '+' and '-' from the typed text or the keypad, kKeyEscape for Esc.
struct InputEvent {
  enum class Type { Key, MouseDown, MouseUp, MouseMove, Scroll };
  static constexpr int kKeyEscape = 27;
  static constexpr int kKeyF1 = 0x100;

  Type type = Type::Key;
  int key = 0;          ///< Key: the character (see above)
  int button = 0;       ///< MouseDown/Up: 0 left, 1 right, 2 middle
  bool shift = false;   ///< Shift held (Key, MouseDown)
  double x = 0, y = 0;  ///< MouseMove: cursor position in window coordinates; Scroll: offsets
};

class GLWindow {
 public:
  /// Opens a visible window of @p width × @p height screen coordinates (clamped to the monitor)
  /// with an OpenGL 3.3+ core context current on the calling thread.
  /// @throws DisplayError when there is no display or no suitable context.
  GLWindow(int width, int height, const std::string& title);
  ~GLWindow();
  GLWindow(const GLWindow&) = delete;
  GLWindow& operator=(const GLWindow&) = delete;

  /// Collects pending events; with @p timeout > 0 waits up to that many seconds for one.
  void pollEvents(double timeout = 0.0);
  /// Takes the next collected event; false when there is none left.
  bool nextEvent(InputEvent& event);
  /// True while key @p key (a letter or digit, as in InputEvent) is held down.
  bool keyDown(int key) const;
  bool shouldClose() const;
  void requestClose();
  void swapBuffers();
  /// Vertical sync on (1) or off (0).
  void setSwapInterval(int interval);
  void setTitle(const std::string& title);
  /// Size of the default framebuffer in pixels.
  void framebufferSize(int& width, int& height) const;
  /// GL_RENDERER and GL_VERSION.
  std::string description() const;
  /// Seconds since the window was opened.
  double time() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace firstshot
