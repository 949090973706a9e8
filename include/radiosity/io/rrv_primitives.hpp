#pragma once
/// @file rrv_primitives.hpp  The primitives of RRV scenes (Dudka 2007) as triangles, before any
/// transform, all centred on the origin (../shared/rrv/README.md): the unit cuboid, the barrel
/// (a closed cylinder of 20 segments), the globe (20 segments, 10 bands) and the teapot read from
/// RRV's teapot.obj. Faces point outwards, counter-clockwise seen from outside.

#include <radiosity/error.hpp>
#include <radiosity/geometry/vec.hpp>

#include <array>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace radiosity::detail {

/// The unit primitives of RRV, centred on the origin, outward-facing, counter-clockwise.
inline void rrv_cuboid(std::vector<std::array<Vec3, 3>>& out) {
    for (int axis = 0; axis < 3; ++axis)
        for (double side : {-0.5, 0.5}) {
            const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
            auto at = [&](double s, double t) {
                Vec3 p;
                p[axis] = side;
                p[a1] = s;
                p[a2] = t;
                return p;
            };
            std::array<Vec3, 4> q{at(-0.5, -0.5), at(0.5, -0.5), at(0.5, 0.5), at(-0.5, 0.5)};
            if (side < 0) std::swap(q[1], q[3]);  // (a1, a2, axis) is right-handed: flip for -
            out.push_back({q[0], q[1], q[2]});
            out.push_back({q[0], q[2], q[3]});
        }
}

inline void rrv_barrel(std::vector<std::array<Vec3, 3>>& out) {
    constexpr int n = 20;
    const double r = 0.5, pi = std::numbers::pi;
    for (int k = 0; k < n; ++k) {
        const double a0 = 2 * pi * k / n, a1 = 2 * pi * (k + 1) / n;
        const Vec3 b0(r * std::cos(a0), -0.5, r * std::sin(a0)),
            b1(r * std::cos(a1), -0.5, r * std::sin(a1));
        const Vec3 t0(b0.x, 0.5, b0.z), t1(b1.x, 0.5, b1.z);
        out.push_back({b0, t1, b1});  // side, facing out
        out.push_back({b0, t0, t1});
        out.push_back({Vec3(0, 0.5, 0), t1, t0});   // top cap, facing +y
        out.push_back({Vec3(0, -0.5, 0), b0, b1});  // bottom cap, facing -y
    }
}

inline void rrv_globe(std::vector<std::array<Vec3, 3>>& out) {
    constexpr int segments = 20, bands = 10;
    const double pi = std::numbers::pi;
    auto at = [&](int s, int b) {
        const double theta = pi * b / bands, phi = 2 * pi * s / segments;
        return 0.5 * Vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                          std::sin(theta) * std::sin(phi));
    };
    for (int b = 0; b < bands; ++b)
        for (int s = 0; s < segments; ++s) {
            const Vec3 p00 = at(s, b), p10 = at(s + 1, b), p01 = at(s, b + 1),
                       p11 = at(s + 1, b + 1);
            if (b > 0) out.push_back({p00, p10, p01});
            if (b + 1 < bands) out.push_back({p10, p11, p01});
        }
}

/// RRV's teapot: the stored triangles with y and z swapped and the winding reversed.
inline void rrv_teapot(const std::string& path, std::vector<std::array<Vec3, 3>>& out) {
    std::ifstream in(path);
    if (!in) throw Error(path + ": cannot open RRV's teapot mesh (RrvOptions::teapot_obj)");
    std::vector<Vec3> v;
    std::string line;
    for (std::size_t n = 1; std::getline(in, line); ++n) {
        std::istringstream words(line);
        std::string kind;
        words >> kind;
        if (kind == "v") {
            double x, y, z;
            if (!(words >> x >> y >> z))
                throw Error(path + ":" + std::to_string(n) + ": bad vertex");
            v.emplace_back(x, z, y);
        } else if (kind == "f") {
            std::array<long, 3> f{};
            for (long& i : f)
                if (!(words >> i) || i < 1 || std::size_t(i) > v.size())
                    throw Error(path + ":" + std::to_string(n) + ": bad face");
            out.push_back(
                {v[std::size_t(f[2] - 1)], v[std::size_t(f[1] - 1)], v[std::size_t(f[0] - 1)]});
        }
    }
}

}  // namespace radiosity::detail
