#pragma once
/// @file window.hpp  The window and its OpenGL 3.3 core context (GLFW), visible for the
/// interactive viewer or hidden for headless pictures, which draw into a framebuffer object of
/// their own and need the window only for its context.

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

struct GLFWwindow;

namespace radiosity::view {

/// No window or no OpenGL 3.3 core context could be had (no display, too old a driver); the
/// message says which and what to try.
class WindowError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// A GLFW window with a current OpenGL 3.3 core context (swap interval 1 when visible).
class Window {
  public:
    /// Opens the window; throws WindowError with GLFW's reason if it cannot.
    Window(int width, int height, const std::string& title, bool visible);
    ~Window();
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;

    GLFWwindow* handle() const { return window_; }  ///< for the ImGui backend
    bool should_close() const;                      ///< closed by the user
    void request_close();                           ///< asks the main loop to end
    void swap();                                    ///< shows the frame just drawn
    /// Processes pending events; waits up to timeout seconds for one when timeout > 0.
    void poll(double timeout = 0.0);
    std::pair<int, int> framebuffer_size() const;  ///< drawable size in pixels
    /// The OpenGL renderer and version strings, for messages.
    std::string renderer() const;
    /// The keys pressed (or repeated) since the last call, in order (GLFW key codes). Kept from
    /// GLFW's callback, so that a press shorter than a frame is not lost.
    std::vector<int> take_key_presses();
    /// Whether the key is held down now.
    bool key_down(int key) const;

  private:
    static void on_key(GLFWwindow* window, int key, int scancode, int action, int mods);

    GLFWwindow* window_ = nullptr;
    std::vector<int> presses_;
};

}  // namespace radiosity::view
