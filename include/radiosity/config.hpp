#pragma once
/// @file config.hpp  The user-facing macros, documented together.
///
/// - RADIOSITY_ASSERT(cond): checks an internal invariant (never user input, which throws
///   radiosity::Error). On by default; define RADIOSITY_NO_ASSERT, or NDEBUG, to compile it out.
///   Define RADIOSITY_ASSERT yourself before including any header to route it to your own handler.
/// - RADIOSITY_WITH_OPENMP: defined by the build (CMake option RADIOSITY_OPENMP) when OpenMP is
///   used for form-factor rows and solver sweeps. Results do not depend on the thread count.

#include <cstdio>
#include <cstdlib>

#ifndef RADIOSITY_ASSERT
#if defined(RADIOSITY_NO_ASSERT) || defined(NDEBUG)
#define RADIOSITY_ASSERT(cond) ((void)0)
#else
/// Checks an internal invariant; a failure is a bug in the library, so it aborts with the place.
#define RADIOSITY_ASSERT(cond)                                                                   \
    ((cond) ? (void)0                                                                            \
            : (std::fprintf(stderr, "radiosity: internal assertion failed: %s (%s:%d)\n", #cond, \
                            __FILE__, __LINE__),                                                 \
               std::abort()))
#endif
#endif
