// The patches on the GPU (scene_upload.hpp).
#include "scene_upload.hpp"

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>

namespace radiosity::view {

namespace {
/// Which patch each triangle of the topology belongs to: shading fans every patch of k
/// vertices into k - 2 triangles, patch after patch.
std::vector<std::uint32_t> triangle_patches(const Patches& patches, std::size_t triangles) {
    std::vector<std::uint32_t> owner;
    owner.reserve(triangles);
    for (std::size_t i = 0; i < patches.size(); ++i)
        owner.insert(owner.end(), patches.table().polygon(i).size() - 2,
                     static_cast<std::uint32_t>(i));
    if (owner.size() != triangles)
        throw gl::Error("the shaded mesh's triangles do not follow the patches");
    return owner;
}

/// Fills a buffer texture's buffer and ties the texture to it.
void buffer_texture(GLuint texture, GLuint buffer, GLenum format, const void* data,
                    std::size_t bytes) {
    glBindBuffer(GL_TEXTURE_BUFFER, buffer);
    glBufferData(GL_TEXTURE_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(bytes, 16)),
                 nullptr, GL_DYNAMIC_DRAW);
    if (bytes > 0) glBufferSubData(GL_TEXTURE_BUFFER, 0, static_cast<GLsizeiptr>(bytes), data);
    glBindTexture(GL_TEXTURE_BUFFER, texture);
    glTexBuffer(GL_TEXTURE_BUFFER, format, buffer);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
    glBindBuffer(GL_TEXTURE_BUFFER, 0);
}
}  // namespace

GpuScene::GpuScene(const Patches& patches, const radiosity::ShadedMesh& topology)
    : vertices_(topology.positions.size()), patches_(patches.size()) {
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const auto& p : topology.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    if (vertices_ > 0) {
        origin_ = 0.5 * (lo + hi);
        radius_ = std::max(0.5 * glm::length(hi - lo), 1e-12);
    }
    upload_triangles(topology);
    upload_edges(patches);
    upload_patch_tables(patches, topology.triangles.size());
    gl::check("uploading the scene");
}

void GpuScene::upload_triangles(const radiosity::ShadedMesh& topology) {
    std::vector<glm::vec3> positions;
    positions.reserve(vertices_);
    for (const auto& p : topology.positions) positions.emplace_back(p - origin_);
    triangles_vao_ = gl::make_vertex_array();
    positions_ = gl::make_buffer();
    colours_ = gl::make_buffer();
    indices_buffer_ = gl::make_buffer();
    glBindVertexArray(triangles_vao_.get());
    glBindBuffer(GL_ARRAY_BUFFER, positions_.get());
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(positions.size() * sizeof(glm::vec3)),
                 positions.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec3), nullptr);
    glEnableVertexAttribArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, colours_.get());
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices_ * sizeof(glm::vec3)), nullptr,
                 GL_DYNAMIC_DRAW);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec3), nullptr);
    glEnableVertexAttribArray(1);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices_buffer_.get());
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(topology.triangles.size() * 3 * sizeof(std::uint32_t)),
                 topology.triangles.data(), GL_STATIC_DRAW);
    indices_ = static_cast<GLsizei>(topology.triangles.size() * 3);
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
}

void GpuScene::upload_edges(const Patches& patches) {
    // Each edge of each patch, with the patch's normal so that edges of back faces can be hidden.
    std::vector<glm::vec3> edges;
    for (std::size_t i = 0; i < patches.size(); ++i) {
        const auto polygon = patches.table().polygon(i);
        const glm::vec3 normal(patches.table().normal(i));
        for (std::size_t k = 0; k < polygon.size(); ++k) {
            for (const auto& p : {polygon[k], polygon[(k + 1) % polygon.size()]}) {
                edges.emplace_back(p - origin_);
                edges.push_back(normal);
            }
        }
    }
    edge_vertices_ = static_cast<GLsizei>(edges.size() / 2);
    edges_vao_ = gl::make_vertex_array();
    edge_buffer_ = gl::make_buffer();
    glBindVertexArray(edges_vao_.get());
    glBindBuffer(GL_ARRAY_BUFFER, edge_buffer_.get());
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(edges.size() * sizeof(glm::vec3)),
                 edges.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 2 * sizeof(glm::vec3), nullptr);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 2 * sizeof(glm::vec3),
                          reinterpret_cast<const void*>(sizeof(glm::vec3)));
    glEnableVertexAttribArray(1);
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
}

void GpuScene::upload_patch_tables(const Patches& patches, std::size_t triangles) {
    const auto owner = triangle_patches(patches, triangles);
    triangle_patch_buffer_ = gl::make_buffer();
    triangle_patch_texture_ = gl::make_texture();
    buffer_texture(triangle_patch_texture_.get(), triangle_patch_buffer_.get(), GL_R32UI,
                   owner.data(), owner.size() * sizeof(std::uint32_t));
    patch_value_buffer_ = gl::make_buffer();
    patch_value_texture_ = gl::make_texture();
    // RGBA: OpenGL 3.3 has no three-component buffer textures.
    const std::vector<glm::vec4> zero(patches_, glm::vec4(0.0f));
    buffer_texture(patch_value_texture_.get(), patch_value_buffer_.get(), GL_RGBA32F, zero.data(),
                   zero.size() * sizeof(glm::vec4));
}

void GpuScene::set_vertex_colours(const std::vector<glm::vec3>& colours) {
    if (colours.size() != vertices_) throw gl::Error("vertex colours: one per vertex expected");
    glBindBuffer(GL_ARRAY_BUFFER, colours_.get());
    glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(colours.size() * sizeof(glm::vec3)),
                    colours.data());
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    gl::check("uploading vertex colours");
}

void GpuScene::set_patch_values(const std::vector<glm::vec3>& values) {
    if (values.size() != patches_) throw gl::Error("patch values: one per patch expected");
    std::vector<glm::vec4> rgba;
    rgba.reserve(values.size());
    for (const auto& v : values) rgba.emplace_back(v, 1.0f);
    glBindBuffer(GL_TEXTURE_BUFFER, patch_value_buffer_.get());
    glBufferSubData(GL_TEXTURE_BUFFER, 0, static_cast<GLsizeiptr>(rgba.size() * sizeof(glm::vec4)),
                    rgba.data());
    glBindBuffer(GL_TEXTURE_BUFFER, 0);
    gl::check("uploading patch values");
}

void GpuScene::draw_triangles() const {
    glBindVertexArray(triangles_vao_.get());
    glDrawElements(GL_TRIANGLES, indices_, GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
}

void GpuScene::draw_edges() const {
    glBindVertexArray(edges_vao_.get());
    glDrawArrays(GL_LINES, 0, edge_vertices_);
    glBindVertexArray(0);
}

}  // namespace radiosity::view
