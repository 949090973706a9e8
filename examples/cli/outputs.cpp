// Writing the solution (outputs.hpp).
#include "cli/outputs.hpp"

#include <radiosity/error.hpp>
#include <radiosity/io/gltf.hpp>
#include <radiosity/io/image.hpp>
#include <radiosity/io/ply.hpp>
#include <radiosity/io/rrv.hpp>
#include <radiosity/io/scenes.hpp>
#include <radiosity/shading/camera.hpp>
#include <radiosity/shading/vertex_shading.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace radiosity::cli {

void check_outputs(const OutputArgs& a) {
    if (!a.lightmap.path.empty()) radiosity::picture_format(a.lightmap.path);
}

void write_form_factor_text(const std::string& path, const radiosity::DenseMatrix& F,
                            const radiosity::PatchTable& patches) {
    std::ofstream out(path);
    if (!out) throw radiosity::Error(path + ": cannot open for writing");
    char buf[32];
    out << "# radiosity view factors: n, then areas A_i, then rows F_ij (A_i F_ij = A_j F_ji)\n";
    out << F.size() << '\n';
    for (std::size_t i = 0; i < F.size(); ++i) {
        std::snprintf(buf, sizeof buf, "%.12g", patches.area(i));
        out << (i ? " " : "") << buf;
    }
    out << '\n';
    for (std::size_t i = 0; i < F.size(); ++i) {
        for (std::size_t j = 0; j < F.size(); ++j) {
            std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(F(i, j)));
            out << (j ? " " : "") << buf;
        }
        out << '\n';
    }
    if (!out) throw radiosity::Error(path + ": write failed");
}

void write_form_factors(const std::string& path, const radiosity::DenseMatrix& F) {
    std::ofstream out(path);
    if (!out) throw radiosity::Error(path + ": cannot open for writing");
    char buf[32];
    for (std::size_t i = 0; i < F.size(); ++i) {
        for (std::size_t j = 0; j < F.size(); ++j) {
            std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(F(i, j)));
            out << (j ? "," : "") << buf;
        }
        out << '\n';
    }
    if (!out) throw radiosity::Error(path + ": write failed");
}

void write_patches(const std::string& path, const radiosity::SolveResult<Colour>& r) {
    std::ofstream out(path);
    if (!out) throw radiosity::Error(path + ": cannot open for writing");
    out << "patch,area,cx,cy,cz,nx,ny,nz,E_r,E_g,E_b,R_r,R_g,R_b,B_r,B_g,B_b\n";
    char buf[64];
    auto num = [&](double x) {
        std::snprintf(buf, sizeof buf, ",%.9g", x);
        out << buf;
    };
    for (auto f : r.mesh.faces()) {
        const auto i = static_cast<std::size_t>(f.idx());
        const auto& d = r.mesh.data(f);
        out << i;
        num(r.patches.area(i));
        for (int k = 0; k < 3; ++k) num(r.patches.centroid(i)[k]);
        for (int k = 0; k < 3; ++k) num(r.patches.normal(i)[k]);
        for (const Colour* c : {&d.emission, &d.reflectance, &d.radiosity})
            for (std::size_t k = 0; k < 3; ++k) num(band(*c, k));
        out << '\n';
    }
    if (!out) throw radiosity::Error(path + ": write failed");
}

void write_lightmap(const LightmapArgs& a, const std::string& gltf,
                    const radiosity::BakeResult<Colour>& b, const radiosity::ToneMapOptions& tone,
                    bool quiet, double metres_per_unit) {
    radiosity::write_image(b.lightmap.image, a.path, tone);
    if (!gltf.empty())
        radiosity::write_gltf_lightmapped(b.shaded, b.lightmap.image, gltf,
                                          radiosity::exposure_scale(b.lightmap.image.pixels, tone),
                                          metres_per_unit);
    using radiosity::TexelState;
    if (!quiet)
        std::fprintf(stderr,
                     "lightmap %dx%d, %s UVs (%zu charts, %.4g texels per unit, patches cut to "
                     "%.4g units): %zu surface, %zu inside geometry, %zu gutter texels; unwrap "
                     "%.2f s, solve %.2f s, bake %.2f s; wrote %s\n",
                     b.atlas.width, b.atlas.height, b.generated_uvs ? "generated" : "the scene's",
                     b.atlas.charts, b.atlas.texel_density, b.patch_edge,
                     b.lightmap.count(TexelState::surface), b.lightmap.count(TexelState::inside),
                     b.lightmap.count(TexelState::dilated), b.unwrap_seconds, b.solve_seconds,
                     b.bake_seconds, a.path.c_str());
}

std::string picture_path(const std::string& scene, const OutputArgs& a) {
    const auto& e = a.exports;
    for (const std::string* o :
         {&a.picture.image, &a.picture.hdr, &e.ply, &e.gltf, &e.rrv_out, &a.lightmap.path,
          &e.dump_patches, &e.dump_form_factors, &e.form_factors_text})
        if (!o->empty()) return a.picture.image;
    return scene == "cornell" ? "cornell_box.png"
                              : std::filesystem::path(scene).stem().string() + ".png";
}

namespace {

/// The dumps: the matrix (CSV, text) and the patches (CSV).
void write_dumps(const radiosity::SolveResult<Colour>& r, const ExportArgs& e,
                 std::vector<std::string>& written) {
    if (!e.dump_form_factors.empty()) {
        write_form_factors(e.dump_form_factors, *r.form_factors);
        written.push_back(e.dump_form_factors);
    }
    if (!e.form_factors_text.empty()) {
        write_form_factor_text(e.form_factors_text, *r.form_factors, r.patches);
        written.push_back(e.form_factors_text);
    }
    if (!e.dump_patches.empty()) {
        write_patches(e.dump_patches, r);
        written.push_back(e.dump_patches);
    }
}

/// The PNG (if image is not empty) and the HDR picture of the shaded mesh, through the chosen
/// camera.
void write_pictures(const radiosity::ShadedMesh& shaded, const std::string& image,
                    const std::string& scene, const radiosity::Mesh<Colour>& mesh,
                    const PictureArgs& p, const radiosity::ToneMapOptions& tone,
                    const SceneInfo& info, std::vector<std::string>& written) {
    if (image.empty() && p.hdr.empty()) return;
    // Back faces culled: a closed room seen from outside shows its inside (a cut-away).
    const auto picture =
        radiosity::render(shaded, chosen_camera(p.camera, scene, mesh, info.enclosure),
                          {.width = p.width, .height = p.height, .cull_back_faces = true});
    if (!image.empty()) {
        radiosity::write_png(picture, image, tone);
        written.push_back(image);
    }
    if (!p.hdr.empty()) {
        radiosity::write_hdr(picture, p.hdr);
        written.push_back(p.hdr);
    }
}

/// A glTF path and, for a .gltf, the .bin written beside it.
void add_gltf(const std::string& path, std::vector<std::string>& written) {
    written.push_back(path);
    if (std::filesystem::path(path).extension() != ".glb")
        written.push_back(std::filesystem::path(path).replace_extension(".bin").string());
}

}  // namespace

std::vector<std::string> write_all_outputs(const Solution& s, const std::string& scene,
                                           const OutputArgs& a, const SceneInfo& info, bool quiet) {
    const auto& r = s.result;
    const auto& e = a.exports;
    std::vector<std::string> written;
    write_dumps(r, e, written);
    const std::string image = picture_path(scene, a);
    const radiosity::ShadedMesh shaded = s.baked          ? s.baked->shaded
                                         : a.picture.flat ? radiosity::flat_shading(r.mesh)
                                                          : radiosity::smooth_shading(r.mesh);
    radiosity::ToneMapOptions tone;
    tone.stops = a.picture.exposure;
    if (s.baked) {
        write_lightmap(a.lightmap, e.gltf, *s.baked, tone, quiet, info.metres_per_unit);
        written.push_back(a.lightmap.path);
        if (!e.gltf.empty()) add_gltf(e.gltf, written);
    }
    write_pictures(shaded, image, scene, r.mesh, a.picture, tone, info, written);
    if (!e.rrv_out.empty()) {
        radiosity::write_rrv(r.mesh, e.rrv_out);
        written.push_back(e.rrv_out);
    }
    if (!e.gltf.empty() && !s.baked) {
        radiosity::write_gltf(shaded, e.gltf, radiosity::exposure_scale(shaded.colours, tone),
                              info.metres_per_unit);
        add_gltf(e.gltf, written);
    }
    if (!e.ply.empty()) {
        radiosity::write_ply(
            shaded, e.ply, radiosity::exposure_scale(shaded.colours, tone),
            e.ply_float ? radiosity::PlyColours::linear_float : radiosity::PlyColours::srgb8);
        written.push_back(e.ply);
    }
    return written;
}

std::string write_outputs(const Solution& s, const std::string& scene, const OutputArgs& a,
                          bool quiet) {
    const auto names = radiosity::builtin_scene_names();
    const bool builtin = std::find(names.begin(), names.end(), scene) != names.end();
    const SceneInfo info{
        builtin ? radiosity::builtin_scene<Colour>(scene).metres_per_unit : 1.0,
        scene == "cornell"
            ? radiosity::Enclosure::open
            : radiosity::classify_enclosure(radiosity::make_patch_table(s.result.mesh)).kind};
    write_all_outputs(s, scene, a, info, quiet);
    return picture_path(scene, a);
}

void print_summary(const radiosity::SolveResult<Colour>& r, const std::string& form_factor,
                   double seconds, const std::vector<std::string>& files) {
    const auto& report = r.report;
    std::string wrote;
    for (const std::string& f : files) wrote += (wrote.empty() ? "; wrote " : ", ") + f;
    const char* state = report.cancelled   ? "INTERRUPTED"
                        : report.converged ? "converged"
                                           : "NOT converged";
    if (r.hierarchy) {  // no matrix: what the hierarchy holds instead
        const auto& h = *r.hierarchy;
        std::fprintf(stderr,
                     "%zu patches (leaves); %zu elements, %zu links (%.1f per element), %zu "
                     "clusters, %.0f MB; refinement %.2f s, %zu passes; hierarchical: %zu "
                     "iterations, residual %.2e, %s in %.2f s; total %.2f s%s\n",
                     r.patches.size(), h.elements, h.links, h.links_per_element(), h.clusters,
                     double(h.bytes) / 1e6, h.refine_seconds, h.passes, report.iterations,
                     report.residual, state, report.seconds, seconds, wrote.c_str());
        if (h.held_rows > 0)
            std::fprintf(stderr,
                         "radiosity: the sweeps ran away: the links' estimated transfers gave %zu "
                         "leaves more light than any surface can gather; those were held to the "
                         "most (row sums of 1) and the sweeps started again\n",
                         h.held_rows);
        if (h.ranks > 1)
            std::fprintf(stderr,
                         "%d ranks: rank 0 judged and evaluated links %.2f s of the refinement's "
                         "%.2f s (waited %.2f s on the others); load imbalance %.2f (the busiest "
                         "rank's link work over the mean); exchange %.2f s, %.0f kB per sweep; "
                         "rank 0 received %.1f MB in all\n",
                         h.ranks, h.link_seconds, h.refine_seconds, h.refine_wait_seconds,
                         h.imbalance, h.exchange_seconds, double(h.exchange_bytes_per_sweep) / 1e3,
                         double(h.bytes_received) / 1e6);
        return;
    }
    std::fprintf(stderr,
                 "%zu patches; form factors (%s) %.2f s; %s: %zu iterations, residual %.2e, %s "
                 "in %.2f s; total %.2f s%s\n",
                 r.patches.size(), form_factor.c_str(), r.form_factor_seconds,
                 report.solver.c_str(), report.iterations, report.residual, state, report.seconds,
                 seconds, wrote.c_str());
}

void print_summary(const radiosity::SolveResult<Colour>& r, const std::string& form_factor,
                   double seconds, const std::string& image) {
    print_summary(r, form_factor, seconds,
                  image.empty() ? std::vector<std::string>{} : std::vector<std::string>{image});
}

void warn_not_converged(const radiosity::Report& r, double tolerance) {
    std::fprintf(stderr,
                 "radiosity: warning: %s stopped after %zu iterations at residual %.2e without "
                 "reaching the tolerance %.2e; the outputs are written but not converged (exit "
                 "status %d; raise --max-iterations or --tolerance)\n",
                 r.solver.c_str(), r.iterations, r.residual, tolerance, not_converged_status);
}

}  // namespace radiosity::cli
