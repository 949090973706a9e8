#pragma once
/// @file embree.hpp  Optional Visibility backend on Intel Embree 3 (Wald et al. 2014), for
/// comparison with the library's own BVH. Built only with -DRADIOSITY_WITH_EMBREE=ON (Debian's
/// libembree-dev); include it explicitly, the umbrella header does not.

#if !defined(RADIOSITY_WITH_EMBREE)
#error "radiosity/geometry/embree.hpp needs the library configured with RADIOSITY_WITH_EMBREE=ON"
#endif

#include <radiosity/concepts.hpp>
#include <radiosity/error.hpp>
#include <radiosity/geometry/patch_table.hpp>
#include <radiosity/geometry/vec.hpp>

#include <embree3/rtcore.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace radiosity {

/// Visibility through Embree: the patches' fan triangles in one Embree scene (single
/// precision), occlusion rays with a context filter that ignores the two end patches.
/// Build: Embree's default SAH builder. Thread-safe queries. No pair culling (PairCulling):
/// RayCast<EmbreeVisibility> casts rays for every pair.
class EmbreeVisibility {
  public:
    /// Builds the Embree scene over the patches. Throws Error if Embree cannot start.
    explicit EmbreeVisibility(const PatchTable& patches) : device_(rtcNewDevice(nullptr)) {
        if (!device_) throw Error("embree: cannot create a device");
        scene_ = rtcNewScene(device_);
        rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
        std::vector<float> vertices;
        std::vector<std::uint32_t> indices;
        for (std::size_t i = 0; i < patches.size(); ++i) {
            const auto p = patches.polygon(i);
            const auto base = static_cast<std::uint32_t>(vertices.size() / 3);
            for (const Vec3& v : p)
                vertices.insert(vertices.end(), {float(v.x), float(v.y), float(v.z)});
            for (std::uint32_t k = 1; k + 1 < p.size(); ++k) {
                indices.insert(indices.end(), {base, base + k, base + k + 1});
                patch_.push_back(static_cast<std::uint32_t>(i));
            }
        }
        RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0,
                                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                               vertices.size() / 3));
        std::copy(vertices.begin(), vertices.end(), vb);
        auto* ib = static_cast<std::uint32_t*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(std::uint32_t), indices.size() / 3));
        std::copy(indices.begin(), indices.end(), ib);
        rtcCommitGeometry(g);
        rtcAttachGeometry(scene_, g);
        rtcReleaseGeometry(g);
        rtcCommitScene(scene_);
    }
    EmbreeVisibility(const EmbreeVisibility&) = delete;
    EmbreeVisibility& operator=(const EmbreeVisibility&) = delete;
    ~EmbreeVisibility() {
        rtcReleaseScene(scene_);
        rtcReleaseDevice(device_);
    }

    /// Visibility: true if the open segment p -> q hits a patch other than a and b.
    bool occluded(const Vec3& p, const Vec3& q, std::uint32_t a, std::uint32_t b) const {
        Context ctx;
        rtcInitIntersectContext(&ctx.base);
        ctx.base.filter = &Context::skip_end_patches;
        ctx.patch = patch_.data();
        ctx.a = a;
        ctx.b = b;
        RTCRay ray{};
        ray.org_x = float(p.x);
        ray.org_y = float(p.y);
        ray.org_z = float(p.z);
        ray.dir_x = float(q.x - p.x);
        ray.dir_y = float(q.y - p.y);
        ray.dir_z = float(q.z - p.z);
        ray.tnear = 1e-6f;
        ray.tfar = 1.0f - 1e-6f;
        ray.mask = ~0u;  // Debian's Embree needs every mask bit set
        rtcOccluded1(scene_, &ctx.base, &ray);
        return ray.tfar == -std::numeric_limits<float>::infinity();
    }

  private:
    /// The intersection context, extended with what the filter needs (Embree passes it on).
    struct Context {
        RTCIntersectContext base;
        const std::uint32_t* patch;
        std::uint32_t a, b;
        static void skip_end_patches(const RTCFilterFunctionNArguments* args) {
            const auto* self = reinterpret_cast<const Context*>(args->context);
            for (unsigned i = 0; i < args->N; ++i) {
                if (args->valid[i] == 0) continue;
                const std::uint32_t patch = self->patch[RTCHitN_primID(args->hit, args->N, i)];
                if (patch == self->a || patch == self->b) args->valid[i] = 0;
            }
        }
    };

    RTCDevice device_;
    RTCScene scene_ = nullptr;
    std::vector<std::uint32_t> patch_;  // patch of each triangle
};

static_assert(Visibility<EmbreeVisibility>);

}  // namespace radiosity
