#pragma once
/// @file spectrum.hpp  Colour types of the radiosity quantities E, R and B: `float` (grey, for
/// teaching), `Rgb` (the default) and `Spectrum<N>` (N spectral bands), and the `SpectrumType`
/// concept they model. Radiosity is linear, so each band is solved independently: every
/// operation here is per band.

#include <array>
#include <cmath>
#include <algorithm>
#include <concepts>
#include <type_traits>
#include <cstddef>

namespace radiosity {

/// N bands of a spectral quantity (exitance, reflectance), stored as float per band.
template <std::size_t N>
struct Spectrum {
    static_assert(N >= 1, "a spectrum needs at least one band");
    std::array<float, N> v{};  ///< the bands

    constexpr Spectrum() = default;
    /// The same value in every band.
    constexpr explicit Spectrum(float all) { v.fill(all); }
    /// One value per band, e.g. Rgb{0.7f, 0.2f, 0.1f}.
    template <std::convertible_to<float>... T>
    requires(sizeof...(T) == N && N > 1) constexpr Spectrum(T... bands)
        : v{static_cast<float>(bands)...} {}

    constexpr float& operator[](std::size_t k) { return v[k]; }
    constexpr float operator[](std::size_t k) const { return v[k]; }

    constexpr Spectrum& operator+=(const Spectrum& o) {
        for (std::size_t k = 0; k < N; ++k) v[k] += o.v[k];
        return *this;
    }
    constexpr Spectrum& operator-=(const Spectrum& o) {
        for (std::size_t k = 0; k < N; ++k) v[k] -= o.v[k];
        return *this;
    }
    constexpr Spectrum& operator*=(const Spectrum& o) {
        for (std::size_t k = 0; k < N; ++k) v[k] *= o.v[k];
        return *this;
    }
    constexpr Spectrum& operator*=(float s) {
        for (float& x : v) x *= s;
        return *this;
    }
    friend constexpr Spectrum operator+(Spectrum a, const Spectrum& b) { return a += b; }
    friend constexpr Spectrum operator-(Spectrum a, const Spectrum& b) { return a -= b; }
    friend constexpr Spectrum operator*(Spectrum a, const Spectrum& b) { return a *= b; }
    friend constexpr Spectrum operator*(Spectrum a, float s) { return a *= s; }
    friend constexpr Spectrum operator*(float s, Spectrum a) { return a *= s; }
    friend constexpr bool operator==(const Spectrum&, const Spectrum&) = default;
};

/// Red, green, blue: the default colour type.
using Rgb = Spectrum<3>;

/// Number of bands of a colour type: 1 for float.
template <class S>
inline constexpr std::size_t band_count = 1;
template <std::size_t N>
inline constexpr std::size_t band_count<Spectrum<N>> = N;

/// Band k of a colour value (float has one band).
constexpr float band(float s, std::size_t) {
    return s;
}
template <std::size_t N>
constexpr float band(const Spectrum<N>& s, std::size_t k) {
    return s.v[k];
}
/// Sets band k of a colour value.
constexpr void set_band(float& s, std::size_t, float x) {
    s = x;
}
template <std::size_t N>
constexpr void set_band(Spectrum<N>& s, std::size_t k, float x) {
    s.v[k] = x;
}

/// Largest band: the norm used by convergence tests (max over bands of |x|).
inline float max_abs(float s) {
    return std::abs(s);
}
template <std::size_t N>
float max_abs(const Spectrum<N>& s) {
    float m = 0.0f;
    for (float x : s.v) m = std::max(m, std::abs(x));
    return m;
}

/// Mean over bands, a grey summary of a colour (e.g. for choosing the brightest shooter).
inline float mean_band(float s) {
    return s;
}
template <std::size_t N>
float mean_band(const Spectrum<N>& s) {
    float t = 0.0f;
    for (float x : s.v) t += x;
    return t / static_cast<float>(N);
}

/// True when every band is a finite number.
inline bool all_finite(float s) {
    return std::isfinite(s);
}
template <std::size_t N>
bool all_finite(const Spectrum<N>& s) {
    for (float x : s.v)
        if (!std::isfinite(x)) return false;
    return true;
}

/// A colour type for E, R and B: per-band arithmetic, a value-initialised zero, and the band
/// accessors above. Models: float, Rgb, Spectrum<N>.
template <class S>
concept SpectrumType = std::regular<S> && requires(S a, const S b, float s, std::size_t k) {
    { a + b } -> std::convertible_to<S>;
    { a - b } -> std::convertible_to<S>;
    { a* b } -> std::convertible_to<S>;
    { a* s } -> std::convertible_to<S>;
    { band(b, k) } -> std::convertible_to<float>;
    set_band(a, k, s);
    { max_abs(b) } -> std::convertible_to<float>;
    { all_finite(b) } -> std::convertible_to<bool>;
};

static_assert(SpectrumType<float>);
static_assert(SpectrumType<Rgb>);
static_assert(SpectrumType<Spectrum<8>>);

}  // namespace radiosity

namespace radiosity {

/// Converts an RGB triple (red, green, blue) to a colour type: grey takes the mean, Rgb is
/// unchanged, and N bands (ordered by wavelength, shortest first) take blue, green and red over
/// thirds of the band range. Used for scenes published in RGB (the Cornell box, MTL files).
template <SpectrumType S>
S from_rgb(float r, float g, float b) {
    if constexpr (std::is_same_v<S, float>) {
        return (r + g + b) / 3.0f;
    } else {
        S s{};
        constexpr std::size_t n = band_count<S>;
        for (std::size_t k = 0; k < n; ++k) {
            const std::size_t third = (3 * k) / n;  // 0: blue, 1: green, 2: red
            set_band(s, k,
                     n == 3 ? (k == 0   ? r
                               : k == 1 ? g
                                        : b)
                            : (third == 0   ? b
                               : third == 1 ? g
                                            : r));
        }
        return s;
    }
}

/// Converts a colour value to RGB for display, the inverse of from_rgb: grey is copied to all
/// three, N bands are averaged over thirds of the band range.
template <SpectrumType S>
std::array<float, 3> to_rgb(const S& s) {
    if constexpr (std::is_same_v<S, float>) {
        return {s, s, s};
    } else {
        constexpr std::size_t n = band_count<S>;
        if constexpr (n == 3) {
            return {band(s, 0), band(s, 1), band(s, 2)};
        } else {
            std::array<float, 3> sum{}, count{};
            for (std::size_t k = 0; k < n; ++k) {
                const std::size_t c = 2 - std::min<std::size_t>(2, (3 * k) / n);
                sum[c] += band(s, k);
                count[c] += 1.0f;
            }
            for (std::size_t c = 0; c < 3; ++c) sum[c] = count[c] > 0 ? sum[c] / count[c] : 0.0f;
            return sum;
        }
    }
}

}  // namespace radiosity
