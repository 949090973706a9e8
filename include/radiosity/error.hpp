#pragma once
/// @file error.hpp  The library's exception types.

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace radiosity {

namespace detail {

/// The length of the well-formed UTF-8 sequence at s[i] (RFC 3629: no overlong forms, no
/// surrogates, nothing above U+10FFFF), or 0 if the bytes there are not one.
inline std::size_t utf8_sequence(std::string_view s, std::size_t i) {
    const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned char b = byte(i);
    std::size_t n = 0;
    unsigned char lo = 0x80, hi = 0xBF;  // the allowed range of the second byte
    if (b >= 0xC2 && b <= 0xDF)
        n = 2;
    else if (b >= 0xE0 && b <= 0xEF)
        n = 3, lo = b == 0xE0 ? 0xA0 : 0x80, hi = b == 0xED ? 0x9F : 0xBF;
    else if (b >= 0xF0 && b <= 0xF4)
        n = 4, lo = b == 0xF0 ? 0x90 : 0x80, hi = b == 0xF4 ? 0x8F : 0xBF;
    if (n == 0 || i + n > s.size() || byte(i + 1) < lo || byte(i + 1) > hi) return 0;
    for (std::size_t k = 2; k < n; ++k)
        if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
    return n;
}

/// A message as one readable terminal line: control bytes (a newline, an escape sequence that
/// would recolour or clear the terminal), DEL and bytes that are not well-formed UTF-8, as a
/// bad file may hold them, become \xNN (a backslash itself stays as it is). Cost: O(length).
inline std::string printable(std::string_view s) {
    static constexpr char hex[] = "0123456789abcdef";
    std::string out;
    out.reserve(s.size());
    for (std::size_t i = 0; i < s.size();) {
        const auto b = static_cast<unsigned char>(s[i]);
        if (b >= 0x20 && b < 0x7F) {
            out += s[i++];
        } else if (const std::size_t n = b >= 0x80 ? utf8_sequence(s, i) : 0; n > 0) {
            out.append(s.substr(i, n));
            i += n;
        } else {
            out += "\\x";
            out += hex[b >> 4];
            out += hex[b & 15];
            ++i;
        }
    }
    return out;
}

}  // namespace detail

/// Bad input at a boundary (a file, a user array, an option). The message names the file,
/// line or element at fault, e.g. "scene.obj:12: face 3 has zero area"; whatever bytes of the
/// input it quotes are escaped (detail::printable), so it stays one readable line.
class Error : public std::runtime_error {
  public:
    /// An error with the message `what`, its non-printable bytes escaped. Cost: O(length).
    explicit Error(const std::string& what) : std::runtime_error(detail::printable(what)) {}
    /// The same for a C string.
    explicit Error(const char* what) : Error(std::string(what)) {}
};

/// Thrown when a progress callback asked to stop during work that has no partial result
/// (form-factor assembly); solvers instead return early with Report::cancelled set.
class Cancelled : public std::runtime_error {
  public:
    Cancelled() : std::runtime_error("cancelled") {}
};

}  // namespace radiosity
