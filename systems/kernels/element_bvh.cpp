#include "systems/kernels/element_bvh.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>

#include "engine/error.h"

namespace xcut {

struct ElementBvh::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::vector<RTCBounds> boxes;
    std::vector<Vec3> built_at;   ///< node positions at the last build [m]
    double margin = 0.0;          ///< [m]
};

namespace {

void bounds_callback(const RTCBoundsFunctionArguments* args) {
    const auto* boxes = static_cast<const std::vector<RTCBounds>*>(args->geometryUserPtr);
    *args->bounds_o = (*boxes)[args->primID];
}

struct BallQuery {
    const std::vector<RTCBounds>* boxes;
    std::vector<int>* out;
    float radius;
};

float box_distance2(const RTCBounds& b, float x, float y, float z) {
    const float dx = std::max({b.lower_x - x, 0.0f, x - b.upper_x});
    const float dy = std::max({b.lower_y - y, 0.0f, y - b.upper_y});
    const float dz = std::max({b.lower_z - z, 0.0f, z - b.upper_z});
    return dx * dx + dy * dy + dz * dz;
}

bool ball_callback(RTCPointQueryFunctionArguments* args) {
    auto* q = static_cast<BallQuery*>(args->userPtr);
    const RTCBounds& b = (*q->boxes)[args->primID];
    if (box_distance2(b, args->query->x, args->query->y, args->query->z) <= q->radius * q->radius)
        q->out->push_back(static_cast<int>(args->primID));
    return false;
}

}  // namespace

// The Embree device is made on first use: a scene without tools never pays for it.
ElementBvh::ElementBvh() : impl_(std::make_unique<Impl>()) {}

ElementBvh::~ElementBvh() {
    if (impl_->scene) rtcReleaseScene(impl_->scene);
    if (impl_->device) rtcReleaseDevice(impl_->device);
}

bool ElementBvh::ensure(const MeshView& mesh, double margin) {
    bool valid = impl_->scene != nullptr && impl_->built_at.size() == static_cast<size_t>(mesh.mesh_nodes);
    for (int i = 0; valid && i < mesh.mesh_nodes; ++i)
        valid = ((*mesh.position)[i] - impl_->built_at[i]).squaredNorm() <= impl_->margin * impl_->margin;
    if (valid) return false;
    build(mesh, margin);
    return true;
}

void ElementBvh::build(const MeshView& mesh, double margin) {
    const std::vector<Vec3>& x = *mesh.position;
    impl_->margin = margin;
    impl_->built_at.assign(x.begin(), x.begin() + mesh.mesh_nodes);
    const Elements& el = *mesh.elements;
    const int npe = el.nodes_per_element();
    impl_->boxes.resize(mesh.mesh_elements);
    for (int e = 0; e < mesh.mesh_elements; ++e) {
        Vec3 lo = x[el.nodes[e][0]], hi = lo;
        for (int a = 1; a < npe; ++a) {
            lo = lo.cwiseMin(x[el.nodes[e][a]]);
            hi = hi.cwiseMax(x[el.nodes[e][a]]);
        }
        const double pad = margin + 1e-5 * (hi - lo).norm() + 1e-12;
        RTCBounds& b = impl_->boxes[e];
        b.lower_x = static_cast<float>(lo.x() - pad), b.lower_y = static_cast<float>(lo.y() - pad);
        b.lower_z = static_cast<float>(lo.z() - pad);
        b.upper_x = static_cast<float>(hi.x() + pad), b.upper_y = static_cast<float>(hi.y() + pad);
        b.upper_z = static_cast<float>(hi.z() + pad);
    }
    if (!impl_->device) impl_->device = rtcNewDevice("threads=1");
    if (!impl_->device) throw std::runtime_error("Embree: cannot create a device");
    if (impl_->scene) rtcReleaseScene(impl_->scene);
    impl_->scene = rtcNewScene(impl_->device);
    RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geom, static_cast<unsigned>(impl_->boxes.size()));
    rtcSetGeometryUserData(geom, &impl_->boxes);
    rtcSetGeometryBoundsFunction(geom, bounds_callback, &impl_->boxes);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(impl_->scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(impl_->scene);
}

void ElementBvh::query_ball(const Vec3& centre, double radius, std::vector<int>& out) const {
    if (!impl_->scene) return;
    RTCPointQuery q;
    q.x = static_cast<float>(centre.x()), q.y = static_cast<float>(centre.y()), q.z = static_cast<float>(centre.z());
    q.time = 0.0f;
    q.radius = static_cast<float>(radius * (1.0 + 1e-5) + 1e-12);
    RTCPointQueryContext ctx;
    rtcInitPointQueryContext(&ctx);
    BallQuery data{&impl_->boxes, &out, q.radius};
    rtcPointQuery(impl_->scene, &q, &ctx, ball_callback, &data);
}

}  // namespace xcut
