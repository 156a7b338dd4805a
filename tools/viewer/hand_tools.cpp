#include "tools/viewer/hand_tools.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <stdexcept>

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

SurfaceRaycaster::SurfaceRaycaster() {
    device_ = rtcNewDevice("threads=1");
    if (!device_) throw std::runtime_error("Embree: cannot create a device");
}

SurfaceRaycaster::~SurfaceRaycaster() {
    if (scene_) rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
}

void SurfaceRaycaster::build(const Snapshot& s) {
    if (scene_) rtcReleaseScene(scene_);
    scene_ = rtcNewScene(device_);
    triangles_ = s.triangles, cut_face_ = s.cut_face;
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), std::max<size_t>(s.surface.size(), 1)));
    for (size_t i = 0; i < s.surface.size(); ++i)
        for (int k = 0; k < 3; ++k) v[3 * i + k] = static_cast<float>(s.surface[i][k]);
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), s.triangles.size()));
    for (size_t t = 0; t < s.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) idx[3 * t + k] = static_cast<unsigned>(s.triangles[t][k]);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene_);
}

std::optional<SurfaceHit> SurfaceRaycaster::cast(const Ray& ray) const {
    if (!scene_ || triangles_.empty()) return std::nullopt;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray.org_x = static_cast<float>(ray.origin.x()), rh.ray.org_y = static_cast<float>(ray.origin.y());
    rh.ray.org_z = static_cast<float>(ray.origin.z());
    rh.ray.dir_x = static_cast<float>(ray.direction.x()), rh.ray.dir_y = static_cast<float>(ray.direction.y());
    rh.ray.dir_z = static_cast<float>(ray.direction.z());
    rh.ray.tnear = 0.0f, rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.mask = ~0u, rh.ray.flags = 0, rh.ray.time = 0.0f;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    SurfaceHit h;
    h.triangle = static_cast<int>(rh.hit.primID);
    h.point = ray.origin + static_cast<double>(rh.ray.tfar) * ray.direction;
    h.normal = Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z).normalized();
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
