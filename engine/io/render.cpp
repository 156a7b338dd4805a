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

Camera frame_surface(const SurfaceMesh& s, int width, int height) {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::max()), hi = -lo;
    for (const Vec3& p : s.position) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    Camera c;
    c.width = width, c.height = height;
    c.target = 0.5 * (lo + hi);
    const double radius = 0.5 * (hi - lo).norm();
    const Vec3 dir = Vec3(0.45, -0.6, 1.0).normalized();  // from above, in front and to the side
    c.position = c.target + dir * radius / std::tan(0.5 * c.fov_deg * M_PI / 180.0) * 1.05;
    c.up = Vec3::UnitY();
    c.automatic = false;
    return c;
}

Image render_surface(const SurfaceMesh& s, const Camera& cam) {
    EmbreeSurface embree;
    embree.build(s.position, s.triangles);

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
            const bool cut = t < static_cast<int>(s.cut_face.size()) && s.cut_face[t];
            const double base[3] = {cut ? 0.80 : 0.93, cut ? 0.12 : 0.76, cut ? 0.12 : 0.66};
            for (int k = 0; k < 3; ++k) px[k] = static_cast<unsigned char>(std::lround(255.0 * base[k] * shade));
        }
    }, 1);
    return img;
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
