#pragma once
/// @file camera_control.hpp  The two ways of moving the camera: orbit (turn about the target,
/// pan, zoom) and fly (look about from the eye, move along the view). Both move a
/// radiosity::Camera, which starts as the `radiosity` program's camera and stays exactly that
/// until the user moves it.

#include <radiosity/shading/camera.hpp>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace radiosity::view {

/// How mouse and keys move the camera.
enum class CameraMode { orbit, fly };

/// One frame's input, already taken from the window (and not claimed by the panels).
struct CameraInput {
    glm::dvec2 drag{0.0};    ///< mouse movement in pixels while the rotate button is held
    glm::dvec2 pan{0.0};     ///< mouse movement in pixels while the pan button is held
    double wheel = 0.0;      ///< scroll steps (positive: towards the scene)
    glm::dvec3 move{0.0};    ///< fly keys: right, up, forward, each -1, 0 or 1
    bool fast = false;       ///< fly faster (shift)
    double seconds = 0.0;    ///< time since the last frame
    double view_height = 1;  ///< viewport height in pixels (pans follow the cursor)
};

/// The camera and how the input moves it.
class CameraControl {
  public:
    /// Starts at `home`, in orbit mode. Orbits turn about the point of the line of sight
    /// nearest the scene's centre (the Cornell camera's target is the box's open front; turning
    /// about it would swing the box out of view), or about the target if that point lies behind
    /// the eye.
    CameraControl(const radiosity::Camera& home, const glm::dvec3& scene_centre);

    const radiosity::Camera& camera() const { return camera_; }  ///< where it is now
    CameraMode mode() const { return mode_; }                    ///< orbit or fly
    void set_mode(CameraMode mode) { mode_ = mode; }             ///< keeps the view
    /// Back to the start.
    void reset() {
        camera_ = home_;
        pivoted_ = false;
    }
    void set_fov(double degrees) { camera_.fov_y_degrees = degrees; }  ///< vertical angle
    /// Applies one frame of input; returns whether the camera moved.
    bool update(const CameraInput& in);

  private:
    void turn(glm::dvec3 pivot, bool about_target, glm::dvec2 pixels);
    void pivot_on_centre();

    radiosity::Camera home_, camera_;
    CameraMode mode_ = CameraMode::orbit;
    glm::dvec3 centre_;
    bool pivoted_ = false;  // the target slid onto the orbit's pivot
    glm::dvec3 up_;         // the world's up: turns keep it up
    double speed_;          // fly speed, scene units per second
};

}  // namespace radiosity::view
