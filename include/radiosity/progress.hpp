#pragma once
/// @file progress.hpp  Progress reporting and cancellation for long work, and a look at an
/// iterative solve as it goes (the solver's current values, for a viewer that draws them).

#include <cstddef>
#include <functional>
#include <span>
#include <string_view>

namespace radiosity {

/// One progress report: which phase, how far through it, and (for solvers) the residual, the
/// iterations done and the current values.
struct Progress {
    std::string_view phase;     ///< "form factors", "solve", "shading", ...
    double fraction = 0.0;      ///< fraction of the phase done, in [0, 1]
    double residual = 0.0;      ///< solver's current relative residual (0 outside solvers)
    std::size_t iteration = 0;  ///< sweeps (or shots) done so far; 0 outside the iterative solvers
    /// The iterative solver's current radiosity B, as it holds it: band_count<S> doubles per
    /// patch, patch after patch; empty outside the iterative solvers. Valid during the call only.
    std::span<const double> radiosity{};
    /// Progressive shooting's unshot radiosity dB, laid out as `radiosity` (what the ambient term
    /// of with_ambient needs); empty for the other solvers.
    std::span<const double> unshot{};
};

/// Called now and then during long work; return false to cancel. An empty function is allowed.
/// A solver calls it from the thread that called solve(), so an observer may also hold the solve
/// there (pause it) by not returning.
using ProgressCallback = std::function<bool(const Progress&)>;

namespace detail {
/// Calls the callback if there is one; returns true to continue.
inline bool report(const ProgressCallback& cb, std::string_view phase, double fraction,
                   double residual = 0.0) {
    return !cb || cb(Progress{phase, fraction, residual});
}
/// Calls the callback with a full report if there is one; returns true to continue.
inline bool report(const ProgressCallback& cb, const Progress& p) {
    return !cb || cb(p);
}
}  // namespace detail

}  // namespace radiosity
