#pragma once
// `xcut render` and the picture that ends a run: the visual surface ray-cast with Embree from a
// pinhole camera, Lambert-shaded, skin in a flesh tone and the cut faces (the wound's inside) in red,
// written as an RGB PNG with libpng.
#include <string>
#include <vector>

#include "engine/world.h"

namespace xcut {

struct Camera {
    Vec3 position = Vec3(0, 0, 1);   ///< [m]
    Vec3 target = Vec3::Zero();      ///< [m]
    Vec3 up = Vec3::UnitY();
    double fov_deg = 40.0;           ///< vertical field of view
    int width = 800, height = 600;   ///< pixels
    bool automatic = true;           ///< frame the surface's bounding box from above at an angle
};

struct Image {
    int width = 0, height = 0;
    std::vector<unsigned char> rgb;  ///< row-major, top row first
    std::vector<int> triangle;       ///< per pixel: the triangle hit, -1 background
};

/// A camera looking at the surface's bounding box from above and in front, the box filling the view.
Camera frame_surface(const SurfaceMesh& surface, int width, int height);
Image render_surface(const SurfaceMesh& surface, const Camera& camera);
/// Writes `image` as PNG; throws InputError naming `path` if it cannot.
void write_png(const Image& image, const std::string& path);

}  // namespace xcut
