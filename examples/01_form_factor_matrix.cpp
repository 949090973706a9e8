// Lecture example 1: the form-factor matrix of a tiny closed scene.
//
// Six patches, the inside of the unit cube. F_ij is the fraction of the energy leaving patch i
// that arrives at patch j. Two identities hold for every exact F:
//   reciprocity   A_i F_ij = A_j F_ji
//   closure       sum_j F_ij = 1 in a closed scene (all energy lands somewhere)
// and F_ii = 0 for flat patches. We compute F with the analytic method (Lambert's contour
// integral, integrated over the patch) and print it with its row sums and reciprocity error.
// Exit status 1 if an identity fails, so this example runs as a test.
#include <radiosity/form_factor/analytic.hpp>
#include <radiosity/form_factor/matrix.hpp>

#include <cstdio>

int main() {
    using namespace radiosity;
    // The faces of the unit cube, counter-clockwise seen from inside (normals point inwards).
    const std::vector<std::vector<Vec3>> faces{
        {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}},  // floor z = 0
        {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}},  // ceiling z = 1
        {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}},  // wall x = 0
        {{1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}},  // wall x = 1
        {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}},  // wall y = 0
        {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}},  // wall y = 1
    };
    PatchTable patches;
    for (const auto& f : faces) patches.add(f);

    Analytic method;
    method.prepare(patches);
    const DenseMatrix F = assemble_dense(method, patches.size());
    const MatrixCheck check = check_matrix(F, patches.areas());

    std::printf("F_ij (row i: where the light leaving patch i goes)\n");
    for (std::size_t i = 0; i < F.size(); ++i) {
        for (std::size_t j = 0; j < F.size(); ++j) std::printf(" %.6f", F(i, j));
        std::printf("   row sum %.7f\n", check.row_sums[i]);
    }
    std::printf("reciprocity error max|A_i F_ij - A_j F_ji| / max A_i F_ij = %.2e\n",
                check.reciprocity_error);
    // Opposite faces: 0.199825, adjacent faces: 0.200044 (Howell's catalogue C-11, C-14).
    const bool ok = check.min_row_sum > 1 - 1e-6 && check.max_row_sum < 1 + 1e-6 &&
                    check.reciprocity_error < 1e-6;
    return ok ? 0 : 1;
}
