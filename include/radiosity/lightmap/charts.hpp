#pragma once
/// @file charts.hpp  Chart segmentation and flattening for lightmap UVs. The faces are split into
/// charts, connected faces of similar normal grown greedily from seeds (a simple form of the
/// chart growing of Levy et al. 2002, "Least squares conformal maps", sec. 5); a face whose
/// projection would overlap the chart is left for another chart, so no chart covers itself.
/// Each chart is projected orthogonally onto the plane of its area-weighted mean normal and
/// turned in that plane to its minimum-area bounding rectangle (Freeman & Shapira 1975, found
/// by rotating calipers, Toussaint 1983). A planar chart (a wall, a floor, a side of a box) is
/// flattened without distortion: the projection is then an isometry, so every lightmap texel
/// covers the same area. A curved chart is foreshortened: the area of each face shrinks by the
/// cosine of the angle between its normal and the chart's.

#include <radiosity/error.hpp>
#include <radiosity/geometry/polygon.hpp>
#include <radiosity/geometry/vec.hpp>
#include <radiosity/mesh/mesh.hpp>
#include <radiosity/mesh/weld.hpp>
#include <radiosity/shading/vertex_shading.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <numeric>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

namespace radiosity {

/// Settings of the chart segmentation.
struct ChartOptions {
    double max_chart_angle_degrees = 45.0;  ///< faces whose normals differ more from the seed's
                                            ///< normal start a new chart; in (0, 90)
    double crease_angle_degrees = 30.0;     ///< never cross an edge sharper than this
    bool split_materials = true;            ///< never cross a change of material
};

/// One chart: faces flattened together into the plane, in scene units, placed so that its
/// bounding rectangle is [0, extent.x] x [0, extent.y] with the long side along u (x).
struct Chart {
    std::vector<std::uint32_t> faces;         ///< mesh face indices, in the order they joined
    std::vector<std::uint32_t> first_corner;  ///< face k's corners are corner[first_corner[k]..
                                              ///< first_corner[k + 1]); one more entry than faces
    std::vector<Vec2> corner;  ///< 2-D position of every face corner (in fv_range order)
    Vec2 extent{0.0};          ///< width (>= height) and height of the bounding rectangle
    Vec3 normal{0.0};          ///< unit normal of the plane the chart was projected onto

    /// The 2-D corners of the chart's k-th face, in the order of mesh.fv_range(faces[k]).
    std::span<const Vec2> corners(std::size_t k) const {
        return std::span<const Vec2>(corner).subspan(first_corner[k],
                                                     first_corner[k + 1] - first_corner[k]);
    }
};

namespace detail {

/// The mesh's faces as flat arrays: corner points, and per face its Newell vector (normal times
/// twice the area), unit normal and area.
struct FaceGeometry {
    std::vector<Vec3> point;            // corners of all faces, face after face
    std::vector<std::uint32_t> first;   // face f's corners: point[first[f]..first[f + 1])
    std::vector<std::uint32_t> welded;  // merged vertex id of every corner
    std::vector<Vec3> newell, normal;   // per face
    std::vector<double> area;           // per face
    double diagonal = 0.0;              // of the scene's bounding box
    std::size_t faces() const { return area.size(); }
};

/// Throws Error for a chart angle outside (0, 90) or a crease angle outside (0, 180] degrees.
inline void check_chart_options(const ChartOptions& options) {
    const double angle = options.max_chart_angle_degrees, crease = options.crease_angle_degrees;
    if (!(angle > 0.0 && angle < 90.0))
        throw Error("charts: max chart angle must lie in (0, 90) degrees, not " +
                    std::to_string(angle));
    if (!(crease > 0.0 && crease <= 180.0))
        throw Error("charts: crease angle must lie in (0, 180] degrees, not " +
                    std::to_string(crease));
}

/// Gathers the faces' corners and merges coincident vertices (within 1e-9 of the scene's size)
/// into one id, so that faces that do not share vertex handles (separate quads of one wall,
/// polygon soups from files) are still adjacent across their common edges (weld.hpp).
template <class M>
FaceGeometry face_geometry(const M& mesh) {
    FaceGeometry g;
    const MeshWeld w = weld_mesh(mesh);
    const std::vector<Vec3>& p = w.point;
    const std::vector<std::size_t>& group = w.group;
    g.diagonal = w.diagonal;

    g.first.push_back(0);
    for (auto f : mesh.faces()) {
        const std::size_t begin = g.point.size();
        for (auto v : mesh.fv_range(f)) {
            const auto i = static_cast<std::size_t>(v.idx());
            g.point.push_back(p[i]);
            g.welded.push_back(static_cast<std::uint32_t>(group[i]));
        }
        g.first.push_back(static_cast<std::uint32_t>(g.point.size()));
        const std::span<const Vec3> poly(g.point.data() + begin, g.point.size() - begin);
        const Vec3 n = newell_vector(poly);
        const double len = glm::length(n);
        g.newell.push_back(n);
        g.normal.push_back(len > 0.0 ? n / len : Vec3(0.0));
        g.area.push_back(0.5 * len);
    }
    return g;
}

/// Face adjacency across geometric edges (pairs of welded vertex ids), in compressed rows:
/// the neighbours of face f are neighbour[start[f]..start[f + 1]), sorted. An edge of three or
/// more faces joins all of them. O(corners log corners).
struct Adjacency {
    std::vector<std::uint32_t> start, neighbour;
};

inline Adjacency face_adjacency(const FaceGeometry& g) {
    struct Side {
        std::uint32_t lo, hi, face;
        bool operator<(const Side& o) const {
            return lo != o.lo ? lo < o.lo : hi != o.hi ? hi < o.hi : face < o.face;
        }
    };
    std::vector<Side> sides;
    sides.reserve(g.point.size());
    for (std::size_t f = 0; f < g.faces(); ++f)
        for (std::uint32_t k = g.first[f]; k < g.first[f + 1]; ++k) {
            const std::uint32_t next = k + 1 < g.first[f + 1] ? k + 1 : g.first[f];
            const auto [a, b] = std::minmax(g.welded[k], g.welded[next]);
            if (a != b) sides.push_back({a, b, static_cast<std::uint32_t>(f)});
        }
    std::sort(sides.begin(), sides.end());
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    for (std::size_t s = 0; s < sides.size();) {
        std::size_t e = s;
        while (e < sides.size() && sides[e].lo == sides[s].lo && sides[e].hi == sides[s].hi) ++e;
        for (std::size_t i = s; i < e; ++i)
            for (std::size_t j = s; j < e; ++j)
                if (sides[i].face != sides[j].face)
                    pairs.emplace_back(sides[i].face, sides[j].face);
        s = e;
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    Adjacency adj;
    adj.start.assign(g.faces() + 1, 0);
    for (const auto& pr : pairs) ++adj.start[pr.first + 1];
    for (std::size_t f = 0; f < g.faces(); ++f) adj.start[f + 1] += adj.start[f];
    adj.neighbour.reserve(pairs.size());
    for (const auto& pr : pairs) adj.neighbour.push_back(pr.second);  // pairs are sorted by face
    return adj;
}

using Triangle2 = std::array<Vec2, 3>;

/// Twice the signed area of a 2-D triangle: positive when counter-clockwise.
inline double signed_area2(const Vec2& a, const Vec2& b, const Vec2& c) {
    return cross2(b - a, c - a);
}

/// Whether two triangles' interiors overlap by more than tol, by the separating axis theorem:
/// two convex polygons are disjoint exactly when the projections onto the normal of one of
/// their edges are (Gottschalk et al. 1996). Faces that only touch along an edge or at a vertex
/// project onto such an axis with an overlap of 0 (up to rounding), so they do not count.
inline bool triangles_overlap(const Triangle2& a, const Triangle2& b, double tol) {
    for (const Triangle2* t : {&a, &b})
        for (int k = 0; k < 3; ++k) {
            const Vec2 e = (*t)[(k + 1) % 3] - (*t)[k];
            const double len = glm::length(e);
            if (len == 0.0) continue;
            const Vec2 axis(-e.y / len, e.x / len);
            double a_lo = std::numeric_limits<double>::max(), a_hi = -a_lo;
            double b_lo = a_lo, b_hi = a_hi;
            for (const Vec2& p : a) {
                a_lo = std::min(a_lo, glm::dot(p, axis));
                a_hi = std::max(a_hi, glm::dot(p, axis));
            }
            for (const Vec2& p : b) {
                b_lo = std::min(b_lo, glm::dot(p, axis));
                b_hi = std::max(b_hi, glm::dot(p, axis));
            }
            if (a_hi <= b_lo + tol || b_hi <= a_lo + tol) return false;
        }
    return true;
}

/// The triangles of one chart in a uniform hash grid, so that testing a new triangle for
/// overlap looks only at the triangles in the cells its bounding box covers: growing a chart
/// costs about O(its faces), not O(faces^2).
class OverlapGrid {
  public:
    OverlapGrid(double cell, double tol) : cell_(cell), tol_(tol) {}

    /// Whether t overlaps a triangle already in the grid.
    bool overlaps(const Triangle2& t) {
        ++stamp_;  // each stored triangle is tested at most once per query
        bool hit = false;
        visit(t, false, [&](std::vector<std::uint32_t>& list) {
            for (std::uint32_t i : list) {
                if (seen_[i] == stamp_) continue;
                seen_[i] = stamp_;
                if (triangles_overlap(t, triangles_[i], tol_)) return hit = true;
            }
            return false;
        });
        return hit;
    }

    void insert(const Triangle2& t) {
        const auto id = static_cast<std::uint32_t>(triangles_.size());
        triangles_.push_back(t);
        seen_.push_back(0);
        visit(t, true, [&](std::vector<std::uint32_t>& list) {
            list.push_back(id);
            return false;
        });
    }

  private:
    /// Calls f on the list of every cell that t's bounding box (grown by tol) covers, until f
    /// returns true; empty cells are skipped, or made when `make` is set.
    template <class F>
    void visit(const Triangle2& t, bool make, F&& f) {
        Vec2 lo = glm::min(glm::min(t[0], t[1]), t[2]) - tol_;
        Vec2 hi = glm::max(glm::max(t[0], t[1]), t[2]) + tol_;
        const auto x0 = static_cast<std::int64_t>(std::floor(lo.x / cell_));
        const auto x1 = static_cast<std::int64_t>(std::floor(hi.x / cell_));
        const auto y0 = static_cast<std::int64_t>(std::floor(lo.y / cell_));
        const auto y1 = static_cast<std::int64_t>(std::floor(hi.y / cell_));
        for (std::int64_t y = y0; y <= y1; ++y)
            for (std::int64_t x = x0; x <= x1; ++x) {
                const std::uint64_t key = (static_cast<std::uint64_t>(x) << 32) ^
                                          static_cast<std::uint64_t>(static_cast<std::uint32_t>(y));
                if (make) {
                    if (f(cells_[key])) return;
                } else if (const auto it = cells_.find(key); it != cells_.end()) {
                    if (f(it->second)) return;
                }
            }
    }

    double cell_, tol_;
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
    std::vector<Triangle2> triangles_;
    std::vector<std::uint32_t> seen_;
    std::uint32_t stamp_ = 0;
};

/// An orthonormal frame (t, b, n) of a plane: t x b = n, so a polygon counter-clockwise about n
/// stays counter-clockwise in (t, b) coordinates.
struct PlaneFrame {
    Vec3 t, b, n;
    explicit PlaneFrame(const Vec3& normal) : n(normal) {
        // Cross with the axis least aligned with n: never near-parallel, so t is well defined.
        // (orthonormal_basis would do as well, but would turn every chart of the UV layout.)
        const Vec3 a = std::abs(n.x) <= std::abs(n.y) && std::abs(n.x) <= std::abs(n.z)
                           ? Vec3(1, 0, 0)
                       : std::abs(n.y) <= std::abs(n.z) ? Vec3(0, 1, 0)
                                                        : Vec3(0, 0, 1);
        t = glm::normalize(glm::cross(n, a));
        b = glm::cross(n, t);
    }
    Vec2 project(const Vec3& p, const Vec3& origin) const {
        return {glm::dot(p - origin, t), glm::dot(p - origin, b)};
    }
};

/// Projects face f into the frame and cuts it into a fan of triangles; false when a triangle
/// is not counter-clockwise (the face would be mirrored or folded in the chart).
inline bool project_face(const FaceGeometry& g, std::size_t f, const PlaneFrame& frame,
                         const Vec3& origin, std::vector<Triangle2>& out) {
    out.clear();
    const Vec2 c0 = frame.project(g.point[g.first[f]], origin);
    bool positive = true;
    for (std::uint32_t k = g.first[f] + 1; k + 1 < g.first[f + 1]; ++k) {
        const Triangle2 t{c0, frame.project(g.point[k], origin),
                          frame.project(g.point[k + 1], origin)};
        positive = positive && signed_area2(t[0], t[1], t[2]) > 0.0;
        out.push_back(t);
    }
    return positive;
}

/// Whether the chart's faces, projected into this frame, are all counter-clockwise and have no
/// overlapping interiors. O(faces) with the grid.
inline bool chart_projects_cleanly(const FaceGeometry& g, std::span<const std::uint32_t> faces,
                                   const PlaneFrame& frame, const Vec3& origin, double cell,
                                   double tol) {
    OverlapGrid grid(cell, tol);
    std::vector<Triangle2> tris;
    for (std::uint32_t f : faces) {
        if (!project_face(g, f, frame, origin, tris)) return false;
        for (const Triangle2& t : tris)
            if (grid.overlaps(t)) return false;
        for (const Triangle2& t : tris) grid.insert(t);
    }
    return true;
}

/// Convex hull of 2-D points, counter-clockwise, without collinear points (Andrew 1979,
/// monotone chain). O(n log n).
inline std::vector<Vec2> convex_hull(std::vector<Vec2> p) {
    std::sort(p.begin(), p.end(),
              [](const Vec2& a, const Vec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    p.erase(std::unique(p.begin(), p.end()), p.end());
    if (p.size() < 3) return p;
    std::vector<Vec2> h(2 * p.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {  // lower hull
        while (k >= 2 && signed_area2(h[k - 2], h[k - 1], p[i]) <= 0.0) --k;
        h[k++] = p[i];
    }
    for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {  // upper hull
        while (k >= t && signed_area2(h[k - 2], h[k - 1], p[i]) <= 0.0) --k;
        h[k++] = p[i];
    }
    h.resize(k - 1);  // the last point is the first again
    return h;
}

/// Unit direction of the long side of the minimum-area rectangle around a convex polygon
/// (counter-clockwise). Some side of the minimum rectangle lies on a hull edge (Freeman &
/// Shapira 1975), so each edge direction is tried, and rotating calipers (Toussaint 1983) keep
/// the extreme points along and across it in O(1) amortised per edge: O(n) in all.
inline Vec2 min_area_rectangle_axis(std::span<const Vec2> hull) {
    const std::size_t n = hull.size();
    if (n < 3) return n == 2 && hull[0] != hull[1] ? glm::normalize(hull[1] - hull[0]) : Vec2(1, 0);
    double best = std::numeric_limits<double>::max();
    Vec2 axis(1, 0);
    std::size_t right = 1, top = 1, left = 1;  // farthest along e, across e, against e
    for (std::size_t i = 0; i < n; ++i) {
        const Vec2 e = glm::normalize(hull[(i + 1) % n] - hull[i]);
        const Vec2 up(-e.y, e.x);  // into the polygon, which lies to the left of its edges
        auto along = [&](std::size_t k) { return glm::dot(hull[k % n], e); };
        auto across = [&](std::size_t k) { return glm::dot(hull[k % n], up); };
        while (along(right + 1) > along(right)) right = (right + 1) % n;
        if (i == 0) top = right;
        while (across(top + 1) > across(top)) top = (top + 1) % n;
        if (i == 0) left = top;
        while (along(left + 1) < along(left)) left = (left + 1) % n;
        const double w = along(right) - along(left);
        const double h = across(top) - across(i);
        // Strictly smaller by a margin, so that among equal rectangles the first one is kept
        // whatever the rounding: the result does not flicker between runs or platforms.
        if (w * h < best * (1.0 - 1e-12)) {
            best = w * h;
            axis = w >= h ? e : up;
        }
    }
    return axis;
}

}  // namespace detail

/// Splits the mesh's faces into charts and flattens each (see the file comment). Faces are
/// adjacent when they share a geometric edge after coincident vertices are merged. Each chart
/// grows breadth-first from a seed, the largest face not yet in a chart (ties by index), over
/// neighbours whose normal lies within max_chart_angle_degrees of the seed's. It never crosses
/// an edge where smooth shading breaks (a crease sharper than crease_angle_degrees, or a change
/// of material): the light may jump there, and a jump inside a chart would be blurred across the
/// edge by the texture's bilinear filter (an emitter's light leaking onto its frame); a face whose
/// projection onto the seed's plane would overlap the chart's interior, or be mirrored, is
/// left for a later chart. The chart is then projected onto the plane of its area-weighted
/// mean normal (or kept in the seed's plane where that projection would fold or overlap) and
/// turned to its minimum-area bounding rectangle, long side along u. Deterministic. Throws
/// Error for angles outside their ranges (check_chart_options). Cost: about O(n log n) for n
/// corners.
template <class M>
std::vector<Chart> make_charts(const M& mesh, const ChartOptions& options = {}) {
    detail::check_chart_options(options);
    const double angle = options.max_chart_angle_degrees;
    const detail::FaceGeometry g = detail::face_geometry(mesh);
    const detail::Adjacency adj = detail::face_adjacency(g);
    const std::size_t nf = g.faces();
    const double min_cos = std::cos(angle * std::numbers::pi / 180.0);
    const double crease_cos = std::cos(options.crease_angle_degrees * std::numbers::pi / 180.0);
    // Whether light is continuous across the edge between faces a and b (as smooth shading has it).
    auto material = [&](std::uint32_t f) -> std::uint32_t {
        if constexpr (requires { mesh.data(typename M::FaceHandle(0)).material; })
            if (options.split_materials)
                return mesh.data(typename M::FaceHandle(static_cast<int>(f))).material;
        return 0;
    };
    auto smooth = [&](std::uint32_t a, std::uint32_t b) {
        return light_continuous(g.normal[a], g.normal[b], material(a), material(b), crease_cos);
    };
    // Overlaps smaller than this (scene units) are rounding, e.g. two unmerged copies of an edge.
    const double tol = 1e-8 * g.diagonal;
    // Cells of the mean face size: a face covers about one cell, a cell holds about one face.
    double total_area = 0.0;
    for (double a : g.area) total_area += a;
    double cell = nf > 0 ? std::sqrt(total_area / static_cast<double>(nf)) : 1.0;
    if (!(cell > 0.0)) cell = g.diagonal > 0.0 ? g.diagonal : 1.0;

    std::vector<std::uint32_t> seeds(nf);
    std::iota(seeds.begin(), seeds.end(), std::uint32_t{0});
    std::stable_sort(seeds.begin(), seeds.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return g.area[a] > g.area[b]; });

    constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> chart_of(nf, none), visited(nf, none);
    std::vector<Chart> charts;
    std::vector<detail::Triangle2> tris;
    for (std::uint32_t seed : seeds) {
        if (chart_of[seed] != none) continue;
        const auto id = static_cast<std::uint32_t>(charts.size());
        Chart chart;
        // Grow in the seed's plane: every accepted face is within the angle of its normal, so
        // its projection keeps its orientation and shrinks its area by at most cos(angle).
        const Vec3 seed_normal = g.normal[seed] != Vec3(0.0) ? g.normal[seed] : Vec3(0, 0, 1);
        const detail::PlaneFrame seed_frame(seed_normal);
        const Vec3 origin = g.point[g.first[seed]];
        detail::OverlapGrid grid(cell, tol);
        detail::project_face(g, seed, seed_frame, origin, tris);
        for (const auto& t : tris) grid.insert(t);
        chart_of[seed] = id;
        visited[seed] = id;
        chart.faces.push_back(seed);
        for (std::size_t head = 0; head < chart.faces.size(); ++head) {
            const std::uint32_t f = chart.faces[head];
            for (std::uint32_t k = adj.start[f]; k < adj.start[f + 1]; ++k) {
                const std::uint32_t n = adj.neighbour[k];
                if (chart_of[n] != none || visited[n] == id || !smooth(f, n)) continue;
                visited[n] = id;  // refused faces stay refused: the chart only grows
                if (glm::dot(g.normal[n], seed_normal) < min_cos) continue;
                if (!detail::project_face(g, n, seed_frame, origin, tris)) continue;
                if (std::any_of(tris.begin(), tris.end(),
                                [&](const auto& t) { return grid.overlaps(t); }))
                    continue;
                for (const auto& t : tris) grid.insert(t);
                chart_of[n] = id;
                chart.faces.push_back(n);
            }
        }
        // The mean plane spreads the foreshortening of a curved chart evenly over its faces.
        // Projecting there can fold or overlap what the seed's plane did not (the two
        // projections differ), so it is checked, and the seed's plane kept where it fails.
        Vec3 sum(0.0);
        for (std::uint32_t f : chart.faces) sum += g.newell[f];
        Vec3 normal = seed_normal;
        if (chart.faces.size() > 1 && glm::length(sum) > 0.0) {
            const Vec3 mean = glm::normalize(sum);
            if (glm::dot(mean, seed_normal) < 1.0 - 1e-15 &&
                detail::chart_projects_cleanly(g, chart.faces, detail::PlaneFrame(mean), origin,
                                               cell, tol))
                normal = mean;
        }
        const detail::PlaneFrame frame(normal);
        chart.normal = normal;
        chart.first_corner.push_back(0);
        for (std::uint32_t f : chart.faces) {
            for (std::uint32_t k = g.first[f]; k < g.first[f + 1]; ++k)
                chart.corner.push_back(frame.project(g.point[k], origin));
            chart.first_corner.push_back(static_cast<std::uint32_t>(chart.corner.size()));
        }
        // Turn the chart so its minimum-area rectangle is axis-aligned, long side along u. A
        // rotation (no mirror) keeps every face counter-clockwise.
        const std::vector<Vec2> hull = detail::convex_hull(chart.corner);
        const Vec2 a = detail::min_area_rectangle_axis(hull);
        Vec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        for (Vec2& p : chart.corner) {
            p = Vec2(glm::dot(p, a), -a.y * p.x + a.x * p.y);
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        chart.extent = hi - lo;
        for (Vec2& p : chart.corner) p -= lo;
        if (chart.extent.y >
            chart.extent.x) {  // rounding made a near-square taller: turn 90 degrees
            for (Vec2& p : chart.corner) p = Vec2(p.y, chart.extent.x - p.x);
            chart.extent = Vec2(chart.extent.y, chart.extent.x);
        }
        charts.push_back(std::move(chart));
    }
    return charts;
}

}  // namespace radiosity
