// Orbit and fly cameras (camera_control.hpp).
#include "camera_control.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace radiosity::view {

namespace {
constexpr double radians_per_pixel = 0.005;

/// v turned by angle about the unit axis (Rodrigues' formula).
glm::dvec3 rotate(const glm::dvec3& v, const glm::dvec3& axis, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return v * c + glm::cross(axis, v) * s + axis * glm::dot(axis, v) * (1.0 - c);
}
}  // namespace

CameraControl::CameraControl(const radiosity::Camera& home, const glm::dvec3& scene_centre)
    : home_(home), camera_(home), centre_(scene_centre), up_(glm::normalize(home.up)) {
    speed_ = 0.5 * glm::length(home.target - home.eye);
}

void CameraControl::pivot_on_centre() {
    // The view does not change: the target only slides along the line of sight.
    if (pivoted_) return;
    pivoted_ = true;
    const glm::dvec3 forward = glm::normalize(camera_.target - camera_.eye);
    const double along = glm::dot(centre_ - camera_.eye, forward);
    if (along > 0.0) camera_.target = camera_.eye + along * forward;
}

void CameraControl::turn(glm::dvec3 pivot, bool about_target, glm::dvec2 pixels) {
    // Orbit turns the eye about the target; fly turns the target about the eye.
    const glm::dvec3 other = about_target ? camera_.eye : camera_.target;
    glm::dvec3 d = other - pivot;
    d = rotate(d, up_, -pixels.x * radians_per_pixel);
    const glm::dvec3 forward = glm::normalize(about_target ? -d : d);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, up_));
    // Dragging down shows the scene from higher up (orbit) or looks down (fly).
    const glm::dvec3 pitched = rotate(d, right, -pixels.y * radians_per_pixel);
    // Keep away from looking straight up or down, where "up" no longer says which way is up.
    const double c = glm::dot(glm::normalize(pitched), up_);
    if (std::abs(c) < std::cos(2.0 * std::numbers::pi / 180.0)) d = pitched;
    (about_target ? camera_.eye : camera_.target) = pivot + d;
}

bool CameraControl::update(const CameraInput& in) {
    bool moved = false;
    if (mode_ == CameraMode::orbit && (in.drag != glm::dvec2(0.0) || in.wheel != 0.0))
        pivot_on_centre();
    const glm::dvec3 view = camera_.target - camera_.eye;
    const double distance = glm::length(view);
    if (in.drag != glm::dvec2(0.0)) {
        if (mode_ == CameraMode::orbit)
            turn(camera_.target, true, in.drag);
        else
            turn(camera_.eye, false, in.drag);
        moved = true;
    }
    const glm::dvec3 forward = glm::normalize(camera_.target - camera_.eye);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, up_));
    const glm::dvec3 up = glm::cross(right, forward);
    if (in.pan != glm::dvec2(0.0)) {  // the point under the cursor at the target's depth follows it
        const double per_pixel = 2.0 * distance *
                                 std::tan(0.5 * camera_.fov_y_degrees * std::numbers::pi / 180.0) /
                                 std::max(1.0, in.view_height);
        const glm::dvec3 shift = (-in.pan.x * right + in.pan.y * up) * per_pixel;
        camera_.eye += shift;
        camera_.target += shift;
        moved = true;
    }
    if (in.wheel != 0.0) {
        if (mode_ == CameraMode::orbit) {  // nearer to or farther from the target
            camera_.eye = camera_.target - view * std::pow(0.9, in.wheel);
        } else {
            speed_ *= std::pow(1.25, in.wheel);
        }
        moved = mode_ == CameraMode::orbit || moved;
    }
    if (in.move != glm::dvec3(0.0) && in.seconds > 0.0) {
        const double step = speed_ * in.seconds * (in.fast ? 4.0 : 1.0);
        const glm::dvec3 shift = (in.move.x * right + in.move.y * up_ + in.move.z * forward) * step;
        camera_.eye += shift;
        camera_.target += shift;
        moved = true;
    }
    return moved;
}

}  // namespace radiosity::view
