#pragma once
// Forced thread counts for the tests that compare runs on one thread and on several. Without
// OpenMP every run is on the calling thread, so such a comparison would prove nothing: those
// tests are then skipped (doctest's skip decorator, with `threads::without_openmp`), and say so
// in the summary, rather than pass without having compared anything.
#if defined(RADIOSITY_WITH_OPENMP)
#include <omp.h>
#endif

namespace radiosity::test::threads {

/// True in a build without OpenMP: the argument of doctest::skip for a thread-count test.
#if defined(RADIOSITY_WITH_OPENMP)
inline constexpr bool without_openmp = false;
#else
inline constexpr bool without_openmp = true;
#endif

/// Sets the OpenMP team size for the life of the object and restores the previous one after.
class Forced {
  public:
    explicit Forced(int count) {
#if defined(RADIOSITY_WITH_OPENMP)
        before_ = omp_get_max_threads();
        omp_set_num_threads(count);
#else
        (void)count;
#endif
    }
    ~Forced() {
#if defined(RADIOSITY_WITH_OPENMP)
        omp_set_num_threads(before_);
#endif
    }
    Forced(const Forced&) = delete;
    Forced& operator=(const Forced&) = delete;

  private:
    int before_ = 1;
};

/// How many threads a parallel region gets now: what a test must check after forcing a count,
/// since OMP_THREAD_LIMIT or OMP_DYNAMIC may give fewer than asked for (1 without OpenMP).
inline int team_size() {
    int size = 1;
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel
    {
#pragma omp single
        size = omp_get_num_threads();
    }
#endif
    return size;
}

}  // namespace radiosity::test::threads
