// The visibility seam: every Visibility model answers as the definition (every triangle tested,
// BruteForceVisibility), and the form-factor methods over any model give the Cornell box's rows:
// bit for bit over the brute force and the BVH (the same rays; the BVH's pair culling, which
// the brute force lacks, casts none where none can be blocked), and over Embree (when built with
// RADIOSITY_WITH_EMBREE) but for rays that single precision might decide otherwise.
#include <radiosity/form_factor/analytic.hpp>
#include <radiosity/form_factor/pair_culling.hpp>
#include <radiosity/form_factor/ray_cast.hpp>
#include <radiosity/geometry/brute_force_visibility.hpp>
#include <radiosity/geometry/bvh.hpp>
#include <radiosity/geometry/sampling.hpp>
#include <radiosity/io/scenes.hpp>
#include <radiosity/mesh/mesh.hpp>
#include <radiosity/mesh/subdivide.hpp>
#if defined(RADIOSITY_WITH_EMBREE)
#include <radiosity/geometry/embree.hpp>
#endif

#include "../benchmarks/support/rooms.hpp"
#include "support/threads.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

using namespace radiosity;

namespace {

/// 16 rays per pair that may be blocked: the models are compared ray for ray, and the brute
/// force tests every triangle for each.
const RayCastOptions few_rays{.samples_per_form_factor = 0.0};

/// The Cornell box with its blocks, subdivided to edges of at most 150 mm (158 patches: the
/// brute force tests every triangle for every ray).
const PatchTable& cornell() {
    static const PatchTable t =
        make_patch_table(subdivide(build_mesh(cornell_box<Rgb>()), {.max_edge = 150.0}));
    return t;
}

/// Every other patch of the Cornell box but those of the red wall (normal -x), whose rows cost
/// seconds: the published wall is 3.2 mm off planar, and its neighbours, nearly coplanar and
/// facing each other by a fraction of a degree, drive the near-field quadrature to its depth
/// limit (the same for every visibility model; the columns keep them).
std::vector<std::size_t> cornell_rows() {
    const PatchTable& t = cornell();
    std::vector<std::size_t> out;
    for (std::size_t i = 0; i < t.size(); i += 2)
        if (t.normal(i).x > -0.9) out.push_back(i);
    return out;
}

/// The rows of a method over the table, one after another.
template <class Method>
std::vector<std::vector<float>> rows(Method method, const PatchTable& t,
                                     const std::vector<std::size_t>& which) {
    method.prepare(t);
    std::vector<std::vector<float>> out;
    for (const std::size_t i : which) {
        out.emplace_back(t.size());
        method.row(i, out.back());
    }
    return out;
}

/// Entries of a and b whose bits differ.
std::size_t differing(const std::vector<std::vector<float>>& a,
                      const std::vector<std::vector<float>>& b) {
    std::size_t n = 0;
    for (std::size_t r = 0; r < a.size(); ++r)
        for (std::size_t j = 0; j < a[r].size(); ++j)
            n += std::memcmp(&a[r][j], &b[r][j], sizeof(float)) != 0;
    return n;
}

/// Entries that are not zero (rows that see something).
std::size_t nonzero(const std::vector<std::vector<float>>& a) {
    std::size_t n = 0;
    for (const auto& row : a)
        n += static_cast<std::size_t>(
            std::count_if(row.begin(), row.end(), [](float f) { return f != 0.0f; }));
    return n;
}

/// A closed 4 x 4 x 4 room with nine blocks standing on its floor, sharing the floor's plane.
PatchTable cluttered_room() {
    PatchTable t;
    bench::add_box(t, Vec3(0.0), Vec3(4.0), 3, true);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            bench::add_box(t, Vec3(0.3 + a * 1.3, 0.0, 0.3 + b * 1.3),
                           Vec3(1.1 + a * 1.3, 0.5 + 0.4 * a, 1.1 + b * 1.3), 2, false);
    return t;
}

}  // namespace

TEST_CASE("the BVH answers every occlusion query as the brute force, which tests every triangle") {
    // Random segments, and segments between centroids and vertices of patches sharing planes
    // and edges, where a shortcut would go wrong first.
    const PatchTable t = cluttered_room();
    const Bvh bvh(t);
    const BruteForceVisibility brute(t);
    CHECK(brute.triangle_count() == bvh.triangle_count());
    Rng rng(5);
    std::vector<Vec3> xs, ys;
    int disagree = 0, blocked = 0;
    for (int k = 0; k < 3000; ++k) {
        const auto a = static_cast<std::uint32_t>(rng.uniform() * double(t.size()));
        const auto b = static_cast<std::uint32_t>(rng.uniform() * double(t.size()));
        if (a == b) continue;
        jittered_pairs(t.polygon(a), t.polygon(b), 1, rng, xs, ys);
        const std::array<std::array<Vec3, 2>, 3> segments{
            {{xs[0], ys[0]}, {t.centroid(a), t.centroid(b)}, {t.polygon(a)[0], t.polygon(b)[1]}}};
        for (const auto& [p, q] : segments) {
            const bool hidden = brute.occluded(p, q, a, b);
            blocked += hidden;
            disagree += hidden != bvh.occluded(p, q, a, b);
        }
    }
    CHECK(disagree == 0);
    CHECK(blocked > 1000);  // both answers occur
}

TEST_CASE("the BVH's build gives the same nodes and leaf order on one thread and on two" *
          doctest::skip(test::threads::without_openmp)) {
    // Above 32,768 primitives the two halves of a node are built by two threads and joined;
    // the joined tree must be the one the plain recursion lays out, box for box and index for
    // index (a ray's walk, and so every visibility answer, follows the layout). 65,536 random
    // boxes: the top's halves built apart and joined.
    Rng rng(7);
    std::vector<detail::Box> boxes(65536);
    std::vector<Vec3> centres(boxes.size());
    for (std::size_t k = 0; k < boxes.size(); ++k) {
        const Vec3 c(rng.uniform(), rng.uniform() * 0.5, rng.uniform() * 2.0);
        const Vec3 half(0.01 * rng.uniform(), 0.01 * rng.uniform(), 0.01 * rng.uniform());
        boxes[k].grow(c - half);
        boxes[k].grow(c + half);
        centres[k] = c;
    }
    int team = 0;  // what the two-thread build had
    const auto build = [&](int threads) {
        const test::threads::Forced forced(threads);
        team = test::threads::team_size();
        return build_bvh_nodes(boxes, centres);
    };
    const BvhNodes one = build(1), two = build(2);
    REQUIRE(team == 2);
    CHECK(one.order == two.order);
    REQUIRE(one.nodes.size() == two.nodes.size());
    CHECK(one.nodes.size() > 1000);
    CHECK(std::memcmp(one.nodes.data(), two.nodes.data(), one.nodes.size() * sizeof(BvhNode)) == 0);
}

TEST_CASE("the BVH's box walk visits exactly the triangles whose boxes an accepting test admits") {
    // Accepting every box reaches every triangle once; a query box reaches (at least) every
    // triangle overlapping it, and pruning by the box reaches no box that misses it.
    const PatchTable t = cluttered_room();
    const Bvh bvh(t);
    std::vector<int> seen(t.size(), 0);
    const bool stopped = bvh.any_triangle([](const Vec3&, const Vec3&) { return true; },
                                          [&](const PatchTriangle& tri) {
                                              ++seen[tri.patch];
                                              return false;
                                          });
    CHECK(!stopped);
    bool each_fan_once = true;
    for (std::size_t i = 0; i < t.size(); ++i)
        each_fan_once = each_fan_once && seen[i] == static_cast<int>(t.polygon(i).size()) - 2;
    CHECK(each_fan_once);
    const Vec3 lo(1.0, 0.2, 1.0), hi(2.0, 0.8, 2.5);
    auto overlaps = [&](const Vec3& l, const Vec3& h) {
        return l.x < hi.x && h.x > lo.x && l.y < hi.y && h.y > lo.y && l.z < hi.z && h.z > lo.z;
    };
    std::size_t expected = 0, found = 0, outside = 0;
    for (const PatchTriangle& tri : fan_triangles(t))
        expected += overlaps(glm::min(glm::min(tri.v[0], tri.v[1]), tri.v[2]),
                             glm::max(glm::max(tri.v[0], tri.v[1]), tri.v[2]));
    bvh.any_triangle(overlaps, [&](const PatchTriangle& tri) {
        const bool in = overlaps(glm::min(glm::min(tri.v[0], tri.v[1]), tri.v[2]),
                                 glm::max(glm::max(tri.v[0], tri.v[1]), tri.v[2]));
        found += in;
        outside += !in;
        return false;
    });
    CHECK(expected > 10);
    CHECK(found == expected);
    CHECK(outside < t.size());  // pruned: far fewer than every triangle was offered
}

TEST_CASE("ray-cast over the brute force and over the BVH: the same Cornell rows, bit for bit") {
    // The same seeds draw the same rays; the brute force casts them for every pair, the BVH
    // culls the pairs nothing can stand between (V = 1 without a ray), so equal rows also show
    // that the culling never drops a ray that would have been blocked.
    const PatchTable& t = cornell();
    const std::vector<std::size_t> which = cornell_rows();
    REQUIRE(which.size() > 50);
    const auto by_bvh = rows(RayCast(few_rays), t, which);
    const auto by_brute = rows(RayCast<BruteForceVisibility>(few_rays), t, which);
    CHECK(differing(by_bvh, by_brute) == 0);
    CHECK(nonzero(by_bvh) > t.size() * by_bvh.size() / 4);
    // The culling was at work: many facing pairs need no ray.
    const Bvh bvh(t);
    std::size_t culled = 0, facing = 0;
    for (const std::size_t i : which)
        for (std::size_t j = 0; j < t.size(); ++j) {
            if (i == j || !detail::facing(t, i, j)) continue;
            ++facing;
            culled += !pair_may_be_blocked(bvh, t, i, j);
        }
    CHECK(culled > facing / 10);
    CHECK(culled < facing);  // and the blocks hide some pairs
}

TEST_CASE("analytic with visibility over the brute force and over the BVH: the same Cornell rows") {
    const PatchTable& t = cornell();
    const std::vector<std::size_t> which = cornell_rows();
    // A coarse quadrature tolerance: the visible fraction, not the integral, is under test.
    const AnalyticOptions o{.tolerance = 1e-3, .visibility_samples = 16, .penumbra_samples = 64};
    const auto by_bvh = rows(Analytic(o), t, which);
    const auto by_brute = rows(Analytic<BruteForceVisibility>(o), t, which);
    CHECK(differing(by_bvh, by_brute) == 0);
    // Visibility is on: the blocks hide something, so the rows differ from those without.
    CHECK(differing(by_bvh, rows(Analytic({.tolerance = 1e-3}), t, which)) > 0);
}

#if defined(RADIOSITY_WITH_EMBREE)
TEST_CASE("ray-cast and analytic over Embree give the Cornell rows of the BVH") {
    // The same rays. Embree tests them in single precision, from 1e-6 to 1 - 1e-6 of each
    // segment, with the SIMD width of the CPU it runs on: a ray that grazes an edge could be
    // answered otherwise, and its pair's entries move. On the machine of the tests (Embree
    // 3.13) no entry differs, bit for bit; allowed: one entry in a thousand.
    const PatchTable& t = cornell();
    const std::vector<std::size_t> which = cornell_rows();
    const std::size_t entries = t.size() * which.size();
    const auto by_bvh = rows(RayCast(few_rays), t, which);
    const auto by_embree = rows(RayCast<EmbreeVisibility>(few_rays), t, which);
    CAPTURE(differing(by_bvh, by_embree));
    CHECK(differing(by_bvh, by_embree) <= entries / 1000);
    const AnalyticOptions o{.tolerance = 1e-3, .visibility_samples = 16, .penumbra_samples = 64};
    const auto analytic_bvh = rows(Analytic(o), t, which);
    const auto analytic_embree = rows(Analytic<EmbreeVisibility>(o), t, which);
    CAPTURE(differing(analytic_bvh, analytic_embree));
    CHECK(differing(analytic_bvh, analytic_embree) <= entries / 1000);
}
#endif
