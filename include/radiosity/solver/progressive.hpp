#pragma once
/// @file progressive.hpp  Progressive refinement by shooting (Cohen, Chen, Wallace & Greenberg
/// 1988), i.e. Southwell iteration: instead of gathering light into every patch each sweep, the
/// patch j with the most unshot power dB_j A_j shoots it to all others,
///   dB_i += R_i F_ji dB_j A_j / A_i   and   B_i += the same,   then dB_j = 0,
/// which needs only row j of F (F_ji for all i), computed on demand: no n x n matrix is stored.
/// The picture is useful after a few shots; the ambient term (same paper) stands in for the
/// light not yet shot when showing such intermediate results.

#include <radiosity/concepts.hpp>
#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/progress.hpp>
#include <radiosity/solver/common.hpp>
#include <radiosity/solver/session.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <unordered_map>

namespace radiosity {

/// Settings of progressive shooting.
struct ProgressiveOptions {
    double tolerance = 1e-4;         ///< stop when unshot power / emitted power is this small
    std::size_t max_iterations = 0;  ///< guard on the number of shots; 0: 100 n (at least 1000)
    std::size_t row_cache_bytes = std::size_t(256) << 20;  ///< rows kept for patches that shoot
                                                           ///< again (0: none)
    bool ambient = false;          ///< add the ambient term to the returned B (for early stops)
    std::size_t report_every = 0;  ///< shots between progress reports (and exact re-sums of the
                                   ///< unshot power); 0: n / 100
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

/// Progressive shooting (see the file comment). The residual is the unshot power over the
/// emitted power, sum_i |dB_i| A_i / sum_i |E_i| A_i (summed over bands), which bounds how much
/// light is still missing. Iterations are shots. Works on any RowSource: a form-factor method
/// (rows on demand, cached within row_cache_bytes) or an assembled matrix.
/// Cost per shot: one row of F and O(n).
class Progressive : public detail::SolverBase<Progressive, ProgressiveOptions> {
  public:
    using SolverBase::SolverBase;
    static constexpr const char* name = "progressive";  ///< Report::solver

    /// The iteration of solve() (detail::SolverBase): shoots, computing rows of F from `rows`
    /// as patches shoot, until the stopping rule holds; returns B (with the ambient term if
    /// asked for).
    template <SpectrumType S, RowSource Rows>
    std::vector<S> iterate(detail::SolveSession<S>& session, const Rows& rows) const {
        constexpr std::size_t K = band_count<S>;
        const std::span<const double> area = session.system.area;
        const std::size_t n = area.size();
        Report& report = session.report;
        std::vector<double> B = session.E, unshot = session.E;
        const double emitted = power<K>(unshot, area);
        report.residual = emitted > 0.0 ? 1.0 : 0.0;
        const detail::StoppingRule rule{
            options_.tolerance, options_.max_iterations > 0 ? options_.max_iterations
                                                            : std::max<std::size_t>(1000, 100 * n)};
        RowCache cache(n, options_.row_cache_bytes);
        const std::size_t report_every =
            options_.report_every > 0 ? options_.report_every : std::max<std::size_t>(1, n / 100);
        double left = emitted;  // unshot power, kept up to date shot by shot
        while (!rule.met(report.residual) && !rule.exhausted(report.iterations)) {
            const std::size_t j = brightest<K>(unshot, area);
            left -= power<K>(std::span(unshot).subspan(j * K, K), area.subspan(j, 1));
            left += shoot<K>(j, cache.row(rows, j), session.R, area, B, unshot);
            ++report.iterations;
            const bool due = report.iterations % report_every == 0;
            if (due) left = power<K>(unshot, area);  // exact again: no drift
            report.residual = std::max(left, 0.0) / emitted;
            if (due && !session.proceed(Progress{.phase = "solve",
                                                 .fraction = rule.fraction(1.0, report.residual),
                                                 .residual = report.residual,
                                                 .iteration = report.iterations,
                                                 .radiosity = B,
                                                 .unshot = unshot}))
                break;
        }
        if (emitted > 0.0) report.residual = power<K>(unshot, area) / emitted;
        report.converged = rule.met(report.residual);
        std::vector<S> result = detail::from_doubles<S>(B);
        if (!options_.ambient) return result;
        return with_ambient<S>(session.system, result, detail::from_doubles<S>(unshot));
    }

  private:
    /// Rows of patches that have shot, kept within a memory budget (first come, first kept):
    /// the brightest patches shoot many times, and their rows are the costly ones to redo.
    class RowCache {
      public:
        RowCache(std::size_t n, std::size_t bytes)
            : n_(n), capacity_(n > 0 ? bytes / (n * sizeof(float)) : 0), scratch_(n) {}

        template <RowSource Rows>
        std::span<const float> row(const Rows& rows, std::size_t j) {
            if (auto it = kept_.find(j); it != kept_.end()) return it->second;
            if (kept_.size() < capacity_) {
                std::vector<float>& r = kept_[j];
                r.resize(n_);
                rows.row(j, r);
                return r;
            }
            rows.row(j, scratch_);
            return scratch_;
        }

      private:
        std::size_t n_, capacity_;
        std::unordered_map<std::size_t, std::vector<float>> kept_;
        std::vector<float> scratch_;
    };

    /// Unshot power sum_i sum_k |dB_i[k]| A_i.
    template <std::size_t K>
    static double power(std::span<const double> unshot, std::span<const double> area) {
        double p = 0.0;
        for (std::size_t i = 0; i < area.size(); ++i)
            for (std::size_t k = 0; k < K; ++k) p += std::abs(unshot[i * K + k]) * area[i];
        return p;
    }

    /// The patch with the most unshot power (Southwell's choice); the lowest index on ties.
    template <std::size_t K>
    static std::size_t brightest(const std::vector<double>& unshot, std::span<const double> area) {
        std::size_t best = 0;
        double most = -1.0;
        for (std::size_t i = 0; i < area.size(); ++i) {
            double p = 0.0;
            for (std::size_t k = 0; k < K; ++k) p += unshot[i * K + k];
            p *= area[i];
            if (p > most) {
                most = p;
                best = i;
            }
        }
        return best;
    }

    /// Patch j shoots its unshot radiosity through row j of F: dB_i += R_i F_ji dB_j A_j / A_i.
    /// Returns the power of what the receivers reflect, sum_i sum_k dB_i A_i, now unshot.
    template <std::size_t K>
    static double shoot(std::size_t j, std::span<const float> Fj, const std::vector<double>& R,
                        std::span<const double> area, std::vector<double>& B,
                        std::vector<double>& unshot) {
        std::array<double, K> shot{};
        for (std::size_t k = 0; k < K; ++k) {
            shot[k] = unshot[j * K + k];
            unshot[j * K + k] = 0.0;
        }
        // A shot is about a nanosecond per patch, and shots come by the tens of thousands: below
        // 64k patches, starting threads for each costs more than it saves (4k patches: 5x
        // slower on two busy cores).
        const auto count = static_cast<std::int64_t>(area.size());
        double reflected = 0.0;
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(static) if (count > 65536) reduction(+ : reflected)
#endif
        for (std::int64_t s = 0; s < count; ++s) {
            const auto i = static_cast<std::size_t>(s);
            if (Fj[i] == 0.0f) continue;
            const double w = Fj[i] * area[j] / area[i];
            double d_sum = 0.0;
            for (std::size_t k = 0; k < K; ++k) {
                const double d = R[i * K + k] * w * shot[k];
                B[i * K + k] += d;
                unshot[i * K + k] += d;
                d_sum += d;
            }
            reflected += d_sum * area[i];
        }
        return reflected;
    }
};

// The solver contract (concepts.hpp): shooting takes assembled matrices as row sources too.
static_assert(Solver<Progressive, float, DenseMatrix> && Solver<Progressive, Rgb, SparseMatrix>);

}  // namespace radiosity
