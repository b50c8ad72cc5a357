// The preview window: GLFW, an OpenGL 3.3+ core context and glad.
#include "render/preview/gl_window.h"

// glad first: it provides the GL declarations; GLFW must not include its own.
#include <glad/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <deque>
#include <mutex>

namespace firstshot {

namespace {

std::mutex gErrorMutex;
std::string gLastError;  // the last message of GLFW's error callback

void onGlfwError(int code, const char* description) {
  std::lock_guard<std::mutex> lock(gErrorMutex);
  gLastError = description ? description : "GLFW error " + std::to_string(code);
}

std::string lastGlfwError(const char* fallback) {
  std::lock_guard<std::mutex> lock(gErrorMutex);
  return gLastError.empty() ? fallback : gLastError;
}

/// InputEvent's key for a GLFW key, or 0 for keys the preview does not use.
int mapKey(int key) {
  if ((key >= GLFW_KEY_A && key <= GLFW_KEY_Z) || (key >= GLFW_KEY_0 && key <= GLFW_KEY_9)) return key;  // ASCII
  if (key >= GLFW_KEY_KP_0 && key <= GLFW_KEY_KP_9) return '0' + (key - GLFW_KEY_KP_0);
  switch (key) {
    case GLFW_KEY_ESCAPE: return InputEvent::kKeyEscape;
    case GLFW_KEY_KP_ADD: return '+';
    case GLFW_KEY_KP_SUBTRACT: return '-';
    case GLFW_KEY_F1: return InputEvent::kKeyF1;
    default: return 0;
  }
}

}  // namespace

struct GLWindow::Impl {
  GLFWwindow* window = nullptr;
  std::deque<InputEvent> events;

  static Impl& of(GLFWwindow* w) { return *static_cast<Impl*>(glfwGetWindowUserPointer(w)); }

  static void onKey(GLFWwindow* w, int key, int, int action, int mods) {
    if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
    const int k = mapKey(key);
    // Letters repeat only for flying (handled by polling), so report presses only.
    if (k == 0 || (action == GLFW_REPEAT && k != '+' && k != '-')) return;
    InputEvent e;
    e.type = InputEvent::Type::Key;
    e.key = k;
    e.shift = (mods & GLFW_MOD_SHIFT) != 0;
    of(w).events.push_back(e);
  }
  static void onChar(GLFWwindow* w, unsigned int codepoint) {
    // '+' and '-' as typed (any layout); '=' shares the '+' key on US keyboards. Everything else comes from onKey.
    if (codepoint != '+' && codepoint != '-' && codepoint != '=') return;
    InputEvent e;
    e.type = InputEvent::Type::Key;
    e.key = codepoint == '-' ? '-' : '+';
    of(w).events.push_back(e);
  }
  static void onMouseButton(GLFWwindow* w, int button, int action, int mods) {
    InputEvent e;
    e.type = action == GLFW_PRESS ? InputEvent::Type::MouseDown : InputEvent::Type::MouseUp;
    e.button = button == GLFW_MOUSE_BUTTON_LEFT ? 0 : button == GLFW_MOUSE_BUTTON_RIGHT ? 1 : 2;
    e.shift = (mods & GLFW_MOD_SHIFT) != 0;
    of(w).events.push_back(e);
  }
  static void onCursor(GLFWwindow* w, double x, double y) {
    InputEvent e;
    e.type = InputEvent::Type::MouseMove;
    e.x = x, e.y = y;
    of(w).events.push_back(e);
  }
  static void onScroll(GLFWwindow* w, double dx, double dy) {
    InputEvent e;
    e.type = InputEvent::Type::Scroll;
    e.x = dx, e.y = dy;
    of(w).events.push_back(e);
  }
};

GLWindow::GLWindow(int width, int height, const std::string& title) : impl_(std::make_unique<Impl>()) {
  glfwSetErrorCallback(onGlfwError);
  // GLFW stays initialised until the process exits (no glfwTerminate): closing its X display
  // unloads Mesa's driver (dlclose), which turns the driver's one-time allocations into
  // unreachable "leaks" under LeakSanitizer. Calling glfwInit again is a no-op.
  if (!glfwInit()) throw DisplayError(lastGlfwError("glfwInit failed"));
  auto fail = [&](const char* fallback) {
    const std::string msg = lastGlfwError(fallback);
    if (impl_->window) glfwDestroyWindow(impl_->window);
    impl_->window = nullptr;
    throw DisplayError(msg);
  };
  if (const GLFWvidmode* mode = glfwGetPrimaryMonitor() ? glfwGetVideoMode(glfwGetPrimaryMonitor()) : nullptr) {
    // Keep the aspect ratio when the image is larger than the screen.
    const double s = std::min({1.0, double(mode->width) / width, double(mode->height) / height});
    width = std::max(1, int(width * s)), height = std::max(1, int(height * s));
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SRGB_CAPABLE, GLFW_FALSE);  // the display shader applies the sRGB curve itself
  impl_->window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!impl_->window) fail("could not create a window with an OpenGL 3.3 core context");
  glfwMakeContextCurrent(impl_->window);
  if (gladLoadGL(glfwGetProcAddress) == 0) fail("could not load the OpenGL functions");
  glfwSetWindowUserPointer(impl_->window, impl_.get());
  glfwSetKeyCallback(impl_->window, Impl::onKey);
  glfwSetCharCallback(impl_->window, Impl::onChar);
  glfwSetMouseButtonCallback(impl_->window, Impl::onMouseButton);
  glfwSetCursorPosCallback(impl_->window, Impl::onCursor);
  glfwSetScrollCallback(impl_->window, Impl::onScroll);
}

GLWindow::~GLWindow() {
  if (impl_->window) glfwDestroyWindow(impl_->window);  // GLFW itself stays initialised (see the constructor)
}

void GLWindow::pollEvents(double timeout) {
  if (timeout > 0)
    glfwWaitEventsTimeout(timeout);
  else
    glfwPollEvents();
}

bool GLWindow::nextEvent(InputEvent& event) {
  if (impl_->events.empty()) return false;
  event = impl_->events.front();
  impl_->events.pop_front();
  return true;
}

bool GLWindow::keyDown(int key) const { return glfwGetKey(impl_->window, key) == GLFW_PRESS; }
bool GLWindow::shouldClose() const { return glfwWindowShouldClose(impl_->window); }
void GLWindow::requestClose() { glfwSetWindowShouldClose(impl_->window, GLFW_TRUE); }
void GLWindow::swapBuffers() { glfwSwapBuffers(impl_->window); }
void GLWindow::setSwapInterval(int interval) { glfwSwapInterval(interval); }
void GLWindow::setTitle(const std::string& title) { glfwSetWindowTitle(impl_->window, title.c_str()); }
void GLWindow::framebufferSize(int& width, int& height) const { glfwGetFramebufferSize(impl_->window, &width, &height); }
double GLWindow::time() const { return glfwGetTime(); }

std::string GLWindow::description() const {
  auto str = [](GLenum e) {
    const auto* s = reinterpret_cast<const char*>(glGetString(e));
    return std::string(s ? s : "?");
  };
  return str(GL_RENDERER) + ", OpenGL " + str(GL_VERSION);
}

}  // namespace firstshot
