// The hierarchical solve spread over MPI ranks: a program that prints one table row per run, to
// be started under mpirun once per rank count (benchmarks/scaling.sh runs 1, 2 and 4):
//
//   mpirun -np N bench_distributed million [--edge MM]   the Cornell box as a million triangles
//   mpirun -np N bench_distributed room3                 RRV's room3 at its default meshing
//
// Columns, from rank 0 (times are wall seconds on rank 0 unless said): ranks; the whole solve;
// refinement, and of it the link work (judging and evaluating this rank's links: the part that
// divides among ranks) and the wait (inside the rounds' collectives); gather (this rank's links),
// exchange (the per-sweep all-gather) and push-pull (every rank alike); sweeps; bytes rank 0
// received per sweep and in all; the load imbalance (the busiest rank's link work over the mean);
// peak memory of the largest rank.
#include <radiosity/distributed/mpi.hpp>
#include <radiosity/radiosity.hpp>

#include "support/tessellated_box.hpp"

#include <sys/resource.h>
#if defined(RADIOSITY_WITH_OPENMP)
#include <omp.h>
#endif

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

int threads() {
#if defined(RADIOSITY_WITH_OPENMP)
    return omp_get_max_threads();
#else
    return 1;
#endif
}

}  // namespace

int main(int argc, char** argv) {
    radiosity::MpiSession session(argc, argv);
    radiosity::MpiCommunicator world;
    const std::string what = argc > 1 ? argv[1] : "million";
    double edge = 2.85;  // mm: about 1.0 million triangles
    for (int i = 2; i + 1 < argc; i += 2)
        if (std::strcmp(argv[i], "--edge") == 0) edge = std::atof(argv[i + 1]);
    radiosity::Mesh<radiosity::Rgb> scene;
    radiosity::SolveOptions o{.solver = radiosity::SolverKind::hierarchical};
    if (what == "million") {
        scene = radiosity::build_mesh(bench::tessellated_box(edge));
        o.subdivision.cut_intersections = false;  // the box's faces only touch
    } else if (what == "room3") {
        const std::string path = std::string(RADIOSITY_SHARED_DIR) + "/rrv/room3.xml";
        scene = radiosity::build_mesh(radiosity::read_rrv<radiosity::Rgb>(path));
        o.subdivision = {.max_area = 1.0, .conforming = false};  // RRV's default meshing
        o.hierarchical.min_area = 0.25;
    } else {
        if (world.rank() == 0)
            std::fprintf(stderr, "usage: mpirun -np N bench_distributed million|room3\n");
        return 2;
    }
    o.hierarchical.communicator = &world;
    world.max_in_place(std::span<double>());  // start together
    const auto t0 = std::chrono::steady_clock::now();
    const auto r = radiosity::solve(scene, o);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    std::array<double, 1> peak{double(u.ru_maxrss) / 1024.0};
    world.max_in_place(peak);
    if (world.rank() != 0) return 0;
    const auto& h = *r.hierarchy;
    if (std::getenv("BENCH_HEADER"))
        std::printf(
            "| scene | ranks | threads/rank | solve s | refine s | link work s | refine wait s | "
            "gather s | "
            "exchange s | push-pull s | sweeps | kB/sweep | MB received | imbalance | peak MB/rank "
            "| links "
            "|\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    std::printf(
        "| %s | %d | %d | %.2f | %.2f | %.2f | %.2f | %.2f | %.3f | %.2f | %zu | %.0f | %.1f | "
        "%.2f "
        "| %.0f | %zu |\n",
        what.c_str(), h.ranks, threads(), seconds, h.refine_seconds, h.link_seconds,
        h.refine_wait_seconds, h.gather_seconds, h.exchange_seconds, h.push_pull_seconds,
        r.report.iterations, double(h.exchange_bytes_per_sweep) / 1e3,
        double(h.bytes_received) / 1e6, h.imbalance, peak[0], h.links);
    return 0;
}
