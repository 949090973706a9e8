#pragma once
/// @file version.hpp  Version of the radiosity library (semantic versioning).

#define RADIOSITY_VERSION_MAJOR 0
#define RADIOSITY_VERSION_MINOR 1
#define RADIOSITY_VERSION_PATCH 0
/// The version as a string literal, "MAJOR.MINOR.PATCH".
#define RADIOSITY_VERSION_STRING "0.1.0"
