#pragma once
/// @file hemicube.hpp  Hemicube form factors (Cohen & Greenberg 1985): at the centre of patch i,
/// every other patch is projected onto the five faces of a half cube (the top face, and the upper
/// halves of four side faces); a z-buffer keeps the nearest patch in each pixel, and F_ij is the
/// sum of the delta form factors of the pixels where patch j is seen. Visibility comes from the
/// depth test. A patch seen from its back occludes what lies behind it but takes no energy (the
/// light that strikes its back is absorbed, as for every one-sided patch).

#include <radiosity/concepts.hpp>
#include <radiosity/config.hpp>
#include <radiosity/detail/draw_nearest.hpp>
#include <radiosity/error.hpp>
#include <radiosity/geometry/patch_table.hpp>
#include <radiosity/geometry/raster.hpp>
#include <radiosity/geometry/sampling.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <span>
#include <string>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace radiosity {

/// Settings of the hemicube method.
struct HemicubeOptions {
    int resolution = 128;  ///< pixels along an edge of the top face (even, 2..4096)
    bool rotate = true;    ///< turn each hemicube about the normal by a per-patch angle
};

namespace detail {

/// One of the hemicube's five faces, as a view of the hemicube's own frame (u, v, n): clip x is
/// x_sign times the u or v coordinate, the depth axis w is w_sign times the u, v or n
/// coordinate. The top face looks along n with y = v; a side face looks along u or v and maps
/// its upper half (up = n in [0, w]) onto the whole raster, y = 2 n - w.
struct HemicubeFace {
    int x_axis;     // 0: u, 1: v
    double x_sign;  // +1 or -1
    int w_axis;     // 0: u, 1: v, 2: n
    double w_sign;  // +1 or -1
    bool side;      // side faces show only their upper half (above the patch's plane)
};

/// The five faces: the top (right u, up v, forward n) and the four sides, whose forward axes
/// are u, -u, v and -v, up n, and right such that (right, up, forward) is right-handed.
inline constexpr std::array<HemicubeFace, 5> hemicube_faces{{{0, 1.0, 2, 1.0, false},
                                                             {1, 1.0, 0, 1.0, true},
                                                             {1, -1.0, 0, -1.0, true},
                                                             {0, -1.0, 1, 1.0, true},
                                                             {0, 1.0, 1, -1.0, true}}};

/// Clip coordinates (x, y, z, w) of a point with frame coordinates (u, v, n) on one face: the
/// top face shows (u, v) looking along n; a side face maps its upper half (up = n in [0, w])
/// onto the whole raster, y = 2 n - w. z = A w + B is the perspective depth.
inline Vec4 face_clip(const HemicubeFace& face, const std::array<double, 3>& a, double A,
                      double B) {
    const double x = face.x_sign * a[static_cast<std::size_t>(face.x_axis)];
    const double w = face.w_sign * a[static_cast<std::size_t>(face.w_axis)];
    return {x, face.side ? 2.0 * a[2] - w : a[1], A * w + B, w};
}

/// Frustum culling by outcodes (Cohen & Sutherland): bit k of a vertex's code says that the
/// vertex lies beyond plane k; a polygon whose vertices all share a bit lies wholly beyond that
/// plane and cannot cover a pixel of a face bounded by it. The five frusta share their planes:
/// n = +-u and n = +-v bound the top face and top the side faces, u = +-v separate the side
/// faces, n = 0 is the horizon, and each face has a near plane w = near. The codes test the
/// clip coordinates of face_clip: the sign of a rounded sum or difference is that of the exact
/// one.
struct Outcode {
    // In pairs for u and v, so that each SSE2 comparison of (u, v) fills two adjacent bits.
    enum : std::uint32_t {
        u_near = 1u << 0,       // u <= near
        v_near = 1u << 1,       // v <= near
        mu_near = 1u << 2,      // -u <= near
        mv_near = 1u << 3,      // -v <= near
        u_above_n = 1u << 4,    // u - n > 0
        v_above_n = 1u << 5,    // v - n > 0
        u_below_n = 1u << 6,    // u - n < 0
        v_below_n = 1u << 7,    // v - n < 0
        u_above_mn = 1u << 8,   // u + n > 0
        v_above_mn = 1u << 9,   // v + n > 0
        u_below_mn = 1u << 10,  // u + n < 0
        v_below_mn = 1u << 11,  // v + n < 0
        v_above_u = 1u << 12,   // v - u > 0
        v_above_mu = 1u << 13,  // v + u > 0
        v_below_u = 1u << 14,   // v - u < 0
        v_below_mu = 1u << 15,  // v + u < 0
        n_near = 1u << 16,      // n <= near: in front of the top face's near plane
        horizon = 1u << 17,     // n <= 0: not above the patch's plane
        under = 1u << 18,       // n < 0: below the side faces' bottom edge
    };

    /// The code of the vertex with frame coordinates (u, v, n), one comparison at a time: the
    /// definition, and the path of builds without SSE2.
    static std::uint32_t of_scalar(double u, double v, double n, double near) {
        auto bit = [](bool beyond, std::uint32_t b) { return beyond ? b : 0u; };
        return bit(u <= near, u_near) | bit(v <= near, v_near) | bit(-u <= near, mu_near) |
               bit(-v <= near, mv_near) | bit(u - n > 0.0, u_above_n) |
               bit(v - n > 0.0, v_above_n) | bit(u - n < 0.0, u_below_n) |
               bit(v - n < 0.0, v_below_n) | bit(u + n > 0.0, u_above_mn) |
               bit(v + n > 0.0, v_above_mn) | bit(u + n < 0.0, u_below_mn) |
               bit(v + n < 0.0, v_below_mn) | bit(v - u > 0.0, v_above_u) |
               bit(v + u > 0.0, v_above_mu) | bit(v - u < 0.0, v_below_u) |
               bit(v + u < 0.0, v_below_mu) | bit(n <= near, n_near) | bit(n <= 0.0, horizon) |
               bit(n < 0.0, under);
    }

    /// The same code, two comparisons at a time with SSE2 (the same roundings: u - n is one
    /// subtraction in either path, and -u <= near is u >= -near exactly).
    static std::uint32_t of(double u, double v, double n, double near) {
#if defined(__SSE2__)
        return of(_mm_set_pd(v, u), n, near);
#else
        return of_scalar(u, v, n, near);
#endif
    }

#if defined(__SSE2__)
    /// The same with u and v in the lanes of one register.
    static std::uint32_t of(__m128d uv, double n, double near) {
        const double u = _mm_cvtsd_f64(uv), v = _mm_cvtsd_f64(_mm_unpackhi_pd(uv, uv));
        const __m128d nn = _mm_set1_pd(n), zero = _mm_setzero_pd();
        const __m128d lim = _mm_set1_pd(near), minus_lim = _mm_set1_pd(-near);
        const __m128d minus_n = _mm_sub_pd(uv, nn), plus_n = _mm_add_pd(uv, nn);
        const __m128d vu = _mm_set_pd(v + u, v - u);
        auto bits = [](__m128d mask, int shift) {
            return static_cast<std::uint32_t>(_mm_movemask_pd(mask)) << shift;
        };
        return bits(_mm_cmple_pd(uv, lim), 0) | bits(_mm_cmpge_pd(uv, minus_lim), 2) |
               bits(_mm_cmpgt_pd(minus_n, zero), 4) | bits(_mm_cmplt_pd(minus_n, zero), 6) |
               bits(_mm_cmpgt_pd(plus_n, zero), 8) | bits(_mm_cmplt_pd(plus_n, zero), 10) |
               bits(_mm_cmpgt_pd(vu, zero), 12) | bits(_mm_cmplt_pd(vu, zero), 14) |
               bits(_mm_cmple_pd(nn, _mm_set_pd(0.0, near)), 16) | (n < 0.0 ? under : 0u);
    }
#endif

    /// The planes of each face of hemicube_faces (near, then x > w, x < -w, y > w, y < -w).
    static constexpr std::array<std::uint32_t, 5> face{
        n_near | u_above_n | u_below_mn | v_above_n | v_below_mn,  // top: x = u, y = v, w = n
        u_near | v_above_u | v_below_mu | u_below_n | under,       // +u: x = v, w = u
        mu_near | v_below_u | v_above_mu | u_above_mn | under,     // -u: x = -v, w = -u
        v_near | v_below_mu | v_below_u | v_below_n | under,       // +v: x = -u, w = v
        mv_near | v_above_mu | v_above_u | v_above_mn | under};    // -v: x = u, w = -v
};

/// What the five faces of one hemicube draw: every patch vertex in the hemicube's frame (its
/// coordinates along u, v and n from the centre, computed once and shared by the five faces),
/// and, per face and in index order, the patches that may show on it.
struct HemicubeView {
    std::array<std::vector<double>, 3> axis;  // [0]: u, [1]: v, [2]: n, one entry per vertex
    std::array<std::vector<std::uint32_t>, 5> patches;
};

/// The vertices of the patches listed for one face, projected before any is drawn (a loop
/// without branches, whose divisions overlap), patch after patch; and per listed patch whether
/// all its vertices lie in front of the near plane and inside the guard band (else it is
/// clipped, and drawn from its clip coordinates).
struct FaceProjection {
    std::vector<ScreenVertex> screen;
    std::vector<std::uint8_t> inside;
};

/// The frame of one hemicube: its centre c and axes u, v (tangents) and n (the normal). Puts a
/// vertex into it, writing its coordinates to a HemicubeView, and returns the vertex's outcode:
/// with SSE2 the two tangent coordinates at once (the same roundings as one at a time).
struct HemicubeFrame {
    Vec3 c, u, v, n;
    double near;
#if defined(__SSE2__)
    __m128d ux, uy, uz;  // (u, v) by component
#endif

    HemicubeFrame(const Vec3& centre, const std::array<Vec3, 3>& axes, double near_plane)
        : c(centre), u(axes[0]), v(axes[1]), n(axes[2]), near(near_plane) {
#if defined(__SSE2__)
        ux = _mm_set_pd(v.x, u.x);
        uy = _mm_set_pd(v.y, u.y);
        uz = _mm_set_pd(v.z, u.z);
#endif
    }

    /// Vertex k at p in the frame: (u, v, n) coordinates of p - c into seen.axis, and the code.
    std::uint32_t to_frame(const Vec3& p, std::uint32_t k, HemicubeView& seen) const {
        const Vec3 d = p - c;
        const double h = glm::dot(d, n);
        seen.axis[2][k] = h;
#if defined(__SSE2__)
        const __m128d ab = _mm_add_pd(
            _mm_add_pd(_mm_mul_pd(_mm_set1_pd(d.x), ux), _mm_mul_pd(_mm_set1_pd(d.y), uy)),
            _mm_mul_pd(_mm_set1_pd(d.z), uz));
        _mm_storel_pd(&seen.axis[0][k], ab);
        _mm_storeh_pd(&seen.axis[1][k], ab);
        return Outcode::of(ab, h, near);
#else
        const double a = glm::dot(d, u), b = glm::dot(d, v);
        seen.axis[0][k] = a;
        seen.axis[1][k] = b;
        return Outcode::of(a, b, h, near);
#endif
    }
};

/// The buffers of one hemicube, kept by each thread from row to row so that a row allocates
/// and clears only what it must (rows are computed by the thousand).
struct HemicubeWorkspace {
    HemicubeView seen;
    std::vector<double> F, depth;
    std::vector<std::int32_t> id;
    std::vector<std::uint32_t> starts;  // accumulate's run starts, grown to the largest face
    FaceProjection projected;
};

}  // namespace detail

/// Hemicube form factors (Cohen & Greenberg 1985) with the delta form factors of the unit
/// hemicube, evaluated at pixel centres:
///   top face (z = 1):        dF = dA / (pi (x^2 + y^2 + 1)^2)
///   side faces (y = 1):      dF = z dA / (pi (x^2 + z^2 + 1)^2)
/// with dA = (2 / resolution)^2. The rasteriser is the library's one (geometry/raster.hpp), the
/// same that draws camera pictures. Approximations of the method: F_ij is seen from the centre
/// of patch i only, and patches are point-sampled by pixels (aliasing for small or distant
/// patches; raise the resolution). Cost per row: O(n) projections plus O(resolution^2) pixels.
class Hemicube {
  public:
    /// A method with the given settings; throws Error for an odd or out-of-range resolution.
    explicit Hemicube(HemicubeOptions options = {}) : options_(options) {
        const int r = options_.resolution;
        if (r < 2 || r > 4096 || r % 2 != 0)
            throw Error("hemicube: resolution must be even and in [2, 4096], not " +
                        std::to_string(r));
        make_delta_form_factors();
    }

    /// Keeps a reference to the patch table and sizes the depth range from its bounding box.
    void prepare(const PatchTable& patches) {
        patches_ = &patches;
        Vec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        for (std::size_t i = 0; i < patches.size(); ++i)
            for (const Vec3& p : patches.polygon(i)) {
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
            }
        const double diagonal = patches.size() > 0 ? glm::length(hi - lo) : 1.0;
        const double far = 2.0 * diagonal;
        near_ = 1e-7 * diagonal;
        A_ = (far + near_) / (far - near_);  // z = A w + B: -w at the near plane, w at far
        B_ = -2.0 * far * near_ / (far - near_);
        index_patches(patches);
    }

    /// Row i: F_ij for every patch j, from the hemicube at the centroid of patch i (RowSource).
    /// Steps: what each face may show (view); per face, the item buffer and the sum of the
    /// delta form factors of each patch's pixels; the patches seen from behind dropped.
    void row(std::size_t i, std::span<float> out) const {
        const PatchTable& t = table();
        if (out.size() != t.size()) throw Error("hemicube: row needs one entry per patch");
        RADIOSITY_ASSERT(i < t.size());
        thread_local detail::HemicubeWorkspace work;
        view(i, work.seen);
        std::vector<double>& F = work.F;
        F.assign(t.size(), 0.0);
        for (std::size_t k = 0; k < 5; ++k) {
            item_buffer(work.seen, k, work.id, work.depth, work.projected);
            accumulate(k > 0 ? side_prefix_ : top_prefix_, work.id, work.starts, F);
        }
        front_sides_only(i, F, out);
    }

    /// The item buffers of patch i's hemicube, for teaching and debugging: for the top face and
    /// then the four side faces, which patch each pixel sees (-1: none), row 0 at the top (the
    /// patch's horizon is the sides' last row). Top: resolution^2 pixels, sides: resolution x
    /// resolution/2. Pair them with top_delta_form_factors() and side_delta_form_factors().
    std::array<std::vector<std::int32_t>, 5> item_buffers(std::size_t i) const {
        std::array<std::vector<std::int32_t>, 5> ids;
        std::vector<double> depth;
        detail::HemicubeView seen;
        detail::FaceProjection projected;
        view(i, seen);
        for (std::size_t k = 0; k < 5; ++k) item_buffer(seen, k, ids[k], depth, projected);
        return ids;
    }
    /// Delta form factor of each top-face pixel, row after row.
    const std::vector<double>& top_delta_form_factors() const { return top_dff_; }
    /// Delta form factor of each side-face pixel, row after row (the same for all four sides).
    const std::vector<double>& side_delta_form_factors() const { return side_dff_; }

    const HemicubeOptions& options() const { return options_; }  ///< the settings
    /// Sum of all delta form factors (the top face and four half side faces): 1 up to the
    /// midpoint-rule error of the pixel grid, the largest row sum a closed scene can reach.
    double delta_form_factor_sum() const {
        double s = 0.0;
        for (double d : top_dff_) s += d;
        for (double d : side_dff_) s += 4.0 * d;
        return s;
    }

  private:
    const PatchTable& table() const {
        if (patches_ == nullptr) throw Error("hemicube: prepare() was not called");
        return *patches_;
    }

    /// out_j = F_j for the patches j that show patch i their front, else 0: a patch seen from
    /// behind keeps its pixels (it occludes) but takes nothing, as the light that strikes its
    /// back is absorbed.
    void front_sides_only(std::size_t i, const std::vector<double>& F, std::span<float> out) const {
        const PatchTable& t = table();
        const Vec3& c = t.centroid(i);
        // Most patches are not seen at all: test the side only of those that are.
        for (std::size_t j = 0; j < t.size(); ++j)
            out[j] = F[j] != 0.0 && glm::dot(c - t.centroid(j), t.normal(j)) > 0.0
                         ? static_cast<float>(F[j])
                         : 0.0f;
    }

    /// Where each patch's vertices start in the table's one vertex array, and the radius of a
    /// sphere about its centroid that holds it (to skip patches below a horizon at once). The
    /// rows read every vertex through that one array (PatchTable::vertices), by these offsets.
    void index_patches(const PatchTable& patches) {
        first_.assign(1, 0);
        radius_.assign(patches.size(), 0.0);
        for (std::size_t j = 0; j < patches.size(); ++j) {
            RADIOSITY_ASSERT(patches.polygon(j).data() == patches.vertices().data() + first_[j]);
            first_.push_back(first_.back() + static_cast<std::uint32_t>(patches.polygon(j).size()));
            for (const Vec3& p : patches.polygon(j))
                radius_[j] = std::max(radius_[j], glm::length(p - patches.centroid(j)));
            radius_[j] *= 1.0 + 1e-9;  // a bounding sphere despite rounding
        }
    }

    /// Draws the patches that may show on face k into its z-buffer, keeping the nearest patch
    /// per pixel: projects all their vertices first, then draws them in index order.
    void item_buffer(const detail::HemicubeView& seen, std::size_t k, std::vector<std::int32_t>& id,
                     std::vector<double>& depth, detail::FaceProjection& projected) const {
        const detail::HemicubeFace& face = detail::hemicube_faces[k];
        const int w = options_.resolution, h = face.side ? w / 2 : w;
        id.assign(static_cast<std::size_t>(w * h), -1);
        depth.assign(id.size(), std::numeric_limits<double>::infinity());
        project(seen, k, w, h, projected);
        const detail::ScreenVertex* s = projected.screen.data();
        for (std::size_t n = 0; n < seen.patches[k].size(); ++n) {
            const std::uint32_t j = seen.patches[k][n];
            draw(j, seen, face, s, projected.inside[n] != 0, w, h, id, depth);
            s += first_[j + 1] - first_[j];
        }
        RADIOSITY_ASSERT(s <= projected.screen.data() + projected.screen.size());
    }

    /// Projects the vertices of the patches listed for face k onto its w x h raster (see
    /// FaceProjection), exactly as rasterize_depth would project each.
    void project(const detail::HemicubeView& seen, std::size_t k, int w, int h,
                 detail::FaceProjection& projected) const {
        const std::vector<std::uint32_t>& list = seen.patches[k];
        std::size_t vertices = 0;
        for (const std::uint32_t j : list) vertices += first_[j + 1] - first_[j];
        if (projected.screen.size() < vertices) projected.screen.resize(vertices);  // grown only
        projected.inside.resize(list.size());
        // One loop per face, with the face's axes known at compile time: the clip coordinates
        // come straight from the frame's arrays, not through an array indexed at run time.
        switch (k) {
            case 0:
                return project_face<0>(seen, w, h, projected);
            case 1:
                return project_face<1>(seen, w, h, projected);
            case 2:
                return project_face<2>(seen, w, h, projected);
            case 3:
                return project_face<3>(seen, w, h, projected);
            default:
                return project_face<4>(seen, w, h, projected);
        }
    }

    template <std::size_t K>
    void project_face(const detail::HemicubeView& seen, int w, int h,
                      detail::FaceProjection& projected) const {
        static constexpr detail::HemicubeFace face = detail::hemicube_faces[K];
        const std::vector<std::uint32_t>& list = seen.patches[K];
        const double *const u = seen.axis[0].data(), *const v = seen.axis[1].data(),
                            *const n = seen.axis[2].data();
        const double extent = std::max(w, h);
        static constexpr glm::dvec3 unused{1, 0, 0};  // barycentric weights: not needed
        detail::ScreenVertex* s = projected.screen.data();
        for (std::size_t m = 0; m < list.size(); ++m) {
            bool inside = true;
            for (std::uint32_t k = first_[list[m]]; k < first_[list[m] + 1]; ++k) {
                const Vec4 p = detail::face_clip(face, {u[k], v[k], n[k]}, A_, B_);
                const bool in = detail::inside_guard_band(p, extent);
                inside = inside && in;
                // A vertex outside is not projected (w may be 0): its patch will be clipped.
                *s++ = detail::to_screen(in ? p : Vec4(0, 0, 0, 1), unused, w, h);
            }
            projected.inside[m] = inside ? 1 : 0;
        }
    }

    /// The delta form factors of each pixel (the equations above), computed once.
    void make_delta_form_factors() {
        const int r = options_.resolution;
        const double d = 2.0 / r, dA = d * d, pi = std::numbers::pi;
        top_dff_.resize(static_cast<std::size_t>(r * r));
        side_dff_.resize(static_cast<std::size_t>(r * r / 2));
        for (int py = 0; py < r; ++py)
            for (int px = 0; px < r; ++px) {
                const double x = -1.0 + (px + 0.5) * d, y = 1.0 - (py + 0.5) * d;
                const double q = x * x + y * y + 1.0;
                top_dff_[static_cast<std::size_t>(py * r + px)] = dA / (pi * q * q);
                if (py < r / 2) {  // side face: row 0 at height z = 1, last row at z = 0
                    const double z = y, s = x * x + z * z + 1.0;
                    side_dff_[static_cast<std::size_t>(py * r + px)] = z * dA / (pi * s * s);
                }
            }
        for (auto [dff, prefix] :
             {std::pair{&top_dff_, &top_prefix_}, {&side_dff_, &side_prefix_}}) {
            prefix->assign(1, 0.0);
            for (double d : *dff) prefix->push_back(prefix->back() + d);
        }
    }

    /// The hemicube's frame at patch i: two tangents u, v and the normal n, turned about the
    /// normal by a per-patch angle.
    std::array<Vec3, 3> frame(std::size_t i) const {
        const Vec3 n = table().normal(i);
        Vec3 u, v;
        orthonormal_basis(n, u, v);
        if (options_.rotate) {
            const double angle =
                2.0 * std::numbers::pi * static_cast<double>(splitmix64(i) >> 11) * 0x1.0p-53;
            const Vec3 u2 = std::cos(angle) * u + std::sin(angle) * v;
            v = glm::cross(n, u2);
            u = u2;
        }
        return {u, v, n};
    }

    /// The vertices of the patches above the horizon of patch i in the frame of its hemicube
    /// (one transform per vertex, not one per face), and the patches that may show on each face.
    /// A patch whose bounding sphere lies below the horizon shows on no face (every face looks
    /// into n > 0), and is skipped before its vertices are touched. Frustum culling by outcodes:
    /// a polygon whose vertices all lie beyond one plane of a face's frustum cannot cover a pixel
    /// of it; most patches lie in one or two of the five faces, so this skips most of the
    /// rasteriser's setup.
    void view(std::size_t i, detail::HemicubeView& seen) const {
        const PatchTable& t = table();
        const Vec3& c = t.centroid(i);
        const detail::HemicubeFrame hemicube(c, frame(i), near_);
        const std::size_t m = first_.back();
        for (auto& a : seen.axis) a.resize(m);  // entries are written before they are read
        for (auto& list : seen.patches) list.clear();
        const Vec3* p = t.vertices().data();  // all polygons, one array (index_patches)
        for (std::size_t j = 0; j < t.size(); ++j) {
            if (glm::dot(t.centroid(j) - c, hemicube.n) + radius_[j] <= 0.0 || j == i) continue;
            std::uint32_t shared = ~0u;  // the planes all its vertices lie beyond
            for (std::uint32_t k = first_[j]; k < first_[j + 1]; ++k)
                shared &= hemicube.to_frame(p[k], k, seen);
            if (shared & detail::Outcode::horizon) continue;  // below the horizon
            for (std::size_t f = 0; f < 5; ++f)
                if (!(shared & detail::Outcode::face[f]))
                    seen.patches[f].push_back(static_cast<std::uint32_t>(j));
        }
    }

    /// Draws patch j into the z-buffer of one face, from its projected vertices s when all lie
    /// inside the guard band (the usual case: each vertex was projected once for the whole fan,
    /// exactly as rasterize_depth would project it per triangle), else clipped.
    void draw(std::uint32_t j, const detail::HemicubeView& seen, const detail::HemicubeFace& face,
              const detail::ScreenVertex* s, bool inside, int w, int h,
              std::vector<std::int32_t>& id, std::vector<double>& depth) const {
        const std::uint32_t first = first_[j], count = first_[j + 1] - first;
        const detail::NearestItems items{depth.data(), id.data(), w, static_cast<std::int32_t>(j)};
        if (inside) {
            for (std::uint32_t k = 1; k + 1 < count; ++k)
                detail::draw_nearest(s[0], s[k], s[k + 1], w, h, items);
            return;
        }
        std::array<Vec4, 16> clip;
        std::vector<Vec4> big;
        Vec4* p = count <= clip.size() ? clip.data() : (big.resize(count), big.data());
        for (std::uint32_t k = 0; k < count; ++k)
            p[k] = detail::face_clip(
                face, {seen.axis[0][first + k], seen.axis[1][first + k], seen.axis[2][first + k]},
                A_, B_);
        for (std::uint32_t k = 1; k + 1 < count; ++k)
            rasterize_depth({p[0], p[k], p[k + 1]}, w, h, items);
    }

    /// Adds the delta form factor of every pixel to the patch seen there. Neighbouring pixels
    /// mostly see the same patch, so whole runs are added at once, each from the prefix sums of
    /// the delta form factors (prefix[b] - prefix[a] for pixels a .. b - 1): no arithmetic per
    /// pixel.
    /// The runs' starts are found first, without a branch per pixel (a run's end follows no
    /// pattern the branch predictor could learn): each pixel writes its index to the list and
    /// advances the list's end only where the patch changes.
    static void accumulate(const std::vector<double>& prefix, const std::vector<std::int32_t>& id,
                           std::vector<std::uint32_t>& starts, std::vector<double>& F) {
        RADIOSITY_ASSERT(prefix.size() == id.size() + 1 && !id.empty());
        if (starts.size() < id.size() + 1) starts.resize(id.size() + 1);  // never shrinks
        std::size_t n = 0;
        starts[n++] = 0;
        for (std::size_t k = 1; k < id.size(); ++k) {
            starts[n] = static_cast<std::uint32_t>(k);
            n += id[k] != id[k - 1] ? 1 : 0;
        }
        starts[n] = static_cast<std::uint32_t>(id.size());
        for (std::size_t r = 0; r < n; ++r) {
            const std::uint32_t a = starts[r], b = starts[r + 1];
            if (id[a] >= 0) F[static_cast<std::size_t>(id[a])] += prefix[b] - prefix[a];
        }
    }

    HemicubeOptions options_;
    const PatchTable* patches_ = nullptr;
    std::vector<double> top_dff_, side_dff_;
    std::vector<double> top_prefix_, side_prefix_;  // prefix[k]: sum of the first k dff
    std::vector<std::uint32_t> first_{0};  // patch j's vertices: first_[j] .. first_[j + 1] - 1
    std::vector<double> radius_;           // of a sphere about patch j's centroid holding it
    double near_ = 1e-7, A_ = 1.0, B_ = 0.0;
};

static_assert(FormFactorMethod<Hemicube>);

}  // namespace radiosity
