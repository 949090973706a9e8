#pragma once
/// @file progressive.hpp  Progressive refinement by shooting (Cohen, Chen, Wallace & Greenberg
/// 1988), i.e. Southwell iteration: instead of gathering light into every patch each sweep, the
/// patch j with the most unshot power dB_j A_j shoots it to all others,
///   dB_i += R_i F_ij dB_j   and   B_i += the same,   then dB_j = 0,
/// which needs only column j of F. Over an assembled matrix that is what is used; with rows on
/// demand (no n x n matrix stored) F_ij is taken from row j by reciprocity, F_ji A_j / A_i,
/// which is exact only for a reciprocal method (see Progressive).
/// The picture is useful after a few shots; the ambient term (same paper) stands in for the
/// light not yet shot when showing such intermediate results.

#include <radiosity/concepts.hpp>
#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/progress.hpp>
#include <radiosity/solver/common.hpp>
#include <radiosity/solver/session.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <span>
#include <unordered_map>

namespace radiosity {

/// Settings of progressive shooting.
struct ProgressiveOptions {
    /// Stop once the relative error of B against the exact solution B* is bounded by this: in
    /// the max norm over an assembled matrix, in the power norm with rows on demand (see
    /// Progressive).
    double tolerance = 1e-4;
    /// Guard on the number of shots; 0: n shots for each sweep that the tolerance needs, twice
    /// over (detail::StoppingRule::shots).
    std::size_t max_iterations = 0;
    std::size_t row_cache_bytes = std::size_t(256) << 20;  ///< rows (columns of an assembled
                                                           ///< matrix) kept for patches that
                                                           ///< shoot again (0: none)
    bool ambient = false;  ///< add the ambient term to the returned B (for early stops)
    /// Over-relaxation omega in (0, 2): each shot sends omega times the unshot radiosity
    /// (overshooting); 1: plain shooting; 0: chosen from the mean reflectance (see Progressive).
    double relaxation = 0.0;
    std::size_t report_every = 0;  ///< shots between progress reports; 0: n / 100
};

/// The ambient term (Cohen et al. 1988): the unshot radiosity spread evenly over the scene and
/// inter-reflected as in an enclosure of the mean reflectance R_avg = sum R_i A_i / sum A_i,
///   ambient = 1 / (1 - R_avg) * sum_i dB_i A_i / sum_i A_i   (per band),
/// of which patch i reflects R_i * ambient. Returns B_i + R_i * ambient, for display only; it is
/// exact when the unshot radiosity is uniform in a closed scene of uniform reflectance.
template <SpectrumType S>
std::vector<S> with_ambient(const System<S>& system, std::span<const S> B,
                            std::span<const S> unshot) {
    constexpr std::size_t K = band_count<S>;
    double area = 0.0;
    std::array<double, detail::max_bands> mean_r{}, mean_unshot{};
    for (std::size_t i = 0; i < system.size(); ++i) {
        area += system.area[i];
        for (std::size_t k = 0; k < K; ++k) {
            mean_r[k] += band(system.reflectance[i], k) * system.area[i];
            mean_unshot[k] += band(unshot[i], k) * system.area[i];
        }
    }
    std::vector<S> out(B.begin(), B.end());
    for (std::size_t k = 0; k < K; ++k) {
        const double r = mean_r[k] / area;
        const double ambient = mean_unshot[k] / area / (1.0 - r);
        for (std::size_t i = 0; i < out.size(); ++i)
            set_band(
                out[i], k,
                band(out[i], k) + static_cast<float>(band(system.reflectance[i], k) * ambient));
    }
    return out;
}

/// Progressive shooting (see the file comment), over-relaxed: each shot sends omega times the
/// unshot radiosity and leaves (1 - omega) of it, negative for omega > 1, to be shot back later.
/// Feda & Purgathofer (1992) shoot beyond the unshot light so as to anticipate the light still
/// to come back, which pays most in bright scenes; Gortler, Cohen & Slusallek (1994) show that
/// shooting is Southwell relaxation, for which such overshooting is over-relaxation. omega is
/// Young's optimum for successive over-relaxation, 2 / (1 + sqrt(1 - rho^2)), taken with the
/// area-weighted mean reflectance rho (the ambient term's, largest band) for the spectral radius,
/// which it equals in a closed scene of uniform reflectance; a patch's own reflectance, or the
/// bound q, would over-relax a dark scene with one bright patch. In a closed cube of reflectance
/// 0.99 (96 patches, tolerance 1e-6) that takes the shots from 723 per patch to 92, at 0.5 from
/// 11 to 9.
///
/// The tolerance bounds the relative error of B against the exact solution B* of the system
/// shot, since B* - B = (I - M)^-1 M dB (dB the unshot radiosity) and so
/// ||B - B*|| <= q / (1 - q) ||dB|| (detail::bound_from_change), in the norm where q is known:
/// - over an assembled matrix (an AssembledMatrix), patch j shoots along column j of F,
///   dB_i += R_i F_ij s_j: the system of the gathering solvers, whatever F's reciprocity error,
///   in their max norm with their q = ||R F||_inf (one pass over F). The columns come from a
///   transposed copy where it fits in row_cache_bytes (one pass over F), else by strided reads;
/// - with rows on demand (a form-factor method), patch j shoots along its own row, taking
///   F_ij = F_ji A_j / A_i by reciprocity: for a method that is not reciprocal (the hemicube)
///   that is another system, whose solution differs from the gathering solvers' by about the
///   reciprocity error over (1 - rho): max |dB| / B_max = 5.2e-3 on the Cornell box in 150 mm
///   patches, 6.3e-3 on the default 2,302-patch box, 2.2% / 4.3% / 4.8% in a closed cube of 96
///   patches at rho = 0.5 / 0.9 / 0.99 (128^2 hemicube; against the direct solve, shooting to
///   tolerance 1e-4 on the default box, 1e-6 on the others). Its columns are unknown, so the bound
///   is in the power norm sum_i A_i |x_i| (every band), where ||M|| = max_j max_k sum_i R_i[k]
///   F_ji; q is the largest of these over the rows seen so far, and at least R_max, which bounds
///   them for rows not yet seen (a physical row sums to at most 1, up to the method's error).
/// The report's residual is the unshot power over the emitted power, sum_i |dB_i| A_i /
/// sum_i E_i A_i (summed over bands). Iterations are shots. Cost per shot: one row of F (on
/// demand; cached within row_cache_bytes) and O(n K).
class Progressive : public detail::SolverBase<Progressive, ProgressiveOptions> {
  public:
    using SolverBase::SolverBase;
    static constexpr const char* name = "progressive";  ///< Report::solver

    /// The iteration of solve() (detail::SolverBase): shoots, along the columns of an assembled
    /// matrix or the rows of a form-factor method, until the stopping rule holds; returns B
    /// (with the ambient term if asked for). Throws Error for a relaxation outside (0, 2).
    template <SpectrumType S, RowSource Rows>
    std::vector<S> iterate(detail::SolveSession<S>& session, const Rows& rows) const {
        constexpr std::size_t K = band_count<S>;
        const std::size_t n = session.system.size();
        const double omega = relaxation(session);
        std::vector<double> B = session.E, unshot = session.E;
        if constexpr (AssembledMatrix<Rows>) {
            const ColumnsOf<Rows> columns(rows, options_.row_cache_bytes);
            RowCache cache(columns, n, columns.copied() ? 0 : options_.row_cache_bytes);
            const double q = detail::contraction_bound<K>(rows, session.R);
            shoot_until<K>(
                session, omega, B, unshot, Norm::max, [&] { return q; },
                [&](std::size_t j) {
                    return Shot{columns.copied() ? columns.view(j) : cache.row(j), false};
                });
        } else {
            RowCache cache(rows, n, options_.row_cache_bytes, session.R, K);
            const double r_max = detail::max_abs(session.R);
            shoot_until<K>(
                session, omega, B, unshot, Norm::power,
                [&] { return std::max(r_max, cache.largest_reflected()); },
                [&](std::size_t j) {
                    return Shot{cache.row(j), true};
                });
        }
        std::vector<S> result = detail::from_doubles<S>(B);
        if (!options_.ambient) return result;
        return with_ambient<S>(session.system, result, detail::from_doubles<S>(unshot));
    }

  private:
    /// The norm of the error bound: max over patches, or the power sum_i A_i |x_i|.
    enum class Norm { max, power };

    /// The vector patch j shoots along: column j of F, or row j to be taken by reciprocity.
    struct Shot {
        std::span<const float> f;  ///< F_ij (column) or F_ji (row) for every i
        bool by_reciprocity;       ///< whether f is row j (F_ij = F_ji A_j / A_i)
    };

    /// omega: the option, or Young's 2 / (1 + sqrt(1 - rho^2)) for the area-weighted mean
    /// reflectance rho of the largest band (see the class comment).
    template <SpectrumType S>
    double relaxation(const detail::SolveSession<S>& session) const {
        const double w = options_.relaxation;
        if (w != 0.0) {
            if (!(w > 0.0 && w < 2.0))
                throw Error("progressive: relaxation must lie in (0, 2), or be 0 (chosen), not " +
                            std::to_string(w));
            return w;
        }
        constexpr std::size_t K = band_count<S>;
        const std::span<const double> area = session.system.area;
        double total = 0.0;
        std::array<double, detail::max_bands> reflected{};
        for (std::size_t i = 0; i < area.size(); ++i) {
            total += area[i];
            for (std::size_t k = 0; k < K; ++k) reflected[k] += session.R[i * K + k] * area[i];
        }
        double rho = 0.0;
        for (std::size_t k = 0; k < K; ++k)
            rho = std::max(rho, total > 0.0 ? reflected[k] / total : 0.0);
        return 2.0 / (1.0 + std::sqrt(1.0 - rho * rho));
    }

    /// What the stopping rule and the next shot need, from one pass over the patches.
    struct Scan {
        std::size_t brightest = 0;  ///< the most unshot power |dB_j| A_j (lowest index on ties)
        double unshot_power = 0.0;  ///< sum_i A_i |dB_i|
        double unshot_max = 0.0;    ///< max_i |dB_i|
        double power = 0.0;         ///< sum_i A_i |B_i|
        double max = 0.0;           ///< max_i |B_i|
    };

    /// The scan of dB and B (bands summed in the powers, all bands in the maxima): Southwell's
    /// choice of the patch with the most unshot power, and the norms. Cost: O(n K).
    template <std::size_t K>
    static Scan scan(const std::vector<double>& unshot, const std::vector<double>& B,
                     std::span<const double> area) {
        Scan s;
        double most = -1.0;
        for (std::size_t i = 0; i < area.size(); ++i) {
            double u = 0.0, b = 0.0;
            for (std::size_t k = 0; k < K; ++k) {
                const double du = std::abs(unshot[i * K + k]), bi = std::abs(B[i * K + k]);
                u += du;
                b += bi;
                s.unshot_max = std::max(s.unshot_max, du);
                s.max = std::max(s.max, bi);
            }
            s.unshot_power += u * area[i];
            s.power += b * area[i];
            if (u * area[i] > most) {
                most = u * area[i];
                s.brightest = i;
            }
        }
        return s;
    }

    /// The shooting loop: scans, judges the bound in `norm` with the contraction q() (which may
    /// grow as rows are seen), and shoots the brightest patch along shot_of(j), until the rule
    /// holds, its guard is reached or the progress callback cancels.
    template <std::size_t K, SpectrumType S, class Contraction, class ShotOf>
    void shoot_until(detail::SolveSession<S>& session, double omega, std::vector<double>& B,
                     std::vector<double>& unshot, Norm norm, Contraction&& q,
                     ShotOf&& shot_of) const {
        const std::span<const double> area = session.system.area;
        const std::size_t n = area.size();
        Report& report = session.report;
        const double emitted = scan<K>(session.E, session.E, area).power;
        const double brightest = detail::emission_scale(session.E);
        auto rule =
            detail::StoppingRule::shots(options_.tolerance, q(), options_.max_iterations, n);
        const std::size_t report_every =
            options_.report_every > 0 ? options_.report_every : std::max<std::size_t>(1, n / 100);
        double first = -1.0;
        for (;;) {
            const Scan now = scan<K>(unshot, B, area);
            report.residual = emitted > 0.0 ? now.unshot_power / emitted : 0.0;
            rule.contraction = q();
            detail::check_divergence(report, "shot", now.max, brightest, rule.contraction);
            report.error_bound = norm == Norm::max ? rule.bound(now.unshot_max, now.max)
                                                   : rule.bound(now.unshot_power, now.power);
            if (first < 0.0) first = report.error_bound;
            // The report of the shots so far comes before the verdict, so that an observer sees
            // the state after every report_every-th shot, the last one included.
            if (report.iterations > 0 && report.iterations % report_every == 0 &&
                !session.proceed(Progress{.phase = "solve",
                                          .fraction = rule.fraction(first, report.error_bound),
                                          .residual = report.residual,
                                          .iteration = report.iterations,
                                          .radiosity = B,
                                          .unshot = unshot}))
                return;
            if (rule.met(report.error_bound)) {
                report.converged = true;
                return;
            }
            if (rule.exhausted(report.iterations)) return;
            shoot<K>(now.brightest, shot_of(now.brightest), omega, session.R, area, B, unshot);
            ++report.iterations;
        }
    }

    /// Rows of patches that have shot, kept within a memory budget (first come, first kept):
    /// the brightest patches shoot many times, and their rows are the costly ones to redo. Given
    /// R (K bands a patch), also keeps the largest max_k sum_i R_i[k] |F_ji| of the rows computed:
    /// the norm of row j's shot in the power norm, for the contraction bound.
    template <RowSource Rows>
    class RowCache {
      public:
        RowCache(const Rows& rows, std::size_t n, std::size_t bytes, std::span<const double> R = {},
                 std::size_t K = 0)
            : rows_(rows),
              n_(n),
              capacity_(n > 0 ? bytes / (n * sizeof(float)) : 0),
              scratch_(n),
              R_(R),
              K_(K) {}

        /// Row j, computed or kept.
        std::span<const float> row(std::size_t j) {
            if (auto it = kept_.find(j); it != kept_.end()) return it->second;
            if (kept_.size() < capacity_) {
                std::vector<float>& r = kept_[j];
                r.resize(n_);
                return computed(j, r);
            }
            return computed(j, scratch_);
        }
        /// The largest max_k sum_i R_i[k] |F_ji| of the rows computed so far (0 before any, or
        /// without R).
        double largest_reflected() const { return largest_; }

      private:
        std::span<const float> computed(std::size_t j, std::vector<float>& out) {
            rows_.row(j, out);
            for (std::size_t k = 0; k < K_; ++k) {
                double sum = 0.0;
                for (std::size_t i = 0; i < n_; ++i) sum += R_[i * K_ + k] * std::abs(out[i]);
                largest_ = std::max(largest_, sum);
            }
            return out;
        }

        const Rows& rows_;
        std::size_t n_, capacity_;
        std::unordered_map<std::size_t, std::vector<float>> kept_;
        std::vector<float> scratch_;
        std::span<const double> R_;
        std::size_t K_;
        double largest_ = 0.0;
    };

    /// The columns of an assembled matrix as rows (a RowSource: row j is column j of F, F_ij for
    /// every i), from a transposed copy made once: dense where it fits in `bytes`, always for
    /// sparse rows (the copy is then F's size); else read from F itself, a strided walk.
    template <AssembledMatrix Mx>
    class ColumnsOf {
      public:
        ColumnsOf(const Mx& F, std::size_t bytes) : F_(F) {
            const std::size_t n = F.size();
            if constexpr (!DenseRowMatrix<Mx>)
                sparse_ = transpose_sparse(F);
            else if (n > 0 && n <= bytes / sizeof(float) / n)
                dense_ = transpose_dense(F);
        }

        /// Whether the columns are held densely, for view().
        bool copied() const { return dense_.size() > 0; }
        /// Column j in the dense copy (copied() only).
        std::span<const float> view(std::size_t j) const { return dense_.row(j); }
        /// Column j of F into out.
        void row(std::size_t j, std::span<float> out) const {
            if constexpr (!DenseRowMatrix<Mx>)
                sparse_.row(j, out);
            else if (copied())
                std::copy_n(view(j).begin(), out.size(), out.begin());
            else
                for (std::size_t i = 0; i < F_.size(); ++i) out[i] = F_.row(i)[j];
        }

      private:
        /// F^T, in tiles of 64 x 64 so that reads and writes both stay in cache; tiles of rows of
        /// the copy shared among threads on large matrices (the same values either way).
        static DenseMatrix transpose_dense(const Mx& F) {
            constexpr std::size_t tile = 64;
            const std::size_t n = F.size();
            DenseMatrix T(n);
            const auto tiles = static_cast<std::int64_t>((n + tile - 1) / tile);
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(static) if (detail::worth_threads(n, 1))
#endif
            for (std::int64_t t = 0; t < tiles; ++t) {
                const std::size_t j0 = static_cast<std::size_t>(t) * tile;
                const std::size_t j1 = std::min(n, j0 + tile);
                for (std::size_t i0 = 0; i0 < n; i0 += tile)
                    for (std::size_t i = i0; i < std::min(n, i0 + tile); ++i) {
                        const std::span<const float> row = F.row(i);
                        for (std::size_t j = j0; j < j1; ++j) T.row(j)[i] = row[j];
                    }
            }
            return T;
        }

        /// F^T as sparse rows: the entries F stores, by column.
        static SparseMatrix transpose_sparse(const Mx& F) {
            std::vector<std::vector<std::pair<std::uint32_t, float>>> by_column(F.size());
            for (std::size_t i = 0; i < F.size(); ++i)
                F.for_each_in_row(i, [&](std::size_t j, float f) {
                    by_column[j].emplace_back(static_cast<std::uint32_t>(i), f);
                });
            return SparseMatrix::from_rows(by_column);
        }

        const Mx& F_;
        DenseMatrix dense_;
        SparseMatrix sparse_;
    };

    /// Patch j shoots omega times its unshot radiosity, s = omega dB_j, and keeps dB_j - s: every
    /// patch i receives, in both B_i and dB_i,
    ///   R_i F_ij s              along column j of an assembled F, or
    ///   R_i F_ji (A_j / A_i) s  along row j, F_ij by reciprocity A_i F_ij = A_j F_ji.
    template <std::size_t K>
    static void shoot(std::size_t j, Shot along, double omega, const std::vector<double>& R,
                      std::span<const double> area, std::vector<double>& B,
                      std::vector<double>& unshot) {
        std::array<double, K> s{};
        for (std::size_t k = 0; k < K; ++k) {
            s[k] = omega * unshot[j * K + k];
            unshot[j * K + k] -= s[k];
        }
        // A shot is about a nanosecond per patch, and shots come by the tens of thousands: below
        // 64k patches, starting threads for each costs more than it saves (4k patches: 5x
        // slower on two busy cores). Each patch's update is its own: the same B on any thread.
        const auto count = static_cast<std::int64_t>(area.size());
        const std::span<const float> f = along.f;
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(static) if (count > 65536)
#endif
        for (std::int64_t c = 0; c < count; ++c) {
            const auto i = static_cast<std::size_t>(c);
            if (f[i] == 0.0f) continue;
            const double F_ij = along.by_reciprocity ? f[i] * area[j] / area[i] : f[i];
            for (std::size_t k = 0; k < K; ++k) {
                const double d = R[i * K + k] * F_ij * s[k];
                B[i * K + k] += d;
                unshot[i * K + k] += d;
            }
        }
    }
};

// The solver contract (concepts.hpp): shooting takes assembled matrices as row sources too.
static_assert(Solver<Progressive, float, DenseMatrix> && Solver<Progressive, Rgb, SparseMatrix>);

}  // namespace radiosity
