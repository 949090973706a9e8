// The GLFW window and its context (window.hpp).
#include "window.hpp"

#include "gl.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cstdlib>

namespace radiosity::view {

namespace {
std::string glfw_reason;  // the last error GLFW reported (it reports from inside its calls)

void on_glfw_error(int, const char* description) {
    glfw_reason = description ? description : "unknown GLFW error";
}

std::string no_window(const std::string& what) {
    const char* display = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    std::string hint;
    if ((display == nullptr || *display == '\0') && (wayland == nullptr || *wayland == '\0'))
        hint = " (no display: DISPLAY is not set; without a screen run it under xvfb-run -a)";
    return what + ": " + (glfw_reason.empty() ? "no reason given" : glfw_reason) + hint;
}
}  // namespace

Window::Window(int width, int height, const std::string& title, bool visible) {
    glfwSetErrorCallback(on_glfw_error);
    if (glfwInit() != GLFW_TRUE) throw WindowError(no_window("cannot start GLFW"));
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
    window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (window_ == nullptr) {
        const std::string message = no_window("cannot open an OpenGL 3.3 core window");
        glfwTerminate();
        throw WindowError(message);
    }
    // Installed before the panels' backend, which calls it on from its own callback.
    glfwSetWindowUserPointer(window_, this);
    glfwSetKeyCallback(window_, on_key);
    glfwMakeContextCurrent(window_);
    if (visible) glfwSwapInterval(1);
    gl::check("creating the context");
}

Window::~Window() {
    glfwDestroyWindow(window_);
    glfwTerminate();
}

bool Window::should_close() const {
    return glfwWindowShouldClose(window_) == GLFW_TRUE;
}

void Window::request_close() {
    glfwSetWindowShouldClose(window_, GLFW_TRUE);
}

void Window::swap() {
    glfwSwapBuffers(window_);
}

void Window::poll(double timeout) {
    if (timeout > 0.0)
        glfwWaitEventsTimeout(timeout);
    else
        glfwPollEvents();
}

std::pair<int, int> Window::framebuffer_size() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    return {w, h};
}

void Window::on_key(GLFWwindow* window, int key, int, int action, int) {
    auto* self = static_cast<Window*>(glfwGetWindowUserPointer(window));
    if (self != nullptr && (action == GLFW_PRESS || action == GLFW_REPEAT))
        self->presses_.push_back(key);
}

std::vector<int> Window::take_key_presses() {
    return std::exchange(presses_, {});
}

bool Window::key_down(int key) const {
    return glfwGetKey(window_, key) == GLFW_PRESS;
}

std::string Window::renderer() const {
    const auto* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const auto* v = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    return std::string(r ? r : "?") + ", OpenGL " + (v ? v : "?");
}

}  // namespace radiosity::view
