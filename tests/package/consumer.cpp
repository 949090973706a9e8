// Solves two facing unit squares one unit apart, only the first emitting, and checks the
// radiosity of the second against the closed form: B_1 = R F E / (1 - R^2 F^2), F = 0.1998...
// (Howell C-11). Exit status 0 when the installed library works.
#include <radiosity/radiosity.hpp>

#include <cmath>
#include <cstdio>

int main() {
    using namespace radiosity;
    Scene<float> scene;
    scene.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                       {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    scene.faces = {{0, 1, 2, 3}, {4, 7, 6, 5}};
    scene.face_material = {0, 1};
    scene.materials = {{1.0f, 0.5f, "lamp"}, {0.0f, 0.5f, "wall"}};
    SolveOptions options;
    options.form_factor = FormFactorKind::analytic;
    options.solver = SolverKind::direct;
    const auto result = solve(build_mesh(scene), options);
    const double F = 0.199824895698, R = 0.5;
    const double expected = R * F / (1.0 - R * R * F * F);
    const double got = result.mesh.data(result.mesh.face_handle(1)).radiosity;
    std::printf("B_1 = %.9f, closed form %.9f\n", got, expected);
    return std::abs(got - expected) < 1e-5 * expected ? 0 : 1;
}
