#include "systems/kernels/tool_shape_depth.h"

#include <cmath>
#include <limits>

namespace xcut {
namespace {

/// Unit direction of d, or +z when d is (numerically) zero: a point at the shape's centre.
Vec3 direction(const Vec3& d) {
    const double n = d.norm();
    return n > 1e-15 ? Vec3(d / n) : Vec3(Vec3::UnitZ());
}

Penetration from_core(const Vec3& q, const Vec3& core, double radius) {
    return {radius - (q - core).norm(), direction(q - core)};
}

/// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
    const double denom = 1.0 / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

/// Solid angle of triangle abc seen from p (Van Oosterom & Strackee), signed by orientation.
double solid_angle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 x = a - p, y = b - p, z = c - p;
    const double lx = x.norm(), ly = y.norm(), lz = z.norm();
    const double num = x.dot(y.cross(z));
    const double den = lx * ly * lz + x.dot(y) * lz + y.dot(z) * lx + z.dot(x) * ly;
    return 2.0 * std::atan2(num, den);
}

Penetration mesh_penetration(const ToolShape& s, const Vec3& q) {
    double winding = 0.0, best = std::numeric_limits<double>::max();
    Vec3 nearest = q;
    for (const auto& t : s.triangles) {
        const Vec3 &a = s.vertices[t[0]], &b = s.vertices[t[1]], &c = s.vertices[t[2]];
        winding += solid_angle(q, a, b, c);
        const Vec3 p = closest_on_triangle(q, a, b, c);
        const double d = (p - q).squaredNorm();
        if (d < best) best = d, nearest = p;
    }
    const double depth = std::sqrt(best);
    if (winding / (4.0 * M_PI) <= 0.5) return {-depth, direction(q - nearest)};
    return {depth, direction(nearest - q)};
}

}  // namespace

Penetration penetration(const ToolShape& s, const Vec3& point) {
    const Vec3 q = s.kind == ToolShape::kMesh ? point : Vec3(point - s.centre);
    switch (s.kind) {
        case ToolShape::kSphere: return from_core(q, Vec3::Zero(), s.radius);
        case ToolShape::kCapsule: {
            const double z = std::clamp(q.z(), -0.5 * s.length, 0.5 * s.length);
            return from_core(q, Vec3(0, 0, z), s.radius);
        }
        case ToolShape::kBox: {
            Penetration p{std::numeric_limits<double>::max(), Vec3::UnitZ()};
            for (int k = 0; k < 3; ++k) {
                const double d = s.half_extent[k] - std::abs(q[k]);
                if (d < p.depth) p.depth = d, p.normal = Vec3::Unit(k) * (q[k] >= 0 ? 1.0 : -1.0);
            }
            return p;  // the nearest face's distance: negative (a lower bound) outside
        }
        case ToolShape::kMesh: return mesh_penetration(s, q);
        case ToolShape::kNone: break;
    }
    return {-std::numeric_limits<double>::max(), Vec3::UnitZ()};
}

}  // namespace xcut
