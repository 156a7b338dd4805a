#include "tools/viewer/orbit_camera.h"

#include <Eigen/Geometry>
#include <cmath>

namespace xcut::viewer {

namespace {
struct Basis {
    Vec3 forward, right, up;
};
Basis basis(const OrbitCamera& c) {  // as engine/io/render.cpp builds it
    Basis b;
    b.forward = (c.target - c.position).normalized();
    b.right = b.forward.cross(c.up).normalized();
    b.up = b.right.cross(b.forward);
    return b;
}
}  // namespace

OrbitCamera OrbitCamera::from(const Camera& c) {
    OrbitCamera o;
    o.position = c.position, o.target = c.target, o.up = c.up, o.fov_deg = c.fov_deg;
    return o;
}

Camera OrbitCamera::as_render_camera(int width, int height) const {
    Camera c;
    c.position = position, c.target = target, c.up = up, c.fov_deg = fov_deg;
    c.width = width, c.height = height;
    c.automatic = false;
    return c;
}

Eigen::Matrix4f OrbitCamera::view() const {
    const Basis b = basis(*this);
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.block<1, 3>(0, 0) = b.right.transpose();
    m.block<1, 3>(1, 0) = b.up.transpose();
    m.block<1, 3>(2, 0) = -b.forward.transpose();
    m(0, 3) = -b.right.dot(position), m(1, 3) = -b.up.dot(position), m(2, 3) = b.forward.dot(position);
    return m.cast<float>();
}

Eigen::Matrix4f OrbitCamera::projection(double aspect) const {
    const double dist = (target - position).norm();
    const double n = 0.01 * dist, f = 100.0 * dist;
    const double t = 1.0 / std::tan(0.5 * fov_deg * M_PI / 180.0);
    Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
    p(0, 0) = t / aspect, p(1, 1) = t;
    p(2, 2) = -(f + n) / (f - n), p(2, 3) = -2.0 * f * n / (f - n);
    p(3, 2) = -1.0;
    return p.cast<float>();
}

Ray OrbitCamera::ray(double x, double y, int width, int height) const {
    const Basis b = basis(*this);
    const double half_h = std::tan(0.5 * fov_deg * M_PI / 180.0), half_w = half_h * width / height;
    const double sx = (2.0 * x / width - 1.0) * half_w, sy = (1.0 - 2.0 * y / height) * half_h;
    Ray r;
    r.origin = position;
    r.direction = (b.forward + sx * b.right + sy * b.up).normalized();
    return r;
}

void OrbitCamera::orbit(double yaw, double pitch) {
    const Basis b = basis(*this);
    const Eigen::Matrix3d rot = (Eigen::AngleAxisd(-yaw, b.up) * Eigen::AngleAxisd(-pitch, b.right)).toRotationMatrix();
    position = target + rot * (position - target);
    up = rot * b.up;
}

void OrbitCamera::pan(double dx, double dy) {
    const Basis b = basis(*this);
    const double h = 2.0 * std::tan(0.5 * fov_deg * M_PI / 180.0) * (target - position).norm();
    const Vec3 move = (-dx * b.right + dy * b.up) * h;
    position += move, target += move;
}

void OrbitCamera::zoom(double factor) { position = target + factor * (position - target); }

}  // namespace xcut::viewer
