// Lecture example 5: writing your own form-factor policy.
//
// A form-factor method is any type with prepare(PatchTable) and row(i, span<float>) (the
// FormFactorMethod concept in concepts.hpp). Here: the simplest useful one, the "centre-point"
// method, F_ij ~ F(dA_i -> A_j) at the centre of patch i, by Lambert's contour integral; no
// visibility. It is what the hemicube estimates, without the pixels. We plug it into the same
// assembly and solver as the built-in methods and compare it with the analytic area-to-area
// value on two parallel unit squares one apart (exact F = 0.199825, Howell's C-11).
// Exit status 1 if the policy misbehaves.
#include <radiosity/form_factor/analytic.hpp>
#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/solver/gauss_seidel.hpp>

#include <cmath>
#include <cstdio>

/// F_ij from the centre of patch i (see the file comment).
class CentrePoint {
  public:
    void prepare(const radiosity::PatchTable& patches) { patches_ = &patches; }
    void row(std::size_t i, std::span<float> out) const {
        for (std::size_t j = 0; j < out.size(); ++j)
            out[j] = i == j
                         ? 0.0f
                         : static_cast<float>(radiosity::point_to_polygon(
                               patches_->centroid(i), patches_->normal(i), patches_->polygon(j)));
    }

  private:
    const radiosity::PatchTable* patches_ = nullptr;
};
static_assert(radiosity::FormFactorMethod<CentrePoint>);

int main() {
    using namespace radiosity;
    PatchTable patches;
    patches.add(std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});  // faces up
    patches.add(std::vector<Vec3>{{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}});  // faces down
    CentrePoint mine;
    Analytic exact;
    mine.prepare(patches);
    exact.prepare(patches);
    const DenseMatrix F = assemble_dense(mine, patches.size());
    std::printf("centre-point F_01 = %.6f, analytic F_01 = %.6f, closed form 0.199825\n", F(0, 1),
                exact.pair(0, 1));
    // The centre sees more of the opposite square than its average point does.
    const std::vector<float> E{1, 0}, R{0.5f, 0.5f};
    const auto B = GaussSeidel({1e-8, 100}).solve(System<float>{E, R, patches.areas()}, F);
    std::printf("B = %.6f, %.6f (converged: %s)\n", B.radiosity[0], B.radiosity[1],
                B.report.converged ? "yes" : "no");
    const bool ok =
        F(0, 1) > exact.pair(0, 1) && std::abs(F(0, 1) - 0.2395) < 1e-3 && B.report.converged;
    return ok ? 0 : 1;
}
