#pragma once
/// @file session.hpp  The opening and closing that every solver shares, written once: the checks
/// of the system against its matrix, E and R as doubles, the clock, progress and cancellation,
/// and the report (SolveSession); the rule that stops an iterative solve (StoppingRule,
/// sweep_until); and the solver class that puts them around a solver's own iteration
/// (SolverBase). A solver's header then holds only its method.

#include <radiosity/error.hpp>
#include <radiosity/progress.hpp>
#include <radiosity/solver/common.hpp>
#include <radiosity/solver/system.hpp>
#include <radiosity/spectrum.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace radiosity {

/// Settings of a sweeping solver (Jacobi, Gauss-Seidel): when it stops.
struct SweepOptions {
    double tolerance = 1e-4;            ///< stop when the relative residual is this small
    std::size_t max_iterations = 1000;  ///< guard on the number of sweeps
};

namespace detail {

/// Wall-clock seconds since construction.
class Stopwatch {
  public:
    /// Seconds since construction. Cost: a clock read.
    double seconds() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }

  private:
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

/// One solve from its opening to its closing. Opening checks the system (and that the matrix has
/// one row per patch), converts E and R to doubles and starts the clock; the solver's iteration
/// reads E and R, fills report (iterations, residual, converged) and asks proceed() whether to go
/// on; finish() converts its B back and times the report. Cost: O(n K) at each end.
template <SpectrumType S>
class SolveSession {
  public:
    /// Opens a solve by `solver` ("jacobi", ...) over a matrix of `rows` rows, or, with
    /// std::nullopt, over a row source of unknown size (only the system is checked then).
    /// Throws Error for bad input.
    SolveSession(const char* solver, const System<S>& system, std::optional<std::size_t> rows,
                 const ProgressCallback& progress)
        : system(checked(solver, system, rows)),
          E(to_doubles(system.emission)),
          R(to_doubles(system.reflectance)),
          report{solver},
          progress_(progress) {}

    /// Reports progress (phase "solve") with the current relative residual; returns false, and
    /// marks the report cancelled, when the callback asks to stop.
    bool proceed(double fraction, double residual = 0.0) {
        return proceed(Progress{.phase = "solve", .fraction = fraction, .residual = residual});
    }

    /// The same with a full report (the iteration and the current values, for an observer that
    /// draws them).
    bool proceed(const Progress& p) {
        if (detail::report(progress_, p)) return true;
        report.cancelled = true;
        return false;
    }

    /// Whether anyone is told of progress (so that values for Progress are worth gathering).
    bool observed() const { return static_cast<bool>(progress_); }

    /// Closes the solve with B as the iteration computed it (K doubles per patch).
    Solution<S> finish(const std::vector<double>& B) { return finish(from_doubles<S>(B)); }

    /// Closes the solve with B already in S (progressive adds its ambient term there).
    Solution<S> finish(std::vector<S> B) {
        report.seconds = clock_.seconds();
        return {std::move(B), std::move(report)};
    }

    const System<S>& system;      ///< the system solved, checked
    const std::vector<double> E;  ///< E_i, band_count<S> doubles per patch (to_doubles)
    const std::vector<double> R;  ///< R_i, likewise
    Report report;                ///< filled by the iteration; timed by finish()

  private:
    /// The system, once valid and of the matrix's size; else throws Error naming the solver.
    static const System<S>& checked(const char* solver, const System<S>& system,
                                    std::optional<std::size_t> rows) {
        system.validate();
        if (rows && *rows != system.size())
            throw Error(std::string(solver) + ": the form-factor matrix has " +
                        std::to_string(*rows) + " rows for " + std::to_string(system.size()) +
                        " patches");
        return system;
    }

    const ProgressCallback& progress_;
    Stopwatch clock_;
};

/// The number of rows of a row source that knows it (an assembled matrix), else std::nullopt
/// (a form-factor method, which gives rows for whatever table it was prepared on).
template <class Rows>
std::optional<std::size_t> known_rows(const Rows& rows) {
    if constexpr (requires { rows.size(); })
        return rows.size();
    else
        return std::nullopt;
}

/// When an iterative solve stops: once its relative residual is within the tolerance (met), or
/// at its guard on iterations (exhausted). Every iterative solver judges its residual here, so
/// that a change of the rule (an error bound from the residual and the spectral radius, a guard
/// from what convergence needs) is made in one place.
struct StoppingRule {
    double tolerance;            ///< the largest relative residual accepted
    std::size_t max_iterations;  ///< the guard: sweeps, or shots

    /// Whether the relative residual meets the tolerance.
    bool met(double residual) const { return residual <= tolerance; }
    /// Whether a solve that has made `iterations` sweeps or shots must stop.
    bool exhausted(std::size_t iterations) const { return iterations >= max_iterations; }
    /// Progress as a fraction: how far the residual has come down from `first` towards the
    /// tolerance, on a log scale (so that each digit gained counts alike).
    double fraction(double first, double now) const {
        if (!(now > tolerance) || !(first > tolerance)) return 1.0;
        const double f = std::log(first / now) / std::log(first / tolerance);
        return std::clamp(f, 0.0, 1.0);
    }
};

/// The loop shared by the sweeping solvers: calls sweep() (which returns the largest change of
/// B, absolute) until the change relative to `scale` (max E) meets the rule, the rule's guard is
/// reached or the progress callback cancels; fills iterations, residual (the last relative
/// change), converged and cancelled. values() gives the current B (interleaved, as to_doubles)
/// for Progress::radiosity; it is called only when the session is observed.
template <SpectrumType S, class Sweep, class Values>
void sweep_until(SolveSession<S>& session, const StoppingRule& rule, double scale, Sweep&& sweep,
                 Values&& values) {
    Report& report = session.report;
    double first = -1.0;
    while (!rule.exhausted(report.iterations)) {
        const double change = sweep() / scale;
        ++report.iterations;
        report.residual = change;
        if (first < 0.0) first = change;
        if (rule.met(change)) {
            report.converged = true;
            return;
        }
        if (!session.proceed(
                Progress{.phase = "solve",
                         .fraction = rule.fraction(first, change),
                         .residual = change,
                         .iteration = report.iterations,
                         .radiosity = session.observed() ? values() : std::span<const double>{}}))
            return;
    }
}

/// Whether solver D iterates a system of spectrum S over F: `d.iterate(session, F)` returns B,
/// as doubles or as S.
template <class D, class S, class Mx>
concept IteratesOver = requires(const D& d, SolveSession<S>& session, const Mx& F) {
    d.iterate(session, F);
};

/// What every solver class shares (derived as `class Jacobi : public SolverBase<Jacobi,
/// JacobiOptions>`): its settings, and solve(), which opens a SolveSession, runs the solver's
/// own iteration `Derived::iterate(session, F)` in it and closes it. Derived names itself in
/// `Derived::name`, the report's solver name.
template <class Derived, class Options>
class SolverBase {
  public:
    /// A solver with the given settings.
    explicit SolverBase(Options options = {}) : options_(options) {}

    /// Solves the system over F: an assembled matrix or, for a solver that takes one, a row
    /// source. Throws Error for bad input. What the report's residual means: see the solver.
    template <SpectrumType S, class Mx>
    requires IteratesOver<Derived, S, Mx> Solution<S> solve(const System<S>& system, const Mx& F,
                                                            const ProgressCallback& progress = {})
    const {
        SolveSession<S> session(Derived::name, system, known_rows(F), progress);
        return session.finish(static_cast<const Derived&>(*this).iterate(session, F));
    }

  protected:
    Options options_;  ///< the settings
};

}  // namespace detail
}  // namespace radiosity
