#pragma once
/// @file draw_nearest.hpp  The hemicube's fast z-buffer drawing (form_factor/hemicube.hpp):
/// draw_nearest keeps exactly the items and depths that the plain path keeps (draw_depth's runs
/// into NearestItems, geometry/raster.hpp), but tests the pixels of a narrow box without a
/// branch; tests/test_raster.cpp checks that they agree.

#include <radiosity/geometry/raster.hpp>

#include <bit>
#include <cstddef>
#include <cstdint>
#include <optional>

namespace radiosity::detail {

/// Draws one screen-space triangle into a z-buffer with items (NearestItems): the pixels that
/// draw_depth visits, with the same z/w, and the same decisions. A wide box goes by runs; in a
/// narrow one (a few columns, most triangles of a hemicube) every pixel of the box is tested,
/// coverage and depth together, without a branch: the runs there are a pixel or two, and the
/// branches that find and draw them mispredict more often than not.
inline void draw_nearest(const ScreenVertex& v0, const ScreenVertex& v1, const ScreenVertex& v2,
                         int width, int height, NearestItems items) {
    const std::optional<DepthPlane> plane = depth_plane(v0, v1, v2);
    if (!plane) return;
    const double z0 = plane->z0, dzdx = plane->dzdx, dzdy = plane->dzdy;
    auto span = [items, z0, dzdx, dzdy](int y, int begin, int end) {
        items(DepthSpan{y, begin, end, z0 + dzdy * y, dzdx});
    };
    auto narrow = [items, z0, dzdx, dzdy](const ScreenVertex& u0, const ScreenVertex& u1,
                                          const ScreenVertex& u2, int bx0, int bx1, int by0,
                                          int by1, std::int64_t px, std::int64_t py) {
        EdgeStepper e0 = edge_stepper(u1, u2, px, py), e1 = edge_stepper(u2, u0, px, py),
                    e2 = edge_stepper(u0, u1, px, py);
        for (int y = by0; y <= by1; ++y) {
            const auto row = static_cast<std::size_t>(y) * static_cast<std::size_t>(items.width);
            double* const d = items.depth + row;
            std::int32_t* const it = items.item + row;
            const double zy = z0 + dzdy * y;  // as DepthSpan's z0: the same z, bit for bit
            std::int64_t a = e0.value, b = e1.value, c = e2.value;
            double x = bx0;
            for (int col = bx0; col <= bx1; ++col, x += 1.0) {
                const double z = zy + dzdx * x;
                // All ones where covered and nearer: the stores below select by mask (as
                // written, with ?:, the compiler would branch).
                const std::int64_t nearer =
                    -static_cast<std::int64_t>(((a | b | c) >= 0) & (z < d[col]));
                const auto old_z = std::bit_cast<std::int64_t>(d[col]);
                d[col] = std::bit_cast<double>(old_z ^
                                               ((old_z ^ std::bit_cast<std::int64_t>(z)) & nearer));
                it[col] ^= (it[col] ^ items.who) & static_cast<std::int32_t>(nearer);
                a += e0.step_x;
                b += e1.step_x;
                c += e2.step_x;
            }
            e0.value += e0.step_y;
            e1.value += e1.step_y;
            e2.value += e2.step_y;
        }
    };
    scan_triangle(v0, v1, v2, width, height, span, narrow);
}

}  // namespace radiosity::detail
