#pragma once
/// @file progress.hpp  Progress reporting and cancellation for long work.

#include <functional>
#include <string_view>

namespace radiosity {

/// One progress report: which phase, how far through it, and (for solvers) the residual.
struct Progress {
    std::string_view phase;  ///< "form factors", "solve", "shading", ...
    double fraction = 0.0;   ///< fraction of the phase done, in [0, 1]
    double residual = 0.0;   ///< solver's current relative residual (0 outside solvers)
};

/// Called now and then during long work; return false to cancel. An empty function is allowed.
using ProgressCallback = std::function<bool(const Progress&)>;

namespace detail {
/// Calls the callback if there is one; returns true to continue.
inline bool report(const ProgressCallback& cb, std::string_view phase, double fraction,
                   double residual = 0.0) {
    return !cb || cb(Progress{phase, fraction, residual});
}
}  // namespace detail

}  // namespace radiosity
