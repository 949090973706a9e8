#pragma once
/// @file ply.hpp  PLY export of a shaded mesh (Turk 1994's polygon file format) with 8-bit sRGB
/// or linear float vertex colours, through OpenMesh's writer. 8-bit colours are clamped here:
/// OpenMesh does not.

// OpenMesh's IO header must come before its mesh headers (DESIGN.md, known quirks).
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

// Note for -Werror builds with GCC 12: OpenMesh's 8-bit colour property default-constructs its
// colours uninitialised (harmless: every colour is set before it is written), and GCC reports
// -Wmaybe-uninitialized from inside the standard library where no pragma reaches; build files
// that include this header with -Wno-maybe-uninitialized (see radiosity_setup_target).

#include <radiosity/error.hpp>
#include <radiosity/shading/shaded_mesh.hpp>
#include <radiosity/shading/tonemap.hpp>

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

namespace radiosity {

/// The colour encoding of a PLY export.
enum class PlyColours {
    srgb8,        ///< 8-bit sRGB, clamped: what viewers show directly
    linear_float  ///< linear floats, unclamped: exposure_scale * B, for further processing
};

namespace detail {
/// RGBA float colours (OpenMesh's exporter handles Vec4f, not Vec3f, colours).
struct FloatColourTraits : OpenMesh::DefaultTraits {
    using Color = OpenMesh::Vec4f;
};

/// The shaded mesh as an OpenMesh triangle mesh with its colours, source[v] naming the
/// ShadedMesh vertex of output vertex v. A triangle that OpenMesh cannot attach (non-manifold)
/// is written with copies of its vertices instead of being dropped.
template <class Out, class Colour>
void write_ply_as(const ShadedMesh& mesh, const std::string& path, Colour&& colour,
                  OpenMesh::IO::Options options) {
    if (!std::ofstream(path)) throw Error("cannot write '" + path + "'");  // before OpenMesh talks
    Out out;
    std::vector<typename Out::VertexHandle> vh;
    std::vector<std::uint32_t> source;
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const Vec3& p = mesh.positions[v];
        vh.push_back(out.add_vertex(typename Out::Point(float(p.x), float(p.y), float(p.z))));
        source.push_back(static_cast<std::uint32_t>(v));
    }
    for (const auto& t : mesh.triangles) {
        std::vector<typename Out::VertexHandle> c{vh[t[0]], vh[t[1]], vh[t[2]]};
        if (!out.add_face(c).is_valid()) {
            for (std::size_t k = 0; k < 3; ++k) {
                c[k] = out.add_vertex(out.point(c[k]));
                source.push_back(t[k]);
            }
            out.add_face(c);
        }
    }
    out.request_vertex_colors();
    for (auto v : out.vertices())
        out.set_color(v, colour(mesh.colours[source[static_cast<std::size_t>(v.idx())]]));
    if (!OpenMesh::IO::write_mesh(out, path, options)) throw Error("cannot write '" + path + "'");
}
}  // namespace detail

/// Writes the mesh as a binary PLY with vertex colours: srgb8(exposure_scale * colour),
/// clamped (the same exposure as the PNG gives the same colours), or linear floats
/// exposure_scale * colour, unclamped. Throws Error naming the path on failure.
inline void write_ply(const ShadedMesh& mesh, const std::string& path, double exposure_scale,
                      PlyColours colours = PlyColours::srgb8) {
    using OpenMesh::IO::Options;
    const auto scale = static_cast<float>(exposure_scale);
    if (colours == PlyColours::srgb8) {
        using Out = OpenMesh::TriMesh_ArrayKernelT<>;
        detail::write_ply_as<Out>(
            mesh, path,
            [scale](const glm::vec3& c) {
                return Out::Color(srgb8(scale * c.r), srgb8(scale * c.g), srgb8(scale * c.b));
            },
            Options(Options::VertexColor | Options::Binary));
    } else {
        using Out = OpenMesh::TriMesh_ArrayKernelT<detail::FloatColourTraits>;
        detail::write_ply_as<Out>(
            mesh, path,
            [scale](const glm::vec3& c) {
                return Out::Color(scale * c.r, scale * c.g, scale * c.b, 1.0f);
            },
            Options(Options::VertexColor | Options::ColorFloat | Options::Binary));
    }
}

}  // namespace radiosity
