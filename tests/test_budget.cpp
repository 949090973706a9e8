// The dense matrix's budget (form_factor/budget.hpp): a run whose matrix exceeds the limit is
// refused before anything of that size is allocated, with the patch count and bytes in the
// message; within the limit nothing changes.
#include <radiosity/form_factor/budget.hpp>
#include <radiosity/solve.hpp>

#include "support/approx.hpp"

#include <doctest/doctest.h>

#include <chrono>
#include <string>
#include <sys/resource.h>

using namespace radiosity;

namespace {

/// A floor of nx x ny unit quads (one patch each with max_edge 0), the first one a lamp.
Mesh<Rgb> floor_grid(std::uint32_t nx, std::uint32_t ny) {
    Scene<Rgb> s;
    s.materials = {{Rgb(1.0f), Rgb(0.0f), "lamp"}, {Rgb(0.0f), Rgb(0.5f), "grey"}};
    for (std::uint32_t j = 0; j <= ny; ++j)
        for (std::uint32_t i = 0; i <= nx; ++i) s.positions.emplace_back(i, 0.0, j);
    for (std::uint32_t j = 0; j < ny; ++j)
        for (std::uint32_t i = 0; i < nx; ++i) {
            const std::uint32_t a = j * (nx + 1) + i;
            s.faces.push_back({a, a + nx + 1, a + nx + 2, a + 1});  // facing +y
            s.face_material.push_back(s.faces.size() == 1 ? 0 : 1);
        }
    return build_mesh(s);
}

long max_rss_kib() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_maxrss;
}

}  // namespace

TEST_CASE("a 60,000-patch dense run is refused before it allocates its 14.4 GB") {
    const Mesh<Rgb> scene = floor_grid(300, 200);
    REQUIRE(scene.n_faces() == 60000);
    SolveOptions o;
    o.max_matrix_bytes = std::size_t(8) << 30;  // 8 GiB, a machine of 16 GiB
    const auto t0 = std::chrono::steady_clock::now();
    std::string message;
    try {
        (void)solve(scene, o);
    } catch (const MemoryLimitError& e) {
        message = e.what();
        CHECK(e.patches == 60000);
        CHECK(e.bytes_needed == test::approx(4.0 * 60000.0 * 60000.0));
        CHECK(e.limit_bytes == o.max_matrix_bytes);
        CHECK(e.estimated_seconds > 0.0);
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    MESSAGE("refused in " << seconds << " s: " << message);
    CHECK(message.find("60000 patches") != std::string::npos);
    CHECK(message.find("14.4 GB") != std::string::npos);
    CHECK(message.find("max_edge") != std::string::npos);
    CHECK(message.find("progressive") != std::string::npos);
    CHECK(max_rss_kib() < 2L * 1024 * 1024);  // nothing near the matrix's size was touched
}

TEST_CASE("within the limit the solve runs, and the default limit is half the physical memory") {
    SolveOptions o;
    o.subdivision.max_edge = 0.0;
    o.max_matrix_bytes = 4 * 100 * 100;  // exactly the 100-patch matrix
    const SolveResult<Rgb> r = solve(floor_grid(10, 10), o);
    CHECK(r.patches.size() == 100);
    o.max_matrix_bytes -= 1;
    CHECK_THROWS_AS((void)solve(floor_grid(10, 10), o), MemoryLimitError);
    if (physical_memory_bytes() > 0) CHECK(default_matrix_limit() == physical_memory_bytes() / 2);
    // Progressive shooting takes rows on demand: no matrix, no limit.
    o.solver = SolverKind::progressive;
    CHECK(solve(floor_grid(10, 10), o).patches.size() == 100);
}
