#pragma once
/// @file hemicube.hpp  Hemicube form factors (Cohen & Greenberg 1985): at the centre of patch i,
/// every other patch is projected onto the five faces of a half cube (the top face, and the upper
/// halves of four side faces); a z-buffer keeps the nearest patch in each pixel, and F_ij is the
/// sum of the delta form factors of the pixels where patch j is seen. Visibility comes from the
/// depth test. A patch seen from its back occludes what lies behind it but takes no energy (the
/// light that strikes its back is absorbed, as for every one-sided patch).

#include <radiosity/concepts.hpp>
#include <radiosity/error.hpp>
#include <radiosity/geometry/raster.hpp>
#include <radiosity/geometry/sampling.hpp>
#include <radiosity/mesh/patch_table.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <span>
#include <vector>

namespace radiosity {

/// Settings of the hemicube method.
struct HemicubeOptions {
    int resolution = 128;  ///< pixels along an edge of the top face (even, 2..4096)
    bool rotate = true;    ///< turn each hemicube about the normal by a per-patch angle
};

namespace detail {

/// A frame at the hemicube's centre: right, up and forward axes of one of its five faces, in
/// scene space, and the fraction of the face's height that lies above the patch's horizon.
struct HemicubeFace {
    Vec3 right, up, forward;
    bool side;  // side faces show only their upper half (above the patch's plane)
};

/// Two unit vectors completing n to a right-handed orthonormal frame (Duff et al. 2017).
inline void orthonormal_basis(const Vec3& n, Vec3& u, Vec3& v) {
    const double s = std::copysign(1.0, n.z);
    const double a = -1.0 / (s + n.z), b = n.x * n.y * a;
    u = Vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    v = Vec3(b, s + n.y * n.y * a, -n.y);
}

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
        far_ = 2.0 * diagonal;
        near_ = 1e-7 * diagonal;
    }

    /// Row i: F_ij for every patch j, from the hemicube at the centroid of patch i (RowSource).
    void row(std::size_t i, std::span<float> out) const {
        const PatchTable& t = table();
        if (out.size() != t.size()) throw Error("hemicube: row needs one entry per patch");
        std::vector<double> F(t.size(), 0.0);
        std::vector<std::int32_t> id;
        std::vector<double> depth;
        for (const detail::HemicubeFace& face : faces(i)) {
            item_buffer(i, face, id, depth);
            accumulate(i, face.side ? side_dff_ : top_dff_, id, F);
        }
        for (std::size_t j = 0; j < t.size(); ++j) out[j] = static_cast<float>(F[j]);
    }

    /// The item buffers of patch i's hemicube, for teaching and debugging: for the top face and
    /// then the four side faces, which patch each pixel sees (-1: none), row 0 at the top (the
    /// patch's horizon is the sides' last row). Top: resolution^2 pixels, sides: resolution x
    /// resolution/2. Pair them with top_delta_form_factors() and side_delta_form_factors().
    std::array<std::vector<std::int32_t>, 5> item_buffers(std::size_t i) const {
        std::array<std::vector<std::int32_t>, 5> ids;
        std::vector<double> depth;
        const auto f = faces(i);
        for (std::size_t k = 0; k < 5; ++k) item_buffer(i, f[k], ids[k], depth);
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

    /// Draws every other patch into one face's z-buffer, keeping the nearest patch per pixel.
    void item_buffer(std::size_t i, const detail::HemicubeFace& face, std::vector<std::int32_t>& id,
                     std::vector<double>& depth) const {
        const PatchTable& t = table();
        const int w = options_.resolution, h = face.side ? w / 2 : w;
        id.assign(static_cast<std::size_t>(w * h), -1);
        depth.assign(id.size(), std::numeric_limits<double>::infinity());
        for (std::size_t j = 0; j < t.size(); ++j)
            if (j != i) draw(j, t.centroid(i), face, w, h, id, depth);
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
    }

    /// The five faces of the hemicube of patch i, turned about the normal by a per-patch angle.
    std::array<detail::HemicubeFace, 5> faces(std::size_t i) const {
        const Vec3 n = table().normal(i);
        Vec3 u, v;
        detail::orthonormal_basis(n, u, v);
        if (options_.rotate) {
            const double angle =
                2.0 * std::numbers::pi * static_cast<double>(splitmix64(i) >> 11) * 0x1.0p-53;
            const Vec3 u2 = std::cos(angle) * u + std::sin(angle) * v;
            v = glm::cross(n, u2);
            u = u2;
        }
        return {{{u, v, n, false},
                 {v, n, u, true},
                 {-v, n, -u, true},
                 {-u, n, v, true},
                 {u, n, -v, true}}};
    }

    /// Projects patch j onto one face of the hemicube centred at c and draws it into the
    /// z-buffer: clip coordinates (x, y, z, w) = (right, up, depth, forward) for the top face;
    /// side faces map the upper half (up in [0, forward]) onto the whole raster.
    void draw(std::size_t j, const Vec3& c, const detail::HemicubeFace& face, int w, int h,
              std::vector<std::int32_t>& id, std::vector<double>& depth) const {
        const auto poly = table().polygon(j);
        const double A = (far_ + near_) / (far_ - near_), B = -2.0 * far_ * near_ / (far_ - near_);
        std::array<Vec4, 16> clip;
        std::vector<Vec4> big;
        Vec4* p = poly.size() <= clip.size() ? clip.data() : (big.resize(poly.size()), big.data());
        // Frustum culling by outcodes (Cohen & Sutherland): a polygon whose vertices are all
        // beyond one plane of the face's frustum cannot cover a pixel. Most patches lie in
        // one or two of the five faces, so this skips most of the rasteriser's setup.
        unsigned outside = ~0u;
        for (std::size_t k = 0; k < poly.size(); ++k) {
            const Vec3 d = poly[k] - c;
            const double x = glm::dot(d, face.right), y = glm::dot(d, face.up);
            const double f = glm::dot(d, face.forward);
            p[k] = Vec4(x, face.side ? 2.0 * y - f : y, A * f + B, f);
            const double X = p[k].x, Y = p[k].y, W = p[k].w;
            outside &= (W <= near_ ? 1u : 0u) | (X > W ? 2u : 0u) | (X < -W ? 4u : 0u) |
                       (Y > W ? 8u : 0u) | (Y < -W ? 16u : 0u);
        }
        if (outside != 0u) return;
        const auto index = static_cast<std::int32_t>(j);
        for (std::size_t k = 1; k + 1 < poly.size(); ++k)
            rasterize_triangle({p[0], p[k], p[k + 1]}, w, h, [&](const Fragment& frag) {
                const auto at = static_cast<std::size_t>(frag.y * w + frag.x);
                if (frag.depth < depth[at]) {
                    depth[at] = frag.depth;
                    id[at] = index;
                }
            });
    }

    /// Adds the delta form factor of every pixel to the patch seen there, if it shows patch i
    /// its front; a patch seen from behind keeps its pixels (it occludes) but takes nothing.
    void accumulate(std::size_t i, const std::vector<double>& dff,
                    const std::vector<std::int32_t>& id, std::vector<double>& F) const {
        const PatchTable& t = table();
        const Vec3& c = t.centroid(i);
        for (std::size_t k = 0; k < id.size(); ++k) {
            if (id[k] < 0) continue;
            const auto j = static_cast<std::size_t>(id[k]);
            if (glm::dot(c - t.centroid(j), t.normal(j)) > 0.0) F[j] += dff[k];
        }
    }

    HemicubeOptions options_;
    const PatchTable* patches_ = nullptr;
    std::vector<double> top_dff_, side_dff_;
    double near_ = 1e-7, far_ = 1.0;
};

static_assert(FormFactorMethod<Hemicube>);

}  // namespace radiosity
