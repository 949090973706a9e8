// Lecture example 2: solving B = E + R F B four ways.
//
// The closed cube of example 1, the floor emitting E = 1, every face reflecting R = 0.5.
// In matrix form (I - M) B = E with M_ij = R_i F_ij:
//   direct        B = (I - M)^-1 E by LU factorisation, O(n^3): the reference
//   Jacobi        B(k+1) = E + M B(k)           (all patches from the previous sweep)
//   Gauss-Seidel  the same, using values already updated in this sweep
//   shooting      the patch with the most unshot power dB_j A_j sends it to all others:
//                 dB_i += R_i F_ji dB_j A_j / A_i    (Southwell iteration)
// We print the residual after each step, then every solution. Exit status 1 if an iterative
// solver does not reach the direct solution.
#include <radiosity/form_factor/analytic.hpp>
#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/solver/direct.hpp>
#include <radiosity/solver/gauss_seidel.hpp>
#include <radiosity/solver/jacobi.hpp>
#include <radiosity/solver/progressive.hpp>

#include <cmath>
#include <cstdio>

int main() {
    using namespace radiosity;
    const std::vector<std::vector<Vec3>> faces{
        {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}},
        {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}}, {{1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}},
        {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}}, {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}}};
    PatchTable patches;
    for (const auto& f : faces) patches.add(f);
    Analytic method;
    method.prepare(patches);
    const DenseMatrix F = assemble_dense(method, patches.size());

    const std::vector<float> E{1, 0, 0, 0, 0, 0}, R(6, 0.5f);
    const System<float> system{E, R, patches.areas()};
    int step = 0;
    const ProgressCallback trace = [&](const Progress& p) {
        std::printf("   step %2d  residual %.3e\n", ++step, p.residual);
        return true;
    };

    const auto direct = Direct().solve(system, F);
    std::printf("direct: residual %.1e\n", direct.report.residual);
    bool ok = true;
    auto show = [&](const Solution<float>& s) {
        std::printf("%s: %zu iterations, final residual %.2e\n   B =", s.report.solver.c_str(),
                    s.report.iterations, s.report.residual);
        for (std::size_t i = 0; i < s.radiosity.size(); ++i) {
            std::printf(" %.6f", s.radiosity[i]);
            ok = ok && std::abs(s.radiosity[i] - direct.radiosity[i]) < 1e-5;
        }
        std::printf("\n");
        step = 0;
    };
    std::printf("jacobi:\n");
    show(Jacobi({1e-7, 1000}).solve(system, F, trace));
    std::printf("gauss-seidel:\n");
    show(GaussSeidel({1e-7, 1000}).solve(system, F, trace));
    std::printf("progressive shooting (rows computed on demand, from the method itself):\n");
    show(Progressive({1e-7, 0, 0, false}).solve(system, method));
    std::printf("direct:\n   B =");
    for (float b : direct.radiosity) std::printf(" %.6f", b);
    std::printf("\n");
    return ok ? 0 : 1;
}
