#include "engine/io/tool_meshes.h"

#include <algorithm>
#include <cmath>

namespace xcut {
namespace {

/// A UV sphere of `radius` about `centre`, its axis along z; `stretch` > 0 pulls the upper half up
/// and the lower half down by that much (a capsule).
void add_sphere(ToolTriangles& t, const Vec3& centre, double radius, double stretch, const Mat3& R, const Vec3& p) {
    constexpr int kRings = 10, kSegments = 16;
    const int base = static_cast<int>(t.position.size());
    for (int i = 0; i <= kRings; ++i) {
        const double theta = M_PI * i / kRings;
        for (int j = 0; j < kSegments; ++j) {
            const double phi = 2.0 * M_PI * j / kSegments;
            Vec3 q = centre + radius * Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
            q.z() += (i <= kRings / 2 ? 0.5 : -0.5) * stretch;
            t.position.push_back(p + R * q);
        }
    }
    for (int i = 0; i < kRings; ++i)
        for (int j = 0; j < kSegments; ++j) {
            const int a = base + i * kSegments + j, b = base + i * kSegments + (j + 1) % kSegments;
            const int c = a + kSegments, d = b + kSegments;
            t.triangles.push_back({a, c, b}), t.triangles.push_back({b, c, d});
            t.blade.push_back(0), t.blade.push_back(0);
        }
}

void add_box(ToolTriangles& t, const Vec3& centre, const Vec3& half, const Mat3& R, const Vec3& p) {
    const int base = static_cast<int>(t.position.size());
    for (int k = 0; k < 8; ++k)
        t.position.push_back(p + R * (centre + Vec3(k & 1 ? half.x() : -half.x(), k & 2 ? half.y() : -half.y(),
                                                    k & 4 ? half.z() : -half.z())));
    static constexpr int kFaces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : kFaces) {
        t.triangles.push_back({base + f[0], base + f[1], base + f[2]});
        t.triangles.push_back({base + f[0], base + f[2], base + f[3]});
        t.blade.push_back(0), t.blade.push_back(0);
    }
}

}  // namespace

ToolTriangles tool_triangles(const ToolBodies& tools, double size) {
    ToolTriangles t;
    for (int i = 0; i < tools.count(); ++i) {
        const Mat3 R = tools.orientation[i].normalized().toRotationMatrix();
        const Vec3& p = tools.position[i];
        const ToolShape& s = tools.shape[i];
        if (s.kind == ToolShape::kSphere) add_sphere(t, s.centre, s.radius, 0.0, R, p);
        if (s.kind == ToolShape::kCapsule) add_sphere(t, s.centre, s.radius, s.length, R, p);
        if (s.kind == ToolShape::kBox) add_box(t, s.centre, s.half_extent, R, p);
        if (s.kind == ToolShape::kMesh) {
            const int base = static_cast<int>(t.position.size());
            for (const Vec3& v : s.vertices) t.position.push_back(p + R * v);
            for (const auto& tri : s.triangles) {
                t.triangles.push_back({base + tri[0], base + tri[1], base + tri[2]});
                t.blade.push_back(0);
            }
        }
        const bool faced = tools.has_blade[i] && i < static_cast<int>(tools.blade_back.size());
        const Vec3 face = faced ? Vec3(R * tools.blade_back[i]) : Vec3::Zero();
        if (face != Vec3::Zero()) {  // the blade's own face: tip, heel, heel + back, tip + back
            const Vec3 tip = p + R * tools.blade_tip[i], heel = p + R * tools.blade_heel[i];
            const int base = static_cast<int>(t.position.size());
            for (const Vec3& v : {tip, heel, Vec3(heel + face), Vec3(tip + face)}) t.position.push_back(v);
            t.triangles.push_back({base, base + 1, base + 2});
            t.triangles.push_back({base, base + 2, base + 3});
            t.blade.push_back(1), t.blade.push_back(1);
        } else if (tools.has_blade[i]) {  // the edge, and a back behind it: against the blade's motion (else the tool's -x)
            const Vec3 tip = p + R * tools.blade_tip[i], heel = p + R * tools.blade_heel[i];
            const Vec3 edge = (heel - tip).normalized();
            Vec3 ahead = i < static_cast<int>(tools.velocity.size()) ? tools.velocity[i] : Vec3::Zero();
            ahead -= ahead.dot(edge) * edge;
            if (!(ahead.norm() > 1e-9)) ahead = R * Vec3::UnitX() - (R * Vec3::UnitX()).dot(edge) * edge;
            const double back = std::max(0.2 * (heel - tip).norm(), size);
            const int base = static_cast<int>(t.position.size());
            t.position.push_back(tip), t.position.push_back(heel), t.position.push_back(heel - back * ahead.normalized());
            t.triangles.push_back({base, base + 1, base + 2});
            t.blade.push_back(1);
        }
    }
    return t;
}

}  // namespace xcut
