#pragma once
/// @file links.hpp  Links of hierarchical radiosity and what a link carries: the transfer
/// coefficient between two nodes and its visibility. Between elements, the form factor by
/// Lambert's contour integral (Hanrahan, Salzman & Aupperle 1991) and jittered rays through the
/// scene's BVH; with a cluster at one end, both sampled over the cluster's true faces, and the
/// isotropic cluster (Sillion 1995) only as the refinement oracle's cheap estimate. The receiver
/// gathers B_source * coefficient * visibility as irradiance.

#include <radiosity/concepts.hpp>
#include <radiosity/detail/bulk_memory.hpp>
#include <radiosity/detail/parallel.hpp>
#include <radiosity/form_factor/analytic.hpp>
#include <radiosity/geometry/sampling.hpp>
#include <radiosity/hierarchy/nodes.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace radiosity {

/// A link: receiver r gathers H_r += coefficient * visibility * B_s from source s. 16 bytes.
/// The coefficient is the unoccluded transfer (the form factor F_rs for two elements) and the
/// visibility the fraction of rays between them that nothing blocks, kept apart so that the
/// refinement oracle can judge a shadowed link by what it would carry unshadowed. A link with a
/// mixed cluster at either end also divides its light among the orientation classes of the
/// cluster's faces (ClassShares), which is kept beside the links, not in them (the refinement
/// lists it as it samples; class_shares hands it to the sweeps), so that the millions of links
/// a refinement round makes, sorts and sends between ranks stay small.
struct Link {
    NodeId receiver;    ///< r
    NodeId source;      ///< s
    float coefficient;  ///< T_rs, unoccluded
    float visibility;   ///< V_rs in [0, 1]
};
static_assert(sizeof(Link) == 16);

/// A list of links: a rank's settled links, a refinement round's tasks and frontier. Large, and
/// filled afresh in every round, so in huge pages where the kernel offers them (bulk_memory.hpp).
using LinkVector = std::vector<Link, detail::BulkAllocator<Link>>;

/// Whether a link's split among orientation classes was measured (is not all 0). (Not by
/// operator==, which calls memcmp: 5% of room3's solve.)
inline bool measured(const std::array<std::uint8_t, facing_classes>& split) {
    unsigned any = 0;
    for (const std::uint8_t x : split) any |= x;
    return any != 0;
}

/// Shares (non-negative, any sum) in 255ths that sum to 255, by largest remainders (Hamilton's
/// method), so that rounding neither makes nor loses light; all 0 where the shares sum to 0.
inline std::array<std::uint8_t, facing_classes> in_255ths(
    const std::array<double, facing_classes>& share) {
    std::array<std::uint8_t, facing_classes> q{};
    double sum = 0.0;
    for (double x : share) sum += x;
    if (!(sum > 0.0)) return q;
    std::array<double, facing_classes> rest{};
    int given = 0;
    for (std::size_t d = 0; d < facing_classes; ++d) {
        const double x = 255.0 * share[d] / sum;
        q[d] = static_cast<std::uint8_t>(std::floor(x));
        rest[d] = x - q[d];
        given += q[d];
    }
    for (; given < 255; ++given) {  // at most facing_classes - 1 more, to the largest remainders
        const auto d = std::size_t(std::max_element(rest.begin(), rest.end()) - rest.begin());
        ++q[d];
        rest[d] = -1.0;
    }
    return q;
}

/// The order of a rank's links for every gather: by receiver, then source (a strict weak
/// order; links are unique per pair, so the sorted order never depends on where they came from).
inline bool link_order(const Link& a, const Link& b) {
    return a.receiver < b.receiver || (a.receiver == b.receiver && a.source < b.source);
}

/// Bits of a key that each pass of sort_by_pair's radix sort takes: 2^11 counters per thread
/// (16 KiB, in the first-level cache).
inline constexpr int radix_digit = 11;

/// The order of link_order as one 64-bit key (receiver in the high half, source in the low).
inline std::uint64_t pair_key(NodeId receiver, NodeId source) {
    return std::uint64_t(receiver) << 32 | source;
}

/// Sorts items with a receiver and a source (links, ClassShares) by link_order, whose keys
/// are unique, so that every correct sort gives the same order whatever the threads. The plain
/// version is std::sort by pair_key, as for lists of fewer than 2^16 items here. Longer lists
/// (a pass's links: room3's 700,000 took 24 to 31 ms that way, 2 threads, one piece each then
/// a merge, while nothing else ran) go by least-significant-digit radix sort (Knuth, TAOCP
/// vol. 3, 5.2.5): the key is the receiver above the source, in only as many bits as their
/// largest ids need (room3: 30; a million faces: 44), taken radix_digit bits at a time from the
/// lowest; each pass counts the digits per thread piece and then moves every item, in parallel,
/// to its digit's place, the pieces in order within each digit (a stable pass, so the order by
/// the lower digits is kept). Cost: O(n) per pass, 3 or 4 passes, and a buffer of n items.
template <class Items>
void sort_by_pair(Items& items) {
    using Item = typename Items::value_type;
    const std::size_t n = items.size();
    if (n < (std::size_t{1} << 16)) {
        std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
            return pair_key(a.receiver, a.source) < pair_key(b.receiver, b.source);
        });
        return;
    }
    NodeId last_receiver = 0, last_source = 0;
    for (const Item& x : items) {
        last_receiver = std::max(last_receiver, x.receiver);
        last_source = std::max(last_source, x.source);
    }
    const int source_bits = std::bit_width(last_source);
    const int bits = std::bit_width(last_receiver) + source_bits;
    const auto key = [source_bits](const Item& x) {
        return std::uint64_t(x.receiver) << source_bits | x.source;
    };
    constexpr int digit_bits = radix_digit;
    constexpr std::size_t digits = std::size_t{1} << digit_bits;
    const std::size_t pieces = std::size_t(detail::thread_count());
    const auto cut = [&](std::size_t p) { return n * p / pieces; };
    // Scratch from the program's allocator, left unfilled: a fresh mapping of 11 MB (room3)
    // costs more in page faults than the sort itself.
    const auto buffer = std::make_unique_for_overwrite<Item[]>(n);
    Item* from = items.data();
    Item* to = buffer.get();
    std::vector<std::size_t> place(pieces * digits);  // per piece and digit
    for (int shift = 0; shift < bits; shift += digit_bits) {
        const auto digit = [&](const Item& x) { return (key(x) >> shift) & (digits - 1); };
        std::fill(place.begin(), place.end(), std::size_t{0});
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(static, 1)
#endif
        for (std::int64_t p = 0; p < std::int64_t(pieces); ++p)
            for (std::size_t i = cut(std::size_t(p)); i < cut(std::size_t(p) + 1); ++i)
                ++place[std::size_t(p) * digits + digit(from[i])];
        std::size_t at = 0;  // digit by digit, piece by piece: where each piece's run starts
        for (std::size_t d = 0; d < digits; ++d)
            for (std::size_t p = 0; p < pieces; ++p) at += std::exchange(place[p * digits + d], at);
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(static, 1)
#endif
        for (std::int64_t p = 0; p < std::int64_t(pieces); ++p)
            for (std::size_t i = cut(std::size_t(p)); i < cut(std::size_t(p) + 1); ++i)
                to[place[std::size_t(p) * digits + digit(from[i])]++] = from[i];
        std::swap(from, to);
    }
    if (from != items.data()) std::copy(from, from + n, items.data());
}

/// Sorts links by link_order (sort_by_pair: links are unique per pair).
inline void sort_links(LinkVector& links) {
    sort_by_pair(links);
}

/// A link's transfer coefficient and how far it can be trusted.
struct Transfer {
    double coefficient = 0.0;  ///< T_rs, unoccluded irradiance at r per unit B_s
    /// An upper bound on T_rs where the estimate is unreliable (a plane cuts the other node's
    /// bounding sphere, or the two spheres overlap); equal to coefficient otherwise.
    double bound = 0.0;
    bool unreliable = false;  ///< the estimate cannot be trusted: refine if it might matter
};

/// How exactly a transfer between near elements is integrated.
enum class Accuracy : std::uint8_t {
    estimate,  ///< near pairs by the 7-point rule too: enough to decide whether to refine
    full,      ///< near pairs by adaptive quadrature: the value a kept link carries
};

namespace detail {

/// Settings of the exchange integral for the near pairs that need it (NearPair): there
/// F_dA(x)->larger steps across the smaller element, which a fixed rule serves badly.
inline constexpr AnalyticOptions near_exchange{.tolerance = 1e-2, .max_depth = 3};

/// Whether the edges of convex polygon b (counter-clockwise about its unit normal nb), seen in
/// b's plane, come within `margin` of polygon a's projection onto that plane: not where the
/// projection lies inside b at least `margin` from every edge's line, nor where it lies beyond
/// one edge's line by at least `margin`. Cost: O(corners of a x corners of b).
inline bool edges_near(std::span<const Vec3> a, std::span<const Vec3> b, const Vec3& nb,
                       double margin) {
    bool inside = true;
    for (std::size_t k = 0; k < b.size(); ++k) {
        const Vec3 inward = glm::normalize(glm::cross(nb, b[(k + 1) % b.size()] - b[k]));
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (const Vec3& q : a) {
            const double d = glm::dot(q - b[k], inward);  // signed distance to the edge's line
            lo = std::min(lo, d);
            hi = std::max(hi, d);
        }
        if (hi <= -margin) return false;  // clear of b beyond this edge
        inside = inside && lo >= margin;
    }
    return !inside;
}

/// How element_transfer integrates a near pair: over `outer`, the smaller element (ties by id,
/// so that (r, s) and (s, r) give one number, A_r F_rs = A_s F_sr), toward `inner`; by adaptive
/// quadrature with Accuracy::full (`quadrature`) where the rule fails, by the 7-point rule
/// otherwise. The rule fails where F_dA(x)->inner steps across the outer element: where x, near
/// the inner's plane, passes the prism over the inner's edges. So the quadrature takes the
/// pairs whose outer centroid lies within half the outer's radius of the inner's plane and
/// whose outer projection onto that plane comes within one outer radius of the inner's edges
/// (edges_near). Random triangles near the plane of a unit square, 200,000 pairs against
/// exchange_integral at 1e-7: where the projection kept clear of the edges by the radius, the
/// rule was within 0.27% (inside the square, 0.00%); where the edges passed through it, off by
/// up to 98%, and by more than 1% in 41% of pairs. (Room3: 45% of the kept pairs near a plane
/// keep clear of the edges and take the rule.)
struct NearPair {
    NodeId outer, inner;
    bool quadrature;
};
inline NearPair near_pair(const Hierarchy& h, NodeId r, NodeId s) {
    const bool over_r = h.area[r] < h.area[s] || (h.area[r] == h.area[s] && r < s);
    const NodeId a = over_r ? r : s, b = over_r ? s : r;
    const double height = std::abs(glm::dot(h.centre[a] - h.polygon(b)[0], h.normal[b]));
    return {a, b,
            height < 0.5 * h.radius[a] &&
                edges_near(h.polygon(a), h.polygon(b), h.normal[b], h.radius[a])};
}

/// Element to element: the form factor F_rs from the exchange integral A_r F_rs of Lambert's
/// contour integral (analytic.hpp) at a cost that follows the distance d against the reach
/// radius_r + radius_s: beyond 10 reaches the contour integral at the receiver's centroid (off
/// the receiver's mean by O((reach / d)^2), a few 1e-3); beyond 2, Dunavant's 7-point rule
/// over the receiver (exchange_by_rule, 3e-6 at 3 reaches); nearer, over the smaller of the two
/// (reciprocal by construction: A_r F_rs is one number both ways), by the rule where it holds
/// and by adaptive quadrature (exchange_integral) where it does not. The rule over the smaller
/// element holds where the integrand F_dA(x)->larger is smooth over it: for elements meeting at
/// an angle, touching or not (hinged squares from 30 to 150 degrees: within 0.6%; a quarter
/// square against a wall it touches: 0.002%); it fails where the smaller lies close and nearly
/// parallel to the larger, so that the larger's edge casts a step in F_dA over it (unit squares
/// 0.05 apart: 3%; edge to edge and 0.05 apart: 32%). So the quadrature takes the pairs whose
/// smaller element lies close to the larger's plane with the larger's edges passing by it
/// (near_pair), the rule the rest (the quadrature is five times the rule's cost, and these are
/// a few of the near pairs).
/// Accuracy::estimate (what the oracle judges a new link by) takes the rule for every near pair.
/// 0 if either lies wholly behind the other.
inline Transfer element_transfer(const Hierarchy& h, NodeId r, NodeId s,
                                 Accuracy accuracy = Accuracy::full) {
    if (behind_plane(h.polygon(s), h.centre[r], h.normal[r]) ||
        behind_plane(h.polygon(r), h.centre[s], h.normal[s]))
        return {};  // the analytic method's test: one-sided faces that do not face exchange 0
    const double d = glm::length(h.centre[s] - h.centre[r]);
    const double reach = h.radius[r] + h.radius[s];
    double F;
    if (d > 10.0 * reach) {
        F = point_to_polygon(h.centre[r], h.normal[r], h.polygon(s));
    } else if (d > 2.0 * reach) {
        F = exchange_by_rule(h.polygon(r), h.normal[r], h.polygon(s)) / h.area[r];
    } else {
        const auto [a, b, quadrature] = near_pair(h, r, s);
        F = (accuracy == Accuracy::full && quadrature
                 ? exchange_integral(h.polygon(a), h.normal[a], h.polygon(b), near_exchange)
                 : exchange_by_rule(h.polygon(a), h.normal[a], h.polygon(b))) /
            h.area[r];
    }
    return {F, F};
}

/// Whether element_transfer integrates the pair (r, s) by adaptive quadrature with
/// Accuracy::full, and so differs from its estimate: a near pair with the smaller element close
/// to the larger's plane (see there).
inline bool full_differs(const Hierarchy& h, NodeId r, NodeId s) {
    const double d = glm::length(h.centre[s] - h.centre[r]);
    return !(d > 2.0 * (h.radius[r] + h.radius[s])) && near_pair(h, r, s).quadrature;
}

/// How a node faces a direction u (unit) toward the other node at distance d with bounding
/// radius rad: an element's cos(theta) clamped at 0, a cluster's mean over orientations;
/// `facing.cut` when the element's plane cuts the other's sphere (cos is then unreliable).
struct Facing {
    double cos = 0.0;
    bool cut = false;
};
inline Facing facing(const Hierarchy& h, NodeId n, const Vec3& u, double d, double rad) {
    if (h.is_cluster(n)) return {1.0, false};
    const double c = glm::dot(h.normal[n], u);
    return {std::max(c, 0.0), std::abs(c * d) < rad};
}

/// A cluster's projected area toward direction u (unit) over its area, as the oriented model
/// has it: f max(N^ . u, 0) + (1 - f) / 4, with N = sum A n over its faces (Hierarchy::normal)
/// and f = |N| / A its flatness. Exact for coplanar faces (f = 1: a piece of a wall is an
/// element to the oracle), the isotropic cluster's 1/4 for faces that face every way alike
/// (f = 0), and in between the flat part's projection plus the rest's mean. Also the most it
/// can be toward any u, f + (1 - f) / 4 (the bound's).
struct ClusterFacing {
    double toward = 0.25, largest = 0.25;
};
inline ClusterFacing cluster_facing(const Hierarchy& h, NodeId n, const Vec3& u) {
    const double len = glm::length(h.normal[n]);
    const double f = h.area[n] > 0.0 ? std::min(len / h.area[n], 1.0) : 0.0;
    const double c = len > 0.0 ? std::max(glm::dot(h.normal[n], u) / len, 0.0) : 0.0;
    return {f * c + 0.25 * (1.0 - f), f + 0.25 * (1.0 - f)};
}

}  // namespace detail

/// How transfer() models a cluster's faces.
enum class ClusterModel : std::uint8_t {
    /// Facing every way alike (Sillion 1995): decides whether a pair can exchange anything,
    /// since it never says "nothing" of a cluster that has a face turned toward the other.
    isotropic,
    /// By its faces' area-weighted normal (detail::cluster_facing): the refinement oracle's
    /// estimate. The isotropic model takes two flat clusters facing each other, a floor's
    /// and a ceiling's, for 16 times less than they exchange (1/4 for cos, and 1/(4 pi) for
    /// cos / pi), and the oracle kept such links coarse: the tessellated Cornell box's
    /// floor took its light from links from clusters of the light with the ceiling around it,
    /// whose mean radiosity hides where the light is, and came out 9% dark in its direct light.
    oriented,
};

/// The transfer coefficient T_rs: irradiance at receiver r per unit radiosity of source s.
/// Two elements: the form factor (element_transfer). A cluster in the pair: the point-to-point
/// kernel between the nodes' centres, T = A_s g_s g_r / d^2, with g_s = cos(theta_s) / pi for an
/// element source and, for a cluster, its projected area toward r over pi A_s (`model`:
/// isotropic, 1 / (4 pi), its mean over orientations; or oriented, cluster_facing / pi), g_r =
/// cos(theta_r) for an element receiver and for a cluster its projected area toward s over A_r
/// (1/4, the mean projected area of its surfaces, Sillion 1995; or cluster_facing). Cost:
/// O(corners), or 7-14 contour integrals.
inline Transfer transfer(const Hierarchy& h, NodeId r, NodeId s, Accuracy accuracy = Accuracy::full,
                         ClusterModel model = ClusterModel::isotropic) {
    if (!h.is_cluster(r) && !h.is_cluster(s)) return detail::element_transfer(h, r, s, accuracy);
    const Vec3 rs = h.centre[s] - h.centre[r];
    const double d = glm::length(rs);
    const double reach = h.radius[r] + h.radius[s];
    const double As = h.area[s];
    if (d <= reach) return {0.0, 1.0, true};  // overlapping: no estimate, only a bound (refine)
    const Vec3 u = rs / d;
    const detail::Facing fr = detail::facing(h, r, u, d, h.radius[s]);
    const detail::Facing fs = detail::facing(h, s, -u, d, h.radius[r]);
    const bool behind_r = !h.is_cluster(r) && glm::dot(h.normal[r], rs) + h.radius[s] <= 0.0;
    const bool behind_s = !h.is_cluster(s) && -glm::dot(h.normal[s], rs) + h.radius[r] <= 0.0;
    if (behind_r || behind_s) return {};  // one lies wholly behind the other
    // A cluster's projected area over its area, toward the other node and at most; isotropic,
    // a quarter both ways (ClusterFacing's defaults).
    const auto cluster = [&](NodeId n, const Vec3& toward) {
        return model == ClusterModel::oriented ? detail::cluster_facing(h, n, toward)
                                               : detail::ClusterFacing{};
    };
    const double pi = std::numbers::pi;
    const detail::ClusterFacing cs = h.is_cluster(s) ? cluster(s, -u) : detail::ClusterFacing{};
    const detail::ClusterFacing cr = h.is_cluster(r) ? cluster(r, u) : detail::ClusterFacing{};
    const double gs = h.is_cluster(s) ? cs.toward / pi : fs.cos / pi;
    const double gr = h.is_cluster(r) ? cr.toward : fr.cos;
    const double T = As * gs * gr / (d * d);
    // Bound: both facing head-on at the nearest the spheres allow.
    const double gap = std::max(d - reach, 1e-3 * d);
    const double gs_max = h.is_cluster(s) ? cs.largest / pi : 1.0 / pi;
    const double gr_max = h.is_cluster(r) ? cr.largest : 1.0;
    const bool unreliable = fr.cut || fs.cut || d < 2.0 * reach;
    const double bound = unreliable ? std::min(1.0, As * gs_max * gr_max / (gap * gap)) : T;
    return {T, std::max(bound, T), unreliable};
}

namespace detail {

/// The point of a triangle or convex quad p for (u, v) in the unit square, uniform in area:
/// u picks the fan triangle by its share of the area and, rescaled, the position in it by the
/// area-preserving map (1 - sqrt(u), sqrt(u) (1 - v), sqrt(u) v) (Shirley 1991), as
/// stratified_points does, without its allocations (this runs for every ray of every link).
inline Vec3 polygon_point(std::span<const Vec3> p, double u, double v) {
    std::size_t t = 0;
    if (p.size() == 4) {
        const double a0 = glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
        const double a1 = glm::length(glm::cross(p[2] - p[0], p[3] - p[0]));
        const double split = a0 / (a0 + a1);
        if (u < split) {
            u /= split;
        } else {
            u = (u - split) / (1.0 - split);
            t = 1;
        }
    }
    const double s = std::sqrt(std::clamp(u, 0.0, 1.0));
    return (1.0 - s) * p[0] + s * (1.0 - v) * p[t + 1] + s * v * p[t + 2];
}

/// A root of cluster n picked with probability proportional to its area: the one whose span
/// of the prefix sums (Hierarchy::order_area) holds a uniform draw. One random number.
inline std::uint32_t uniform_root(const Hierarchy& h, NodeId n, Rng& rng) {
    const double a = h.order_area[h.member_begin[n]] + rng.uniform() * h.area[n];
    const auto first = h.order_area.begin() + h.member_begin[n] + 1,
               last = h.order_area.begin() + h.member_end[n];
    const auto pos =
        static_cast<std::uint32_t>(std::upper_bound(first, last, a) - h.order_area.begin() - 1);
    return h.order[std::min(pos, h.member_end[n] - 1)];
}

/// A uniform random point on node n, by area over a cluster's roots (uniform_root), and the
/// root it lies on. Three random numbers for a cluster, two for an element.
inline Vec3 uniform_point(const Hierarchy& h, NodeId n, Rng& rng, std::uint32_t& root) {
    if (!h.is_cluster(n)) {
        root = h.root_of(n);
        const double u = rng.uniform();
        return polygon_point(h.polygon(n), u, rng.uniform());
    }
    root = uniform_root(h, n, rng);
    const double u = rng.uniform();
    return polygon_point(h.roots.polygon(root), u, rng.uniform());
}

}  // namespace detail

/// A link's sampled transfer: the unoccluded coefficient and the visible fraction.
struct SampledTransfer {
    double coefficient = 0.0;  ///< T_rs, unoccluded
    double visibility = 1.0;   ///< the visible fraction, weighted by what each sample carries
    /// A mixed cluster receiver (Hierarchy::mixed): what its visible samples brought, by the
    /// orientation class of the face each lay on; zero for any other receiver.
    std::array<double, facing_classes> facing{};
    /// A mixed cluster source: the same by the class of the source face each sample came from.
    std::array<double, facing_classes> sending{};
};

namespace detail {

/// Whether face p is small as seen from x: x is farther from its centroid than 4 of its radii
/// (the farthest corner), so that the point-to-point kernel varies over it by no more than it
/// does over a far pair's nodes, and the kernel at a uniform point of p, times its area, stands
/// for Lambert's integral over p (the same in expectation). Cost: O(corners).
inline bool small_from(const Vec3& x, std::span<const Vec3> p) {
    Vec3 c(0.0);
    for (const Vec3& v : p) c += v;
    c /= double(p.size());
    double r2 = 0.0;
    for (const Vec3& v : p) r2 = std::max(r2, glm::dot(v - c, v - c));
    return glm::dot(x - c, x - c) > 16.0 * r2;
}

/// Clusters of at most this many faces are sampled face by face by importance (FaceChoice).
inline constexpr std::uint32_t importance_faces = 16;

/// How the samples of a link pick a face of its source cluster s, decided once per link: for a
/// small cluster near the receiver r, by a cheap estimate of what each face b carries to r's
/// centre x, the point-to-point kernel at b's centroid, A_b (cos_x + 0.05) (cos_b + 0.05) /
/// (d^2 + A_b) (never 0, so that every face that can carry anything can be picked and the
/// estimate stays unbiased; cos_x is 1 for a cluster receiver, which faces every way); for a
/// large cluster, or one farther than 4 of its radii (where the kernel varies little over it),
/// by area. One table per link, not per sample: a sample's own point would follow the kernel a
/// little better, at a cost of O(faces) square roots per sample. Cost: O(faces) once.
class FaceChoice {
  public:
    FaceChoice(const Hierarchy& h, NodeId r, NodeId s)
        : h_(h), s_(s), begin_(h.member_begin[s]), end_(h.member_end[s]) {
        const Vec3 x = h.centre[r];
        by_area_ =
            end_ - begin_ > importance_faces || glm::length(h.centre[s] - x) > 4.0 * h.radius[s];
        if (by_area_) return;
        const bool oriented = !h.is_cluster(r);
        for (std::uint32_t i = begin_; i < end_; ++i) {
            const std::uint32_t f = h.order[i];
            const Vec3 d = h.roots.centroid(f) - x;
            const double d2 = glm::dot(d, d), len = std::sqrt(d2) + 1e-300;
            const double cx = oriented ? std::max(glm::dot(h.normal[r], d) / len, 0.0) + 0.05 : 1.0;
            const double cb = std::max(-glm::dot(h.roots.normal(f), d) / len, 0.0) + 0.05;
            total_ += h.roots.area(f) * cx * cb / (d2 + h.roots.area(f));
            cumulative_[i - begin_] = total_;
        }
    }

    /// A face of s, and the probability it was picked with.
    std::uint32_t pick(Rng& rng, double& probability) const {
        if (by_area_) {
            // The draws of uniform_point, whose point is not needed: the same stream (and so
            // the same links, bit for bit) without the point's arithmetic.
            const std::uint32_t root = uniform_root(h_, s_, rng);
            rng.uniform();
            rng.uniform();
            probability = h_.roots.area(root) / h_.area[s_];
            return root;
        }
        const double u = rng.uniform() * total_;
        const std::size_t n = end_ - begin_;
        const std::size_t i = std::min<std::size_t>(
            std::size_t(std::upper_bound(cumulative_.begin(), cumulative_.begin() + n, u) -
                        cumulative_.begin()),
            n - 1);
        probability = (cumulative_[i] - (i > 0 ? cumulative_[i - 1] : 0.0)) / total_;
        return h_.order[begin_ + i];
    }

  private:
    const Hierarchy& h_;
    NodeId s_;
    std::uint32_t begin_, end_;
    bool by_area_ = true;
    double total_ = 0.0;
    std::array<double, importance_faces> cumulative_{};
};

}  // namespace detail

/// Transfer and visibility of a link with a cluster at one end, sampled (Monte Carlo over the
/// true surfaces, not the isotropic model): `samples` points x uniform by area on r, each with a
/// face b of s (FaceChoice: by importance in a small near cluster, by area otherwise, with
/// probability p_b), T_rs = mean of F(x -> b) / p_b, where F(x -> b) is Lambert's exact
/// point-to-polygon form factor (bounded, unlike the point-to-point kernel, so that near and
/// overlapping nodes are estimated as well as far ones; beyond 4 reaches, the kernel at a
/// uniform point y of b times A_b, the same in expectation and cheaper), and V = sum w V / sum w
/// from one ray per sample to y. This is the irradiance averaged over the receiver, so
/// the energy a cluster gathers is right whatever its surfaces' orientations; and, for a
/// cluster receiver, the visible samples' w summed by the orientation class of the face each
/// lay on (an unbiased estimate of what each class takes: a box's top facing the light takes
/// it all, its sides none); for a cluster source, by the class of the face each came from.
/// Seeded by the two nodes' keys. Cost: `samples` contour integrals and rays.
template <Visibility V>
SampledTransfer sampled_transfer(const Hierarchy& h, const V& scene, NodeId r, NodeId s,
                                 int samples, std::uint64_t seed) {
    Rng rng(splitmix64(seed ^ splitmix64(h.key[r]) ^ (splitmix64(h.key[s]) >> 1)));
    const bool far = glm::length(h.centre[s] - h.centre[r]) > 4.0 * (h.radius[r] + h.radius[s]);
    std::optional<detail::FaceChoice> choice;
    if (h.is_cluster(s)) choice.emplace(h, r, s);
    double sum = 0.0, seen = 0.0;
    std::array<double, facing_classes> facing{}, sending{};
    const bool split_r = h.mixed(r), split_s = h.mixed(s);
    for (int i = 0; i < samples; ++i) {
        std::uint32_t a = 0, b = 0;
        const Vec3 x = detail::uniform_point(h, r, rng, a);
        const Vec3 nx = h.is_cluster(r) ? h.roots.normal(a) : h.normal[r];
        double p = 1.0;
        if (choice)
            b = choice->pick(rng, p);
        else
            b = h.root_of(s);
        const auto face = h.is_cluster(s) ? h.roots.polygon(b) : h.polygon(s);
        const double u = rng.uniform();
        const Vec3 y = detail::polygon_point(face, u, rng.uniform());
        // Far apart, the point-to-point kernel at y, times the face's area, is as good and
        // needs no arc tangents; near, only Lambert's integral over the face stays bounded.
        const Vec3 ny = h.is_cluster(s) ? h.roots.normal(b) : h.normal[s];
        const double area_b = h.is_cluster(s) ? h.roots.area(b) : h.area[s];
        const double w =
            (far || detail::small_from(x, face) ? form_factor_kernel(x, nx, y, ny) * area_b
                                                : point_to_polygon(x, nx, face)) /
            p;
        if (w == 0.0) continue;
        sum += w;
        if (scene.occluded(x, y, a, b)) continue;
        seen += w;
        // Which of a mixed cluster's faces took it, by orientation, and which sent it (a
        // cluster whose faces face alike needs neither: its one class is all of it).
        if (split_r) facing[facing_class(nx)] += w;
        if (split_s) sending[facing_class(ny)] += w;
    }
    if (sum == 0.0) return {0.0, 1.0, {}, {}};
    // The visible transfer T V = seen / samples is the mean irradiance over r per unit
    // radiosity of s, at most 1 (a form factor); a few samples near a large s can give more (a
    // face beside x picked with its small share of the area), and links that gather more than
    // 1 / rho make the iteration diverge. So T is cut to 1 / V there. (T alone may pass 1:
    // faces behind faces.)
    const double T = seen > double(samples) ? sum / seen : sum / samples;
    return {T, seen / sum, facing, sending};
}

/// How the light of a link with a mixed cluster (Hierarchy::mixed) at either end divides among
/// the orientation classes of the cluster's faces: at the receiver, the faces that take it
/// (`facing`: push-pull hands it to those that face the source), at the source, those that
/// send it (`sending`: the gather takes the radiosity of the faces that face the receiver, not
/// the whole cluster's mean). Each in 255ths, summing to 255; all 0 where unmeasured (that end
/// is not a mixed cluster), where push-pull hands the light to every exposed face alike and the
/// gather takes the cluster's mean radiosity. See gather.hpp.
struct ClassShares {
    NodeId receiver, source;  ///< the link's
    std::array<std::uint8_t, facing_classes> facing{};
    std::array<std::uint8_t, facing_classes> sending{};
};

/// Whether link l has class shares: it carries light (T V > 0) and a mixed cluster is at an end.
inline bool has_class_shares(const Hierarchy& h, const Link& l) {
    return l.coefficient > 0.0f && l.visibility > 0.0f &&
           (h.mixed(l.receiver) || h.mixed(l.source));
}

/// The class shares of the links that have any (has_class_shares), in the links' order. Each
/// taken from `known` (sorted by link_order: what the refinement sampled, the last pass's)
/// where it is there, found by walking the two lists side by side (the links
/// sorted by link_order too; unsorted, more are sampled again); else from sampled_transfer with
/// the settings that sampled the link (`samples`, `seed`), which gives the very samples that
/// gave its coefficient and visibility, since a link's stream is a function of its pair alone.
/// So the shares need not travel with the links between ranks or through a checkpoint, and a
/// link is 16 bytes, not 28. Cost: O(links + known); `samples` rays and transfers per link
/// not known, in parallel.
template <Visibility V>
std::vector<ClassShares> class_shares(const Hierarchy& h, const V& scene, const LinkVector& links,
                                      int samples, std::uint64_t seed,
                                      const std::vector<ClassShares>& known) {
    std::vector<ClassShares> out;
    std::vector<std::size_t> missing;  // positions in out still to sample
    std::size_t k = 0;
    for (const Link& l : links) {
        if (!has_class_shares(h, l)) continue;
        const std::uint64_t want = pair_key(l.receiver, l.source);
        while (k < known.size() && pair_key(known[k].receiver, known[k].source) < want) ++k;
        if (k < known.size() && pair_key(known[k].receiver, known[k].source) == want) {
            out.push_back(known[k]);
        } else {
            missing.push_back(out.size());
            out.push_back({l.receiver, l.source});
        }
    }
    const auto n = static_cast<std::int64_t>(missing.size());
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(dynamic, 64) if (n > 256)
#endif
    for (std::int64_t j = 0; j < n; ++j) {
        ClassShares& x = out[missing[std::size_t(j)]];
        const SampledTransfer st = sampled_transfer(h, scene, x.receiver, x.source, samples, seed);
        x.facing = in_255ths(st.facing);
        x.sending = in_255ths(st.sending);
    }
    return out;
}

/// The visibility V_rs of a link between two elements: the kernel-weighted fraction
/// (VisibilitySums) of k x k stratified, jittered sample pairs, k = round(sqrt(rays)) at most
/// 16, the strata of s shuffled against those of r (as jittered_pairs draws them), whose segments
/// the scene leaves unblocked. The stream is seeded by the two nodes' keys and `seed`, so a
/// link's visibility never depends on threads or on the order of work. Cost: k^2 occlusion
/// queries, no allocation.
template <Visibility V>
double link_visibility(const Hierarchy& h, const V& scene, NodeId r, NodeId s, int rays,
                       std::uint64_t seed) {
    Rng rng(splitmix64(seed ^ splitmix64(h.key[r]) ^ (splitmix64(h.key[s]) >> 1)));
    const int k = strata_side(rays);
    const int n = k * k;
    const auto strata = shuffled_strata(k, rng);
    const auto pr = h.polygon(r), ps = h.polygon(s);
    const std::uint32_t a = h.root_of(r), b = h.root_of(s);
    VisibilitySums sums;
    for (int i = 0; i < n; ++i) {
        const int j = strata[std::size_t(i)];
        const double u0 = (i / k + rng.uniform()) / k, v0 = (i % k + rng.uniform()) / k;
        const double u1 = (j / k + rng.uniform()) / k, v1 = (j % k + rng.uniform()) / k;
        const Vec3 x = detail::polygon_point(pr, u0, v0), y = detail::polygon_point(ps, u1, v1);
        const double kernel = form_factor_kernel(x, h.normal[r], y, h.normal[s]);
        if (kernel == 0.0) continue;
        sums.total += kernel;
        if (!scene.occluded(x, y, a, b)) sums.seen += kernel;
    }
    return sums.fraction();
}

}  // namespace radiosity
