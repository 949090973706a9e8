// The view's modes by name (view_settings.hpp).
#include "view_settings.hpp"

namespace radiosity::view {

const char* mode_name(Mode m) {
    switch (m) {
        case Mode::wireframe:
            return "wireframe";
        case Mode::flat:
            return "flat";
        case Mode::smooth:
            return "smooth";
        case Mode::reflectance:
            return "reflectance";
        case Mode::emission:
            return "emission";
    }
    return "?";
}

std::optional<Mode> parse_mode(const std::string& name) {
    for (Mode m : all_modes)
        if (name == mode_name(m)) return m;
    return std::nullopt;
}

}  // namespace radiosity::view
