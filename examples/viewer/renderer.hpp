#pragma once
/// @file renderer.hpp  The OpenGL renderer: the scene into an offscreen framebuffer with three
/// pictures at once, what the screen shows (8-bit sRGB after the exposure, as the library's PNGs:
/// shading/tonemap.hpp's curve, computed in the shader), the linear values (B, for the automatic
/// exposure, which the library takes from a picture's pixels) and which patch each pixel sees
/// (for picking). Patch edges go over the surfaces as lines. The camera's projection is the
/// library's (glm::lookAt and radiosity::perspective), so pixels fall where its CPU renderer
/// puts them; back faces are culled, as the `radiosity` program's pictures cull them.

#include "gl.hpp"
#include "scene_upload.hpp"

#include <radiosity/shading/camera.hpp>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace radiosity::view {

/// What one frame shows.
struct DrawSettings {
    radiosity::Camera camera;          ///< where from
    bool smooth = false;               ///< vertex colours, else one value per patch
    bool exposed = true;               ///< values are light: shown times `scale`
    double scale = 1.0;                ///< exposure scale (radiosity::exposure_scale)
    bool edges = false;                ///< patch edges over the surfaces
    glm::vec3 edge_colour{0.0f};       ///< display colour of the edges
    int highlight = -1;                ///< a patch shown in highlight_colour (-1: none)
    glm::vec3 highlight_colour{1.0f};  ///< display colour of that patch
};

/// The offscreen framebuffer and the programs that draw into it (see the file comment). Needs
/// a current OpenGL 3.3 core context; throws gl::Error when GL fails.
class Renderer {
  public:
    Renderer();

    /// Sizes the offscreen pictures (no-op when unchanged).
    void resize(int width, int height);
    int width() const { return width_; }    ///< picture width in pixels
    int height() const { return height_; }  ///< picture height in pixels

    /// Draws the scene into the offscreen pictures.
    void draw(const GpuScene& scene, const DrawSettings& settings);
    /// The patch seen at pixel (x, y), row 0 at the top: patch index + 1, or 0 for none.
    std::uint32_t patch_at(int x, int y) const;
    /// The linear values, width x height, row 0 at the top (0 where nothing is seen).
    std::vector<glm::vec3> linear_pixels() const;
    /// The displayed picture as 8-bit sRGB triples, row 0 at the top.
    std::vector<std::uint8_t> display_pixels() const;
    /// Copies the displayed picture onto the window's framebuffer (width x height).
    void show(int width, int height) const;
    /// The offscreen framebuffer, for drawing more (the panels) into a headless picture.
    GLuint framebuffer() const { return framebuffer_.get(); }

  private:
    void clear();
    void draw_surfaces(const GpuScene& scene, const DrawSettings& s, const glm::mat4& clip);
    void draw_edges(const GpuScene& scene, const DrawSettings& s, const glm::mat4& clip);
    template <class T>
    std::vector<T> read(GLenum attachment, GLenum format, GLenum type, int channels) const;

    int width_ = 0, height_ = 0;
    gl::Program surfaces_, edges_;
    gl::Framebuffer framebuffer_;
    gl::Texture display_, linear_, ids_, depth_;
};

}  // namespace radiosity::view
