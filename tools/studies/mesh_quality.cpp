#include "tools/studies/mesh_quality.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace xcut {

double min_dihedral_angle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const Vec3 p[4] = {a, b, c, d};
    Vec3 n[4];  // outward normal of the face opposite vertex k
    for (int k = 0; k < 4; ++k) {
        const Vec3 &u = p[(k + 1) % 4], &v = p[(k + 2) % 4], &w = p[(k + 3) % 4];
        Vec3 m = (v - u).cross(w - u);
        if (m.dot(p[k] - u) > 0.0) m = -m;
        n[k] = m.normalized();
    }
    double smallest = M_PI;
    for (int k = 0; k < 4; ++k)
        for (int l = k + 1; l < 4; ++l)
            smallest = std::min(smallest, M_PI - std::acos(std::clamp(n[k].dot(n[l]), -1.0, 1.0)));
    return smallest;
}

double min_triangle_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
    auto angle = [](const Vec3& o, const Vec3& p, const Vec3& q) {
        return std::acos(std::clamp((p - o).normalized().dot((q - o).normalized()), -1.0, 1.0));
    };
    return std::min({angle(a, b, c), angle(b, c, a), angle(c, a, b)});
}

MeshQuality mesh_quality(const World& w, double threshold_deg) {
    MeshQuality q;
    q.min_volume = q.min_effective_volume = std::numeric_limits<double>::infinity();
    const Elements& el = w.elements;
    const Vec3* X = w.nodes.rest.data();
    for (int e = 0; e < el.count(); ++e) {
        if (!(el.weight[e] > 0.0)) continue;
        const auto& n = el.nodes[e];
        const double angle = (el.dim == 3 ? min_dihedral_angle(X[n[0]], X[n[1]], X[n[2]], X[n[3]])
                                          : min_triangle_angle(X[n[0]], X[n[1]], X[n[2]])) * 180.0 / M_PI;
        ++q.elements;
        q.min_angle_deg = std::min(q.min_angle_deg, angle);
        q.min_volume = std::min(q.min_volume, el.rest_volume[e]);
        q.min_effective_volume = std::min(q.min_effective_volume, el.rest_volume[e] * el.weight[e]);
        if (angle < threshold_deg) ++q.below_threshold;
    }
    return q;
}

}  // namespace xcut
