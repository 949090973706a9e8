#pragma once
/// @file ui.hpp  Dear ImGui on the viewer's window: the context and the GLFW and OpenGL 3
/// backends (Debian's libimgui.a holds both), set up and torn down together.

#include <glm/vec2.hpp>

#include <optional>

struct GLFWwindow;

namespace radiosity::view {

/// The ImGui context of one window (no imgui.ini is read or written).
class Ui {
  public:
    /// Sets up ImGui on the window (whose OpenGL context is current); throws gl::Error if a
    /// backend cannot start.
    explicit Ui(GLFWwindow* window);
    ~Ui();
    Ui(const Ui&) = delete;
    Ui& operator=(const Ui&) = delete;

    /// Starts a frame. `size`: a fixed display size in pixels (headless pictures), instead of
    /// the window's.
    void begin_frame(std::optional<glm::ivec2> size = std::nullopt);
    /// Ends the frame and draws it into the framebuffer bound now.
    void end_frame();
};

}  // namespace radiosity::view
