#pragma once
// Tests that results do not depend on the thread count. They prove something only where a
// parallel region really runs on several threads: in a build without OpenMP they are skipped
// (TEST_CASE("..." * test::needs_threads())), so that no test passes there by comparing a
// one-thread run with itself; and on_threads fails the test if the OpenMP runtime hands out
// fewer threads than asked for (OMP_THREAD_LIMIT, OMP_DYNAMIC).
#include <doctest/doctest.h>

#if defined(RADIOSITY_WITH_OPENMP)
#include <omp.h>
#endif

#include <utility>

namespace radiosity::test {

/// Whether this build runs parallel regions on several threads.
#if defined(RADIOSITY_WITH_OPENMP)
inline constexpr bool with_threads = true;
#else
inline constexpr bool with_threads = false;
#endif

/// The decorator of a thread-count test: skipped (not even listed for ctest) without OpenMP,
/// where there is only ever one thread.
inline doctest::skip needs_threads() {
    return doctest::skip(!with_threads);
}

/// Calls f() with OpenMP set to n threads (dynamic adjustment off) and returns its result;
/// REQUIREs that a parallel region then gets n threads.
template <class F>
auto on_threads(int n, F&& f) {
#if defined(RADIOSITY_WITH_OPENMP)
    const int before = omp_get_max_threads();
    const int dynamic = omp_get_dynamic();
    omp_set_dynamic(0);
    omp_set_num_threads(n);
    int team = 0;
#pragma omp parallel
    {
#pragma omp single
        team = omp_get_num_threads();
    }
    struct Restore {
        int threads, dynamic;
        ~Restore() {
            omp_set_num_threads(threads);
            omp_set_dynamic(dynamic);
        }
    } restore{before, dynamic};
    REQUIRE_MESSAGE(team == n, "OpenMP gave " << team << " threads where " << n << " were asked");
    return std::forward<F>(f)();
#else
    REQUIRE_MESSAGE(n == 1, "this build has no threads (built without OpenMP)");
    return std::forward<F>(f)();
#endif
}

}  // namespace radiosity::test
