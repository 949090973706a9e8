#pragma once
/// @file ply.hpp  PLY export of a shaded mesh (Turk 1994's polygon file format) with 8-bit sRGB
/// vertex colours, through OpenMesh's writer. Colours are clamped here: OpenMesh does not.

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

/// Writes the mesh as a binary PLY with vertex colours srgb8(exposure_scale * colour) (so the
/// same exposure as the PNG gives the same colours). Throws Error naming the path on failure.
inline void write_ply(const ShadedMesh& mesh, const std::string& path, double exposure_scale) {
    if (!std::ofstream(path)) throw Error("cannot write '" + path + "'");  // before OpenMesh talks
    using Out = OpenMesh::TriMesh_ArrayKernelT<>;
    Out out;
    std::vector<Out::VertexHandle> vh;
    std::vector<std::uint32_t> source;  // the ShadedMesh vertex of each output vertex
    vh.reserve(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const Vec3& p = mesh.positions[v];
        vh.push_back(out.add_vertex(Out::Point(float(p.x), float(p.y), float(p.z))));
        source.push_back(static_cast<std::uint32_t>(v));
    }
    for (const auto& t : mesh.triangles) {
        // A triangle that OpenMesh cannot attach (non-manifold) is written with copies of its
        // vertices instead of being dropped.
        std::vector<Out::VertexHandle> c{vh[t[0]], vh[t[1]], vh[t[2]]};
        if (!out.add_face(c).is_valid()) {
            for (std::size_t k = 0; k < 3; ++k) {
                c[k] = out.add_vertex(out.point(c[k]));
                source.push_back(t[k]);
            }
            out.add_face(c);
        }
    }
    out.request_vertex_colors();
    for (auto v : out.vertices()) {
        const glm::vec3 c = mesh.colours[source[static_cast<std::size_t>(v.idx())]] *
                            static_cast<float>(exposure_scale);
        out.set_color(v, Out::Color(srgb8(c.r), srgb8(c.g), srgb8(c.b)));
    }
    OpenMesh::IO::Options o(OpenMesh::IO::Options::VertexColor | OpenMesh::IO::Options::Binary);
    if (!OpenMesh::IO::write_mesh(out, path, o)) throw Error("cannot write '" + path + "'");
}

}  // namespace radiosity
