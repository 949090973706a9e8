#pragma once
/// @file error.hpp  The library's exception types.

#include <stdexcept>
#include <string>

namespace radiosity {

/// Bad input at a boundary (a file, a user array, an option). The message names the file,
/// line or element at fault, e.g. "scene.obj:12: face 3 has zero area".
class Error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// Thrown when a progress callback asked to stop during work that has no partial result
/// (form-factor assembly); solvers instead return early with Report::cancelled set.
class Cancelled : public std::runtime_error {
  public:
    Cancelled() : std::runtime_error("cancelled") {}
};

}  // namespace radiosity
