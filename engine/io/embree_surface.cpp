#include "engine/io/embree_surface.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace xcut {

EmbreeSurface::EmbreeSurface() {
    device_ = rtcNewDevice("threads=1");
    if (!device_) throw std::runtime_error("Embree: cannot create a device");
}

EmbreeSurface::~EmbreeSurface() {
    if (scene_) rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
}

void EmbreeSurface::build(const std::vector<Vec3>& positions, const std::vector<std::array<int, 3>>& triangles) {
    if (scene_) rtcReleaseScene(scene_);
    scene_ = rtcNewScene(device_);
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), std::max<size_t>(positions.size(), 1)));
    for (size_t i = 0; i < positions.size(); ++i)
        for (int k = 0; k < 3; ++k) v[3 * i + k] = static_cast<float>(positions[i][k]);
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), triangles.size()));
    for (size_t t = 0; t < triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) idx[3 * t + k] = static_cast<unsigned>(triangles[t][k]);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene_);
}

std::optional<RayHit> EmbreeSurface::intersect(const Vec3& origin, const Vec3& direction) const {
    if (!scene_) return std::nullopt;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray.org_x = static_cast<float>(origin.x()), rh.ray.org_y = static_cast<float>(origin.y());
    rh.ray.org_z = static_cast<float>(origin.z());
    rh.ray.dir_x = static_cast<float>(direction.x()), rh.ray.dir_y = static_cast<float>(direction.y());
    rh.ray.dir_z = static_cast<float>(direction.z());
    rh.ray.tnear = 0.0f, rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.mask = ~0u, rh.ray.flags = 0, rh.ray.time = 0.0f;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    RayHit h;
    h.triangle = static_cast<int>(rh.hit.primID);
    h.distance = rh.ray.tfar;
    h.normal = Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    return h;
}

}  // namespace xcut
