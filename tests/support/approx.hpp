#pragma once
// Approximate comparisons with a relative tolerance.
#include <doctest/doctest.h>

#include <limits>

namespace radiosity::test {

/// doctest::Approx with a relative tolerance: a == approx(b).epsilon(e) holds where
/// |a - b| < e max(|a|, |b|). doctest's own Approx adds its scale, 1 unless set, to max(|a|, |b|),
/// so that for values well below 1 its epsilon is an absolute tolerance: Approx(0.03).epsilon(0.02)
/// accepts anything from 0.0094 to 0.051. (The scale here is the smallest normal double, not 0,
/// so that 0 == approx(0) holds, doctest's test being strict; anything else against 0 fails.)
inline doctest::Approx approx(double value) {
    return doctest::Approx(value).scale(std::numeric_limits<double>::min());
}

}  // namespace radiosity::test
