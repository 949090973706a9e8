// Dear ImGui on the viewer's window (ui.hpp).
#include "ui.hpp"

#include "gl.hpp"

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

namespace radiosity::view {

Ui::Ui(GLFWwindow* window) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;
    ImGui::StyleColorsDark();
    if (!ImGui_ImplGlfw_InitForOpenGL(window, true) || !ImGui_ImplOpenGL3_Init("#version 330")) {
        ImGui::DestroyContext();
        throw gl::Error("Dear ImGui's GLFW or OpenGL 3 backend did not start");
    }
}

Ui::~Ui() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
}

void Ui::begin_frame(std::optional<glm::ivec2> size) {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    if (size) {
        ImGuiIO& io = ImGui::GetIO();
        io.DisplaySize = ImVec2(float(size->x), float(size->y));
        io.DisplayFramebufferScale = ImVec2(1.0f, 1.0f);
    }
    ImGui::NewFrame();
}

void Ui::end_frame() {
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    gl::check("drawing the panels");
}

}  // namespace radiosity::view
