#pragma once
/// @file parallel.hpp  The library's parallel plumbing, in one place: which thread is running,
/// whether a pass is worth threads, a pause for spin-waits, and a parallel loop over rows with
/// progress and cancellation. OpenMP when the build has it (RADIOSITY_WITH_OPENMP); otherwise
/// every function here runs on the calling thread, with the same results.

#include <radiosity/error.hpp>
#include <radiosity/progress.hpp>

#include <atomic>
#include <cstddef>
#include <cstdint>

#if defined(RADIOSITY_WITH_OPENMP)
#include <omp.h>
#endif
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace radiosity::detail {

/// This thread's index in its OpenMP team: 0 outside a parallel region or without OpenMP, so
/// that "thread 0" is always the one that reports progress or keeps a result. Cost: a call.
inline int thread_index() {
#if defined(RADIOSITY_WITH_OPENMP)
    return omp_get_thread_num();
#else
    return 0;
#endif
}

/// How many threads a parallel region would have: 1 without OpenMP. Cost: a call.
inline int thread_count() {
#if defined(RADIOSITY_WITH_OPENMP)
    return omp_get_max_threads();
#else
    return 1;
#endif
}

/// Whether a pass over an n x n system of K bands is worth sharing among threads: from 2^24
/// products on (a few milliseconds), below which starting and waking threads, on a machine
/// with other work, can cost more than the pass. Results do not depend on it: the work is cut
/// the same way either way. Cost: a comparison.
inline bool worth_threads(std::size_t n, std::size_t K) {
    return static_cast<double>(n) * static_cast<double>(n) * static_cast<double>(K) >= 0x1p24;
}

/// A short pause in a spin-wait loop: x86's pause, which frees the core's resources for a
/// sibling hyper-thread and saves power while waiting; nothing elsewhere. Cost: tens of cycles.
inline void spin_pause() {
#if defined(__SSE2__)
    _mm_pause();
#endif
}

/// Runs body(i) for every row i < n, rows shared among threads (dynamically, 4 at a time: rows
/// of form factors differ in cost), reporting progress as "form factors" from thread 0 only (so
/// the callback need not be thread-safe) and stopping, by throwing Cancelled, when the callback
/// asks to. body must be safe to call for different rows at once. Cost: n calls of body.
template <class Body>
void for_each_row(std::size_t n, const ProgressCallback& progress, Body&& body) {
    std::atomic<std::size_t> done{0};
    std::atomic<bool> cancel{false};
    const auto count = static_cast<std::int64_t>(n);
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(dynamic, 4)
#endif
    for (std::int64_t i = 0; i < count; ++i) {
        if (cancel.load(std::memory_order_relaxed)) continue;
        body(static_cast<std::size_t>(i));
        const std::size_t d = ++done;
        if (thread_index() == 0 && !detail::report(progress, "form factors",
                                                   static_cast<double>(d) / static_cast<double>(n)))
            cancel = true;
    }
    if (cancel) throw Cancelled();
}

}  // namespace radiosity::detail
