// The OpenGL renderer (renderer.hpp).
#include "renderer.hpp"

#include <radiosity/geometry/raster.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace radiosity::view {

namespace {

const char* surface_vertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 colour;
uniform mat4 clip;
out vec3 vertex_colour;
void main() {
    gl_Position = clip * vec4(position, 1.0);
    vertex_colour = colour;
}
)";

// The sRGB curve of shading/tonemap.hpp (IEC 61966-2-1), after the exposure.
const char* surface_fragment = R"(#version 330 core
in vec3 vertex_colour;
uniform usamplerBuffer triangle_patch;
uniform samplerBuffer patch_value;
uniform bool smooth_shading;
uniform bool exposed;
uniform float scale;
uniform int highlight;
uniform vec3 highlight_colour;
layout(location = 0) out vec4 display;
layout(location = 1) out vec4 linear_value;
layout(location = 2) out uint patch_id;
float srgb(float x) {
    x = clamp(x, 0.0, 1.0);
    return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}
void main() {
    uint owner = texelFetch(triangle_patch, gl_PrimitiveID).r;
    vec3 value = smooth_shading ? vertex_colour : texelFetch(patch_value, int(owner)).rgb;
    vec3 shown = exposed ? value * scale : value;
    display = vec4(srgb(shown.r), srgb(shown.g), srgb(shown.b), 1.0);
    if (int(owner) == highlight) display = vec4(highlight_colour, 1.0);
    linear_value = vec4(value, 1.0);
    patch_id = owner + 1u;
}
)";

const char* edge_vertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 clip;
uniform vec3 eye;
out float facing;
void main() {
    gl_Position = clip * vec4(position, 1.0);
    facing = dot(normal, eye - position);  // linear along the edge, so exact when interpolated
}
)";

// Edges of patches seen from behind are culled, as their triangles are.
const char* edge_fragment = R"(#version 330 core
in float facing;
uniform vec3 colour;
layout(location = 0) out vec4 display;
void main() {
    if (facing <= 0.0) discard;
    display = vec4(colour, 1.0);
}
)";

GLint uniform(GLuint program, const char* name) {
    return glGetUniformLocation(program, name);
}

/// clip = projection * view, in the frame whose origin is the scene's centre.
glm::mat4 clip_matrix(const radiosity::Camera& c, const glm::dvec3& origin, double radius,
                      double aspect) {
    const glm::dvec3 eye = c.eye - origin;
    const double distance = glm::length(eye);
    const double far = distance + 1.01 * radius;
    const double near = std::max(far * 1e-4, distance - 1.01 * radius);
    const glm::dmat4 view = glm::lookAt(eye, c.target - origin, c.up);
    return glm::mat4(
        radiosity::perspective(c.fov_y_degrees * std::numbers::pi / 180.0, aspect, near, far) *
        view);
}

void attach(GLuint texture, GLenum attachment, GLenum internal, GLenum format, GLenum type,
            int width, int height) {
    glBindTexture(GL_TEXTURE_2D, texture);
    glTexImage2D(GL_TEXTURE_2D, 0, static_cast<GLint>(internal), width, height, 0, format, type,
                 nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glFramebufferTexture2D(GL_FRAMEBUFFER, attachment, GL_TEXTURE_2D, texture, 0);
}

}  // namespace

Renderer::Renderer()
    : surfaces_(gl::program(surface_vertex, surface_fragment, "surface")),
      edges_(gl::program(edge_vertex, edge_fragment, "edge")),
      framebuffer_(gl::make_framebuffer()),
      display_(gl::make_texture()),
      linear_(gl::make_texture()),
      ids_(gl::make_texture()),
      depth_(gl::make_texture()) {
    glUseProgram(surfaces_.get());
    glUniform1i(uniform(surfaces_.get(), "triangle_patch"), 0);
    glUniform1i(uniform(surfaces_.get(), "patch_value"), 1);
    glUseProgram(0);
    gl::check("making the renderer");
}

void Renderer::resize(int width, int height) {
    width = std::max(width, 1);
    height = std::max(height, 1);
    if (width == width_ && height == height_) return;
    width_ = width;
    height_ = height;
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
    attach(display_.get(), GL_COLOR_ATTACHMENT0, GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE, width,
           height);
    attach(linear_.get(), GL_COLOR_ATTACHMENT1, GL_RGBA32F, GL_RGBA, GL_FLOAT, width, height);
    attach(ids_.get(), GL_COLOR_ATTACHMENT2, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, width,
           height);
    attach(depth_.get(), GL_DEPTH_ATTACHMENT, GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, GL_FLOAT,
           width, height);
    glBindTexture(GL_TEXTURE_2D, 0);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        throw gl::Error("the offscreen framebuffer is incomplete (status " +
                        std::to_string(status) + ")");
    gl::check("sizing the offscreen framebuffer");
}

void Renderer::draw(const GpuScene& scene, const DrawSettings& s) {
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
    glViewport(0, 0, width_, height_);
    clear();
    const glm::mat4 clip =
        clip_matrix(s.camera, scene.origin(), scene.radius(), double(width_) / double(height_));
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
    glDisable(GL_BLEND);
    draw_surfaces(scene, s, clip);
    if (s.edges) draw_edges(scene, s, clip);
    glDisable(GL_CULL_FACE);
    glDisable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    gl::check("drawing the scene");
}

void Renderer::clear() {
    const GLenum all[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glDrawBuffers(3, all);
    const GLfloat black[4] = {0.0f, 0.0f, 0.0f, 1.0f}, nothing[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    const GLuint none[4] = {0, 0, 0, 0};
    const GLfloat farthest = 1.0f;
    glDepthMask(GL_TRUE);
    glClearBufferfv(GL_COLOR, 0, black);
    glClearBufferfv(GL_COLOR, 1, nothing);
    glClearBufferuiv(GL_COLOR, 2, none);
    glClearBufferfv(GL_DEPTH, 0, &farthest);
}

void Renderer::draw_surfaces(const GpuScene& scene, const DrawSettings& s, const glm::mat4& clip) {
    glDepthFunc(GL_LESS);
    if (s.edges) {  // surfaces a little behind their edges, so that the lines win the depth test
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(1.0f, 1.0f);
    }
    const GLuint p = surfaces_.get();
    glUseProgram(p);
    glUniformMatrix4fv(uniform(p, "clip"), 1, GL_FALSE, glm::value_ptr(clip));
    glUniform1i(uniform(p, "smooth_shading"), s.smooth ? 1 : 0);
    glUniform1i(uniform(p, "exposed"), s.exposed ? 1 : 0);
    glUniform1f(uniform(p, "scale"), static_cast<float>(s.scale));
    glUniform1i(uniform(p, "highlight"), s.highlight);
    glUniform3fv(uniform(p, "highlight_colour"), 1, glm::value_ptr(s.highlight_colour));
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_BUFFER, scene.triangle_patch());
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_BUFFER, scene.patch_values());
    scene.draw_triangles();
    glBindTexture(GL_TEXTURE_BUFFER, 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
    glUseProgram(0);
    glDisable(GL_POLYGON_OFFSET_FILL);
}

void Renderer::draw_edges(const GpuScene& scene, const DrawSettings& s, const glm::mat4& clip) {
    const GLenum display = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &display);  // lines are no light and see no patch: the display picture only
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_FALSE);
    const GLuint e = edges_.get();
    glUseProgram(e);
    glUniformMatrix4fv(uniform(e, "clip"), 1, GL_FALSE, glm::value_ptr(clip));
    const glm::vec3 eye(s.camera.eye - scene.origin());
    glUniform3fv(uniform(e, "eye"), 1, glm::value_ptr(eye));
    glUniform3fv(uniform(e, "colour"), 1, glm::value_ptr(s.edge_colour));
    scene.draw_edges();
    glUseProgram(0);
    glDepthMask(GL_TRUE);
}

template <class T>
std::vector<T> Renderer::read(GLenum attachment, GLenum format, GLenum type, int channels) const {
    const auto row = static_cast<std::size_t>(width_) * static_cast<std::size_t>(channels);
    std::vector<T> bottom_up(row * static_cast<std::size_t>(height_));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_.get());
    glReadBuffer(attachment);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width_, height_, format, type, bottom_up.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    gl::check("reading a picture back");
    std::vector<T> top_down(bottom_up.size());
    for (int y = 0; y < height_; ++y)
        std::copy_n(
            bottom_up.begin() + static_cast<std::ptrdiff_t>(row * std::size_t(y)), row,
            top_down.begin() + static_cast<std::ptrdiff_t>(row * std::size_t(height_ - 1 - y)));
    return top_down;
}

std::uint32_t Renderer::patch_at(int x, int y) const {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return 0;
    GLuint id = 0;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_.get());
    glReadBuffer(GL_COLOR_ATTACHMENT2);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(x, height_ - 1 - y, 1, 1, GL_RED_INTEGER, GL_UNSIGNED_INT, &id);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    gl::check("reading the patch under a pixel");
    return id;
}

std::vector<glm::vec3> Renderer::linear_pixels() const {
    const auto rgba = read<float>(GL_COLOR_ATTACHMENT1, GL_RGBA, GL_FLOAT, 4);
    std::vector<glm::vec3> out(rgba.size() / 4);
    for (std::size_t i = 0; i < out.size(); ++i)
        out[i] = {rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2]};
    return out;
}

std::vector<std::uint8_t> Renderer::display_pixels() const {
    return read<std::uint8_t>(GL_COLOR_ATTACHMENT0, GL_RGB, GL_UNSIGNED_BYTE, 3);
}

void Renderer::show(int width, int height) const {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_.get());
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glBlitFramebuffer(0, 0, width_, height_, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    gl::check("showing the picture");
}

}  // namespace radiosity::view
