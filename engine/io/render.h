#pragma once
// `xcut render` and the picture that ends a run: the visual surface ray-cast with Embree from a
// pinhole camera, Lambert-shaded, skin in a flesh tone and the cut faces (the wound's inside) in red,
// written as an RGB PNG with libpng.
#include <array>
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

/// A camera looking at the points from above and in front, the closest that keeps every point
/// inside the view with a 5 % margin (exact for a pinhole camera, so nothing is cropped).
Camera frame_points(const std::vector<Vec3>& points, int width, int height);
/// frame_points of the surface's vertices.
Camera frame_surface(const SurfaceMesh& surface, int width, int height);
/// Pixels per metre at the camera's target (for a scale bar).
double pixels_per_metre(const Camera& camera);
/// Ray-casts triangles, each Lambert-shaded in its own colour (0..1), on a light background.
Image render_triangles(const std::vector<Vec3>& positions, const std::vector<std::array<int, 3>>& triangles,
                       const std::vector<std::array<double, 3>>& colours, const Camera& camera);
/// The surface in a flesh tone, its cut faces (the wound's inside) in red.
Image render_surface(const SurfaceMesh& surface, const Camera& camera);

/// What `xcut render` and the picture ending a run show (engine/io/render_world.cpp).
struct RenderOptions {
    /// "": the visual surface coloured by material (by region when the body has one material),
    /// the wound in red; "von_mises" [Pa] or "displacement" [m]: coloured by the field, with a
    /// colour bar.
    std::string field;
    bool tools = true;      ///< draw the tools: contact shapes and blades
    bool scale_bar = true;
};
/// Frames the visual surface and, when drawn, the tools (frame_points), in the part of the picture
/// left of the colour bar when there is one.
Camera frame_world(const World& world, int width, int height, const RenderOptions& options);
Image render_world(const World& world, const Camera& camera, const RenderOptions& options);
/// Writes `image` as PNG; throws InputError naming `path` if it cannot.
void write_png(const Image& image, const std::string& path);

}  // namespace xcut
