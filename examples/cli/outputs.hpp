#pragma once
/// @file outputs.hpp  What the radiosity program writes from a solution: pictures, exports
/// (PLY, glTF, RRV), the lightmap, the CSV and text dumps, and the one-line summary.

#include "cli/options.hpp"
#include "cli/solve.hpp"

#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/shading/tonemap.hpp>

#include <string>
#include <vector>

namespace radiosity::cli {

/// Refuses before the solve what would only fail after it: a lightmap picture of an unknown
/// format (radiosity::Error naming it).
void check_outputs(const OutputArgs& a);

/// Writes F as CSV, line i holding F_ij with 9 significant digits. Throws radiosity::Error
/// naming the path if it cannot be written.
void write_form_factors(const std::string& path, const radiosity::DenseMatrix& F);

/// Writes F as plain text for thermal-analysis tools: a comment, n, then the n areas, then n
/// rows of n view factors, whitespace-separated. Throws radiosity::Error naming the path.
void write_form_factor_text(const std::string& path, const radiosity::DenseMatrix& F,
                            const radiosity::PatchTable& patches);

/// Writes the patches as CSV: index, area, centroid, normal, E, R and B per band, in the
/// order of the form-factor dumps. Throws radiosity::Error naming the path.
void write_patches(const std::string& path, const radiosity::SolveResult<Colour>& r);

/// Writes the baked lightmap and, given a glTF path, the glTF textured with it (the PNG and
/// the glTF's texture take the same exposure, chosen from the lightmap's texels; the glTF in
/// metres, metres_per_unit times the scene's units); unless quiet, says on stderr what the
/// atlas holds and where the time went.
void write_lightmap(const LightmapArgs& a, const std::string& gltf,
                    const radiosity::BakeResult<Colour>& b, const radiosity::ToneMapOptions& tone,
                    bool quiet, double metres_per_unit = 1.0);

/// The PNG to write: --image; or, when no output at all is named, cornell_box.png for the
/// Cornell box and the scene's name with .png (in the current folder) for any other scene.
std::string picture_path(const std::string& scene, const OutputArgs& a);

/// Writes every output that a names, after the dumps the shaded mesh (flat, smooth or the
/// bake's) for the picture and the exports: the picture through the default camera for the
/// scene's enclosure (from inside a closed room) unless --camera places one, glTF in metres
/// (info.metres_per_unit). Returns every file written, in the order written (a .gltf's .bin
/// after it).
std::vector<std::string> write_all_outputs(const Solution& s, const std::string& scene,
                                           const OutputArgs& a, const SceneInfo& info, bool quiet);

/// write_all_outputs with the scene's info found again (a built-in scene's unit, else metres;
/// the enclosure from the solved mesh); returns the PNG written ("" if none).
std::string write_outputs(const Solution& s, const std::string& scene, const OutputArgs& a,
                          bool quiet);

/// The summary on stderr: patches, the form factors' and the solver's time and report, the
/// total time and every file written.
void print_summary(const radiosity::SolveResult<Colour>& r, const std::string& form_factor,
                   double seconds, const std::vector<std::string>& files);

/// The summary naming one picture ("" for none).
void print_summary(const radiosity::SolveResult<Colour>& r, const std::string& form_factor,
                   double seconds, const std::string& image);

/// The exit status of a run whose solver stopped at its iteration guard before reaching its
/// tolerance (the outputs are written all the same): 3, apart from errors (1), a bad command
/// line (2) and Ctrl-C (130).
inline constexpr int not_converged_status = 3;

/// The warning on stderr for a solve that ended without reaching `tolerance`: the solver, its
/// iterations and residual, and what to do (more iterations, or a looser tolerance).
void warn_not_converged(const radiosity::Report& r, double tolerance);

}  // namespace radiosity::cli
