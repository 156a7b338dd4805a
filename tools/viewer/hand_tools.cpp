#include "tools/viewer/hand_tools.h"

#include <fmt/format.h>

#include <algorithm>

namespace xcut::viewer {

HandToolSizes hand_tool_sizes(const Vec3& lo, const Vec3& hi) {
    const Vec3 size = hi - lo;
    const double thin = std::max(size.minCoeff(), 1e-4), large = std::max(size.maxCoeff(), 1e-3);
    HandToolSizes s;
    s.lift = 0.05 * large;
    s.max_depth = std::min(1.5 * thin, 0.05);
    s.depth = std::min(1.25 * thin, 0.01);  // through a sheet of skin; 10 mm into an organ
    s.probe_radius = 0.06 * large;
    const Vec3 centre = 0.5 * (lo + hi);
    s.scalpel_park = Vec3(centre.x(), centre.y(), hi.z() + 2.0 * s.lift);
    s.probe_park = Vec3(hi.x() + 2.0 * s.probe_radius, centre.y(), hi.z() + 2.0 * s.probe_radius);
    return s;
}

std::vector<std::string> hand_tool_overrides(const HandToolSizes& s, bool with_probe) {
    auto vec = [](const Vec3& v) { return fmt::format("[{:.17g}, {:.17g}, {:.17g}]", v.x(), v.y(), v.z()); };
    std::vector<std::string> out;
    out.push_back(fmt::format(R"(tools+={{"name": "{}", "blade": {{"tip": [0, 0, 0], "heel": [0, 0, {:.17g}]}}, )"
                                  R"("trajectory": [{{"time": 0, "position": {}}}], "device": {{"type": "viewer"}}}})",
                                  kHandScalpel, s.max_depth + 2.0 * s.lift, vec(s.scalpel_park)));
    if (with_probe)
        out.push_back(fmt::format(R"(tools+={{"name": "{}", "shape": {{"type": "sphere", "radius": {:.17g}}}, )"
                                  R"("trajectory": [{{"time": 0, "position": {}}}], "device": {{"type": "viewer"}}}})",
                                  kHandProbe, s.probe_radius, vec(s.probe_park)));
    return out;
}

void SurfaceRaycaster::build(const Snapshot& s) {
    embree_.build(s.surface, s.triangles);
    cut_face_ = s.cut_face;
    built_ = !s.triangles.empty();
}

std::optional<SurfaceHit> SurfaceRaycaster::cast(const Ray& ray) const {
    const std::optional<RayHit> hit = built_ ? embree_.intersect(ray.origin, ray.direction) : std::nullopt;
    if (!hit) return std::nullopt;
    SurfaceHit h;
    h.triangle = hit->triangle;
    h.point = ray.origin + hit->distance * ray.direction;
    h.normal = hit->normal.normalized();
    if (h.normal.dot(ray.direction) > 0.0) h.normal = -h.normal;
    h.cut_face = h.triangle < static_cast<int>(cut_face_.size()) && cut_face_[h.triangle] != 0;
    return h;
}

MouseScalpel::MouseScalpel(LiveDevice& device, const HandToolSizes& sizes)
    : depth(sizes.depth), max_depth(sizes.max_depth), device_(device), lift_(sizes.lift) {}

void MouseScalpel::place(const Vec3& surface_point) {
    const double below = cutting_ ? std::clamp(depth, 0.0, max_depth) : -lift_;
    const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), normal_);
    device_.set_target(surface_point - below * normal_, q);
    last_ = surface_point;
}

void MouseScalpel::hover(const std::optional<SurfaceHit>& hit) {
    if (cutting_ || !hit || hit->cut_face) return;
    normal_ = hit->normal;
    place(hit->point);
}

void MouseScalpel::press(const std::optional<SurfaceHit>& hit) {
    if (!hit || hit->cut_face) return;  // a press off the skin does nothing
    entry_ = hit->point, normal_ = hit->normal;
    cutting_ = true;
    place(hit->point);
}

void MouseScalpel::drag(const Ray& ray, const std::optional<SurfaceHit>& hit) {
    if (!cutting_) return hover(hit);
    if (hit && !hit->cut_face && hit->normal.dot(normal_) > 0.5) {
        place(hit->point);  // on the skin: follow it, the blade keeps the entry's direction
        return;
    }
    const double denom = ray.direction.dot(normal_);  // into the wound or off the body: the tangent plane
    if (std::abs(denom) < 1e-9) return;
    const double t = (entry_ - ray.origin).dot(normal_) / denom;
    if (t > 0.0) place(ray.origin + t * ray.direction);
}

void MouseScalpel::release() {
    if (!cutting_) return;
    cutting_ = false;
    place(last_);
}

}  // namespace xcut::viewer
