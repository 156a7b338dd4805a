#include "engine/io/render.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "engine/error.h"
#include "engine/io/embree_surface.h"
#include "engine/parallel.h"

namespace xcut {

Camera frame_points(const std::vector<Vec3>& points, int width, int height) {
    Camera c;
    c.width = width, c.height = height, c.automatic = false;
    if (points.empty()) return c;
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::max()), hi = -lo;
    for (const Vec3& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    c.target = 0.5 * (lo + hi);
    const Vec3 dir = Vec3(0.45, -0.6, 1.0).normalized();  // from above, in front and to the side
    c.up = Vec3::UnitY();
    const Vec3 forward = -dir, right = forward.cross(c.up).normalized(), up = right.cross(forward);
    const double half_h = 0.95 * std::tan(0.5 * c.fov_deg * M_PI / 180.0), half_w = half_h * width / height;
    // A point q (from the target) is in view when |q.right| <= half_w (d + q.forward), likewise up:
    // the least distance d that holds for every point.
    double d = 1e-9;
    for (const Vec3& p : points) {
        const Vec3 q = p - c.target;
        const double depth = q.dot(forward);
        d = std::max({d, std::abs(q.dot(right)) / half_w - depth, std::abs(q.dot(up)) / half_h - depth});
    }
    d = std::max(d, 0.55 * (hi - lo).norm());  // and outside the bodies' bounding sphere
    c.position = c.target + dir * d;
    return c;
}

Camera frame_surface(const SurfaceMesh& s, int width, int height) { return frame_points(s.position, width, height); }

double pixels_per_metre(const Camera& c) {
    return 0.5 * c.height / std::tan(0.5 * c.fov_deg * M_PI / 180.0) / (c.target - c.position).norm();
}

Image render_triangles(const std::vector<Vec3>& positions, const std::vector<std::array<int, 3>>& triangles,
                       const std::vector<std::array<double, 3>>& colours, const Camera& cam) {
    EmbreeSurface embree;
    embree.build(positions, triangles);

    Image img;
    img.width = cam.width, img.height = cam.height;
    img.rgb.assign(3 * img.width * img.height, 0);
    img.triangle.assign(img.width * img.height, -1);
    const Vec3 forward = (cam.target - cam.position).normalized();
    const Vec3 right = forward.cross(cam.up).normalized(), up = right.cross(forward);
    const double half_h = std::tan(0.5 * cam.fov_deg * M_PI / 180.0), half_w = half_h * img.width / img.height;
    const Vec3 light = Vec3(0.4, -0.3, 1.0).normalized();
    parallel_for(img.height, [&](int row) {
        for (int col = 0; col < img.width; ++col) {
            const double sx = (2.0 * (col + 0.5) / img.width - 1.0) * half_w;
            const double sy = (1.0 - 2.0 * (row + 0.5) / img.height) * half_h;
            const Vec3 d = (forward + sx * right + sy * up).normalized();
            const std::optional<RayHit> hit = embree.intersect(cam.position, d);
            unsigned char* px = &img.rgb[3 * (row * img.width + col)];
            if (!hit) {
                px[0] = 235, px[1] = 238, px[2] = 242;  // background
                continue;
            }
            const int t = hit->triangle;
            img.triangle[row * img.width + col] = t;
            Vec3 n = hit->normal.normalized();
            if (n.dot(d) > 0) n = -n;  // two-sided
            const double shade = 0.25 + 0.75 * std::max(0.0, n.dot(light));
            for (int k = 0; k < 3; ++k) px[k] = static_cast<unsigned char>(std::lround(255.0 * colours[t][k] * shade));
        }
    }, 1);
    return img;
}

Image render_surface(const SurfaceMesh& s, const Camera& cam) {
    std::vector<std::array<double, 3>> colours(s.triangles.size(), {0.93, 0.76, 0.66});  // skin
    for (size_t t = 0; t < s.triangles.size() && t < s.cut_face.size(); ++t)
        if (s.cut_face[t]) colours[t] = {0.80, 0.12, 0.12};  // the wound's inside
    return render_triangles(s.position, s.triangles, colours, cam);
}

void write_png(const Image& img, const std::string& path) {
    png_image png{};
    png.version = PNG_IMAGE_VERSION;
    png.width = static_cast<png_uint_32>(img.width);
    png.height = static_cast<png_uint_32>(img.height);
    png.format = PNG_FORMAT_RGB;
    if (!png_image_write_to_file(&png, path.c_str(), 0, img.rgb.data(), 3 * img.width, nullptr))
        throw InputError(path, "file", std::string("cannot write the PNG: ") + png.message);
}

}  // namespace xcut
