#pragma once
/// @file budget.hpp  What a dense form-factor matrix will cost before it is allocated: 4 n^2
/// bytes (DenseMatrix stores floats) and n rows of the method. A run over the limit is refused
/// up front, naming what it needs, instead of swapping the machine or being killed by it.

#include <radiosity/concepts.hpp>
#include <radiosity/error.hpp>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

#if defined(__unix__) || defined(__APPLE__)
#include <unistd.h>
#endif

namespace radiosity {

/// The machine's physical memory in bytes (sysconf), or 0 where it cannot be told.
inline std::size_t physical_memory_bytes() {
#if defined(_SC_PHYS_PAGES) && defined(_SC_PAGE_SIZE)
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    if (pages > 0 && page > 0) return static_cast<std::size_t>(pages) * std::size_t(page);
#endif
    return 0;
}

/// The default limit on a dense matrix: half the physical memory (the rest for the mesh, the
/// solver's vectors, the operating system and other programs); 8 GiB where it cannot be told.
inline std::size_t default_matrix_limit() {
    const std::size_t m = physical_memory_bytes();
    return m > 0 ? m / 2 : std::size_t(8) << 30;
}

/// Bytes of the dense n x n matrix of floats: 4 n^2.
inline double dense_matrix_bytes(std::size_t n) {
    return double(n) * double(n) * double(sizeof(float));
}

/// A dense matrix refused for its size: the patch count, the bytes it needs, the limit and an
/// estimate of the form factors' time, for the caller to say which of its options reduce it.
class MemoryLimitError : public Error {
  public:
    /// The refusal of n patches needing `bytes` over `limit`; seconds < 0: no time estimate.
    MemoryLimitError(std::size_t n, double bytes, std::size_t limit, double seconds)
        : Error(message(n, bytes, limit, seconds)),
          patches(n),
          bytes_needed(bytes),
          limit_bytes(limit),
          estimated_seconds(seconds) {}
    std::size_t patches;       ///< n
    double bytes_needed;       ///< 4 n^2
    std::size_t limit_bytes;   ///< the limit it exceeds
    double estimated_seconds;  ///< form factors' time, one thread, from timed rows; < 0: none

    /// "60000 patches need a dense form-factor matrix of 14.4 GB (4 n^2 bytes) ..."
    static std::string message(std::size_t n, double bytes, std::size_t limit, double seconds) {
        char buf[320];
        std::snprintf(buf, sizeof buf,
                      "%zu patches need a dense form-factor matrix of %.3g GB (4 n^2 bytes), "
                      "more than the limit of %.3g GB",
                      n, bytes / 1e9, double(limit) / 1e9);
        std::string s = buf;
        if (seconds >= 0.0) {
            std::snprintf(buf, sizeof buf, ", and its rows would take about %.3g s of one core",
                          seconds);
            s += buf;
        }
        return s +
               "; fewer patches (SolveOptions::subdivision: a longer max_edge or a larger "
               "max_area) need n^2 less, the hierarchical solver and progressive shooting "
               "need no matrix, and "
               "SolveOptions::max_matrix_bytes raises the limit";
    }
};

/// The time of all n rows of a prepared method on one core, from timing `samples` rows spread
/// over the patches (rows differ in cost with what each patch sees). Cost: those rows.
template <RowSource M>
double estimate_rows_seconds(const M& method, std::size_t n, std::size_t samples = 4) {
    if (n == 0) return 0.0;
    samples = std::min(samples, n);
    std::vector<float> row(n);
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t k = 0; k < samples; ++k) method.row(k * n / samples, row);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return s / double(samples) * double(n);
}

/// Refuses a dense matrix of n patches above `limit` bytes (0: default_matrix_limit()) by
/// MemoryLimitError, with the rows' time estimated from a few timed rows of the prepared
/// method. Cost: O(1) when within the limit.
template <RowSource M>
void check_dense_budget(const M& method, std::size_t n, std::size_t limit) {
    if (limit == 0) limit = default_matrix_limit();
    const double bytes = dense_matrix_bytes(n);
    if (bytes <= double(limit)) return;
    throw MemoryLimitError(n, bytes, limit, estimate_rows_seconds(method, n));
}

}  // namespace radiosity
