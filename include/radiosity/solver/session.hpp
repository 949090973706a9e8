#pragma once
/// @file session.hpp  The opening and closing that every solver shares, written once: the checks
/// of the system against its matrix, E and R as doubles, the clock, progress and cancellation,
/// and the report (SolveSession); the rule that stops an iterative solve and the error bounds it
/// rests on (StoppingRule, bound_from_residual, bound_from_change, sweep_until); and the solver
/// class that puts them around a solver's own iteration (SolverBase). A solver's header then holds
/// only its method.

#include <radiosity/error.hpp>
#include <radiosity/progress.hpp>
#include <radiosity/solver/common.hpp>
#include <radiosity/solver/system.hpp>
#include <radiosity/spectrum.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace radiosity {

/// Settings of a sweeping solver (Jacobi, Gauss-Seidel): when it stops.
struct SweepOptions {
    /// Stop once the relative error of B, ||B - B*||_inf / ||B*||_inf against the exact
    /// solution B*, is bounded by this (detail::StoppingRule).
    double tolerance = 1e-4;
    /// Guard on the number of sweeps; 0: twice what the tolerance needs, from the contraction
    /// bound q (detail::StoppingRule::guard_sweeps).
    std::size_t max_iterations = 0;
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

/// A bound on ||B - B*||, the error of an iterate B against the exact solution B* of
/// B = E + M B (M = R F), from the residual r = E + M B - B: B* - B = (I - M)^-1 r, and
/// ||(I - M)^-1|| <= 1 / (1 - q) for any q >= ||M|| below 1 (a Neumann series; Golub & Van Loan
/// 2013, sec. 2.3.4), so ||B - B*|| <= ||r|| / (1 - q). 0 for r = 0; infinity for q >= 1, where
/// the series gives no bound. Cost: O(1).
inline double bound_from_residual(double q, double residual) {
    if (residual == 0.0) return 0.0;
    return q < 1.0 ? residual / (1.0 - q) : std::numeric_limits<double>::infinity();
}

/// A bound on ||B_m - B*|| after a step that changed B by `change` and that contracts the error
/// by q (B_m - B* = G (B_(m-1) - B*) with ||G|| <= q: a Jacobi or Gauss-Seidel sweep), from
/// ||e_(m-1)|| <= ||e_m|| + ||change|| and ||e_m|| <= q ||e_(m-1)||: q / (1 - q) ||change||.
/// The same bound holds for shooting with `change` the unshot radiosity dB, since there
/// B* - B = (I - M)^-1 M dB. 0 for a change of 0 (a fixed point: B = B*); infinity for q >= 1.
/// Cost: O(1).
inline double bound_from_change(double q, double change) {
    if (change == 0.0) return 0.0;
    return q < 1.0 ? q / (1.0 - q) * change : std::numeric_limits<double>::infinity();
}

/// The relative bound ||B - B*|| / ||B*|| from an absolute one, error >= ||B - B*||, at an
/// iterate of norm `size`: error / (size - error), since ||B*|| >= ||B|| - ||B - B*||. 0 for
/// error 0; infinity where error reaches size. Cost: O(1).
inline double relative_bound(double error, double size) {
    if (error == 0.0) return 0.0;
    const double exact_at_least = size - error;
    return exact_at_least > 0.0 ? error / exact_at_least : std::numeric_limits<double>::infinity();
}

/// When an iterative solve stops, and what its tolerance means: a bound on the relative error
/// ||B - B*|| / ||B*|| of its B against the exact solution B* of the system it solves. The bound
/// comes from q, a bound on the norm of M = R F in the solver's norm (the max norm:
/// q = max_i R_i sum_j |F_ij| from the rows of F, detail::contraction_bound), through
/// bound_from_change (a sweep's change, a shot's unshot radiosity) and relative_bound. The guard
/// on iterations comes from the same q: twice the sweeps after which an iteration that contracts
/// by q from B = E is sure to meet the tolerance (sweeps_needed), plus 10, so that it stops only
/// a solve that does not converge as q promises. Where no bound exists (q >= 1: a matrix whose
/// R_i sum_j |F_ij| reach 1; or a tolerance of 0) the bound is infinite and the guard 1000
/// sweeps. Every iterative solver judges its iterate here, so that a change of the rule is made
/// in one place.
struct StoppingRule {
    double tolerance;            ///< the largest relative error bound accepted
    double contraction;          ///< q: a bound on ||M|| in the solver's norm
    std::size_t max_iterations;  ///< the guard: sweeps, or shots

    /// The rule of a sweeping solver: the guard is `cap` if it is not 0, else guard_sweeps().
    static StoppingRule sweeps(double tolerance, double q, std::size_t cap) {
        return {tolerance, q, cap > 0 ? cap : guard_sweeps(tolerance, q)};
    }
    /// The rule of a shooting solver over n patches: the guard is `cap` if it is not 0, else n
    /// shots for each sweep of guard_sweeps() (at least 1000): a sweep's worth of shots reduces
    /// the unshot light about as much as a sweep does.
    static StoppingRule shots(double tolerance, double q, std::size_t cap, std::size_t n) {
        if (cap > 0) return {tolerance, q, cap};
        const std::size_t sweeps = guard_sweeps(tolerance, q), most = std::size_t(1) << 62;
        const std::size_t shots = n > 0 && sweeps > most / n ? most : sweeps * n;
        return {tolerance, q, std::max<std::size_t>(1000, shots)};
    }

    /// The relative error bound at an iterate of norm `size` after a step that changed it by
    /// `change` (see bound_from_change).
    double bound(double change, double size) const {
        return relative_bound(bound_from_change(contraction, change), size);
    }
    /// Whether a relative error bound meets the tolerance.
    bool met(double bound) const { return bound <= tolerance; }
    /// Whether a solve that has made `iterations` sweeps or shots must stop.
    bool exhausted(std::size_t iterations) const { return iterations >= max_iterations; }
    /// Progress as a fraction: how far the bound has come down from `first` towards the
    /// tolerance, on a log scale (so that each digit gained counts alike).
    double fraction(double first, double now) const {
        if (!(now > tolerance) || !(first > tolerance)) return 1.0;
        if (!std::isfinite(first) || !std::isfinite(now)) return 0.0;
        const double f = std::log(first / now) / std::log(first / tolerance);
        return std::clamp(f, 0.0, 1.0);
    }

    /// The sweeps m after which an iteration that contracts the error by q, started from B = E,
    /// is sure to meet the tolerance with the bound from its change. From B = E, e_0 = -M B*, so
    /// ||e_0|| <= q ||B*||, so ||e_m|| <= q^(m+1) ||B*|| and the change of sweep m is
    /// at most (1 + q) q^m ||B*||; the relative bound is then at most x / (1 - 2 x) with
    /// x = q^(m+1) (1 + q) / (1 - q), within the tolerance once x <= tol / (1 + 2 tol).
    /// Infinity where there is no bound (q >= 1 or tol <= 0). Cost: O(1).
    static double sweeps_needed(double tolerance, double q) {
        if (!(q < 1.0) || !(tolerance > 0.0)) return std::numeric_limits<double>::infinity();
        if (q <= 0.0) return 1.0;
        const double x = tolerance / (1.0 + 2.0 * tolerance);
        return std::max(1.0, std::ceil(std::log(x * (1.0 - q) / (1.0 + q)) / std::log(q)) - 1.0);
    }
    /// The default guard in sweeps: 2 sweeps_needed + 10, or 1000 where that is infinite (no
    /// bound). Cost: O(1).
    static std::size_t guard_sweeps(double tolerance, double q) {
        const double m = sweeps_needed(tolerance, q);
        if (!std::isfinite(m)) return 1000;
        return static_cast<std::size_t>(std::min(2.0 * m + 10.0, 1e12));
    }
};

/// Whether an iteration has diverged, the rule every solver stops by: its largest radiosity
/// `size` is past 1e9 times the brightest emission `scale`, or not finite. With q = ||R F||_inf
/// below 1 no iterate from B = E can pass scale / (1 - q), so only an operator whose rows, times
/// R, sum to 1 or more gets there: light grows at every bounce. Cost: O(1).
inline bool diverged(double size, double scale) {
    return !std::isfinite(size) || size > 1e9 * scale;
}

/// Stops a dense iteration that diverged (diverged()): throws Error naming the step and the
/// largest row sum q. Rows sum past 1 where form factors lack visibility and surfaces hide one
/// another (the analytic method by default). Without this check such a solve ran to its guard
/// and wrote radiosities of 1e23, or infinity, into the outputs (RRV's room3 with the analytic
/// method). Cost: O(1).
inline void check_divergence(const Report& report, const char* step, double size, double scale,
                             double q) {
    if (!diverged(size, scale)) return;
    char rows[32];
    std::snprintf(rows, sizeof rows, "%.3g", q);
    throw Error(report.solver + ": the solution diverged after " + step + " " +
                std::to_string(report.iterations) +
                " (a radiosity past 1e9 times the brightest emission, or not finite): the rows "
                "of R F sum to up to " +
                rows +
                ", so light grows at every bounce; form factors whose rows sum past 1 are "
                "missing visibility (the analytic method has none: where surfaces hide one "
                "another use the hemicube or ray casting, or its visibility samples)");
}

/// The loop shared by the sweeping solvers: calls sweep(), which returns the largest change of
/// B (absolute, over every band), and size(), ||B||_inf after it, until the rule's bound from
/// the change meets the tolerance, the rule's guard is reached or the progress callback
/// cancels; fills iterations, residual (the last change relative to `scale`, max E),
/// error_bound, converged and cancelled. Throws Error where B diverges (check_divergence). values()
/// gives the current B (interleaved, as to_doubles) for Progress::radiosity; it is called only when
/// the session is observed.
template <SpectrumType S, class Sweep, class Size, class Values>
void sweep_until(SolveSession<S>& session, const StoppingRule& rule, double scale, Sweep&& sweep,
                 Size&& size, Values&& values) {
    Report& report = session.report;
    double first = -1.0;
    while (!rule.exhausted(report.iterations)) {
        const double change = sweep();
        ++report.iterations;
        const double now = size();
        check_divergence(report, "sweep", now, scale, rule.contraction);
        report.residual = change / scale;
        report.error_bound = rule.bound(change, now);
        if (first < 0.0) first = report.error_bound;
        if (rule.met(report.error_bound)) {
            report.converged = true;
            return;
        }
        if (!session.proceed(
                Progress{.phase = "solve",
                         .fraction = rule.fraction(first, report.error_bound),
                         .residual = report.residual,
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
