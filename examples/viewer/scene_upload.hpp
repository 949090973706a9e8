#pragma once
/// @file scene_upload.hpp  The patches on the GPU. The triangles are those of the library's
/// smooth shading (vertices shared within a smooth group, so colours interpolate across patch
/// boundaries as in the library's pictures); a buffer texture says which patch each triangle
/// belongs to (looked up with gl_PrimitiveID), another holds one value per patch (flat shading,
/// reflectance, emission, a form-factor row), and a line list holds every patch's edges.
/// Positions are stored relative to the scene's centre, so that float keeps their precision.

#include "gl.hpp"
#include "patches.hpp"

#include <radiosity/shading/shaded_mesh.hpp>

#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace radiosity::view {

/// The patches' geometry and values in GL objects (see the file comment). Needs a current
/// context; throws gl::Error if an upload fails.
class GpuScene {
  public:
    /// Uploads the triangles of `topology` (smooth shading of patches.mesh(), whose triangles
    /// run patch after patch) and the edges of every patch.
    GpuScene(const Patches& patches, const radiosity::ShadedMesh& topology);

    /// The vertex colours (linear), one per vertex of the topology: smooth shading's B.
    void set_vertex_colours(const std::vector<glm::vec3>& colours);
    /// One linear value per patch.
    void set_patch_values(const std::vector<glm::vec3>& values);

    const glm::dvec3& origin() const { return origin_; }  ///< the centre subtracted
    double radius() const { return radius_; }  ///< of a sphere about origin holding every vertex

    /// Draws the triangles (vertex array bound, one call).
    void draw_triangles() const;
    /// Draws the edges as lines (vertex array bound, one call).
    void draw_edges() const;
    GLuint triangle_patch() const { return triangle_patch_texture_.get(); }  ///< usamplerBuffer
    GLuint patch_values() const { return patch_value_texture_.get(); }       ///< samplerBuffer

  private:
    void upload_triangles(const radiosity::ShadedMesh& topology);
    void upload_edges(const Patches& patches);
    void upload_patch_tables(const Patches& patches, std::size_t triangles);

    glm::dvec3 origin_{0.0};
    double radius_ = 1.0;
    std::size_t vertices_ = 0, patches_ = 0;
    GLsizei indices_ = 0, edge_vertices_ = 0;
    gl::VertexArray triangles_vao_, edges_vao_;
    gl::Buffer positions_, colours_, indices_buffer_, edge_buffer_;
    gl::Buffer triangle_patch_buffer_, patch_value_buffer_;
    gl::Texture triangle_patch_texture_, patch_value_texture_;
};

}  // namespace radiosity::view
