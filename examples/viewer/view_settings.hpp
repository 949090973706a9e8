#pragma once
/// @file view_settings.hpp  What the picture shows: RRV's modes and more, the patch edges, the
/// ambient term, the exposure, and whether a picked patch's form-factor row replaces the mode.

#include <array>
#include <optional>
#include <string>

namespace radiosity::view {

/// What the surfaces show.
enum class Mode { wireframe, flat, smooth, reflectance, emission };

/// The modes in the order of their keys (1 to 5).
inline constexpr std::array<Mode, 5> all_modes{Mode::wireframe, Mode::flat, Mode::smooth,
                                               Mode::reflectance, Mode::emission};
/// The mode's name as --mode spells it.
const char* mode_name(Mode m);
/// The mode of a name; nothing for an unknown one.
std::optional<Mode> parse_mode(const std::string& name);

/// The settings of the picture that the panels and keys change.
struct ViewSettings {
    Mode mode = Mode::smooth;   ///< what the surfaces show
    bool edges = false;         ///< patch edges in every mode (the wireframe mode always)
    bool ambient = false;       ///< add shooting's ambient term to B (display only)
    bool auto_exposure = true;  ///< the exposure from the picture, as the library's pictures
    double stops = 0.0;         ///< exposure compensation
    bool show_row = true;       ///< a picked patch's form-factor row instead of the mode
};

}  // namespace radiosity::view
