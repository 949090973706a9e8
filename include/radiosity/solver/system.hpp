#pragma once
/// @file system.hpp  The radiosity system B = E + R F B, i.e. (I - M) B = E with M_ij = R_i F_ij
/// (Goral, Torrance, Greenberg & Battaile 1984), and what every solver returns.

#include <radiosity/error.hpp>
#include <radiosity/spectrum.hpp>

#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace radiosity {

/// The per-patch data of the system: emission E_i (radiant exitance), reflectance R_i (each band
/// in [0, 1)) and area A_i. The views must outlive the solve.
template <SpectrumType S>
struct System {
    std::span<const S> emission;     ///< E_i
    std::span<const S> reflectance;  ///< R_i
    std::span<const double> area;    ///< A_i

    std::size_t size() const { return emission.size(); }  ///< number of patches n

    /// Throws Error naming the first patch whose E or R is out of range or not finite, or if the
    /// sizes disagree.
    void validate() const {
        if (reflectance.size() != emission.size() || area.size() != emission.size())
            throw Error("radiosity system: emission, reflectance and area sizes differ");
        for (std::size_t i = 0; i < size(); ++i) {
            const std::string at = "patch " + std::to_string(i);
            if (!all_finite(emission[i]) || !all_finite(reflectance[i]))
                throw Error(at + ": emission or reflectance is not a finite number");
            for (std::size_t k = 0; k < band_count<S>; ++k) {
                const float r = band(reflectance[i], k), e = band(emission[i], k);
                if (r < 0.0f || r >= 1.0f) throw Error(at + ": reflectance must lie in [0, 1)");
                if (e < 0.0f) throw Error(at + ": emission must not be negative");
            }
            if (!(area[i] > 0.0)) throw Error(at + ": area must be positive");
        }
    }
};

/// What a solve did: iterations (sweeps, or shots for progressive), the final relative residual
/// (or relative unshot energy), the bound on the relative error of B that the tolerance is
/// compared with, whether it met its tolerance, whether it was cancelled, and time.
struct Report {
    std::string solver;          ///< "jacobi", "gauss-seidel", "progressive", "direct"
    std::size_t iterations = 0;  ///< sweeps, or shots for progressive
    double residual = 0.0;       ///< final relative residual (see each solver)
    /// A bound on the relative error of the returned B against the exact solution B* of the
    /// system solved, ||B - B*|| / ||B*|| (the max norm; progressive shooting with rows on demand:
    /// the power norm; see detail::StoppingRule); infinity where none can be given.
    double error_bound = std::numeric_limits<double>::infinity();
    bool converged = false;  ///< error_bound <= tolerance (direct: solved)
    bool cancelled = false;  ///< stopped by the progress callback
    double seconds = 0.0;    ///< wall-clock time of the solve
};

/// A solver's result: the radiosity B_i of every patch, and the report.
template <SpectrumType S>
struct Solution {
    std::vector<S> radiosity;  ///< B_i
    Report report;             ///< how the solve went
};

}  // namespace radiosity
