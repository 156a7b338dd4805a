#pragma once
// A triangle surface in an Embree scene, for single rays: the headless render's camera rays
// (engine/io/render.cpp) and the viewer's cursor (tools/viewer/hand_tools.h). Embree 3 works in
// float: positions are rounded to float when built.
#include <embree3/rtcore.h>

#include <array>
#include <optional>
#include <vector>

#include "components/nodes.h"

namespace xcut {

struct RayHit {
    int triangle = -1;
    double distance = 0.0;       ///< along the ray, in units of its direction's length [m]
    Vec3 normal = Vec3::Zero();  ///< the triangle's geometric normal as Embree gives it (not unit)
};

class EmbreeSurface {
public:
    EmbreeSurface();
    ~EmbreeSurface();
    EmbreeSurface(const EmbreeSurface&) = delete;
    EmbreeSurface& operator=(const EmbreeSurface&) = delete;
    /// (Re)builds the scene from the surface.
    void build(const std::vector<Vec3>& positions, const std::vector<std::array<int, 3>>& triangles);
    /// The nearest hit of the ray from `origin` along `direction`; none on a miss or before build().
    std::optional<RayHit> intersect(const Vec3& origin, const Vec3& direction) const;

private:
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
};

}  // namespace xcut
