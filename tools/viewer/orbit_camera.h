#pragma once
// The viewer's camera: a pinhole at `position` looking at `target`, orbited about the target, panned
// across the view and zoomed towards it. Its view and projection are the headless renderer's
// (engine/io/render.h: same eye, target, up and vertical field of view), so a frame of the window and
// `xcut render` of the same state line up pixel for pixel.
#include <Eigen/Core>

#include "engine/io/render.h"
#include "tools/viewer/hand_tools.h"

namespace xcut::viewer {

struct OrbitCamera {
    Vec3 position = Vec3(0, 0, 1), target = Vec3::Zero(), up = Vec3::UnitY();  ///< [m]
    double fov_deg = 40.0;  ///< vertical

    static OrbitCamera from(const Camera& c);
    Camera as_render_camera(int width, int height) const;
    /// Column-major 4x4 matrices for OpenGL (near/far planes fitted to the distance).
    Eigen::Matrix4f view() const;
    Eigen::Matrix4f projection(double aspect) const;
    /// The ray through pixel (x, y) of a width x height window, (0, 0) its top-left corner.
    Ray ray(double x, double y, int width, int height) const;
    /// Orbit by angles [rad] about the view's up and right axes, through the target.
    void orbit(double yaw, double pitch);
    /// Pan by fractions of the view's height.
    void pan(double dx, double dy);
    /// Moves towards the target by `factor` (< 1 nearer).
    void zoom(double factor);
};

}  // namespace xcut::viewer
