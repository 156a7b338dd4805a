#include "engine/fragment_geometry.h"

#include <algorithm>
#include <cmath>


namespace xcut {

std::vector<Vec3> clip_to_side(const std::vector<Vec3>& poly, const CutLine& l, bool bit) {
    const double s = bit ? 1.0 : -1.0;
    std::vector<Vec3> out;
    out.reserve(poly.size() + 1);
    for (size_t k = 0; k < poly.size(); ++k) {
        const Vec3& p = poly[k];
        const Vec3& q = poly[(k + 1) % poly.size()];
        const double dp = s * l.normal.dot(p - l.origin), dq = s * l.normal.dot(q - l.origin);
        if (dp >= 0.0) out.push_back(p);
        if ((dp > 0.0 && dq < 0.0) || (dp < 0.0 && dq > 0.0)) out.push_back(p + dp / (dp - dq) * (q - p));
    }
    return out;
}

double polygon_area(const std::vector<Vec3>& poly) {
    double twice = 0.0;
    for (size_t k = 0; k < poly.size(); ++k) {
        const Vec3& p = poly[k];
        const Vec3& q = poly[(k + 1) % poly.size()];
        twice += p.x() * q.y() - q.x() * p.y();
    }
    return 0.5 * std::abs(twice);
}

std::vector<Vec3> fragment_polygon(const std::array<Vec3, 3>& tri, const CutLine* lines, int n, uint32_t mask) {
    std::vector<Vec3> poly(tri.begin(), tri.end());
    for (int k = 0; k < n && poly.size() >= 3; ++k)
        if (mask & bound_by(k)) poly = clip_to_side(poly, lines[k], mask >> k & 1u);
    return poly;
}

std::array<double, 2> segment_part(const Vec3& a, const Vec3& b, const CutLine* lines, int n, uint32_t mask) {
    double s0 = 0.0, s1 = 1.0;
    for (int k = 0; k < n && s0 <= s1; ++k) {  // the interval shrinks line by line (Cyrus & Beck)
        if (!(mask & bound_by(k))) continue;
        const Vec3 normal = (mask >> k & 1u) ? lines[k].normal : Vec3(-lines[k].normal);
        const double at = normal.dot(a - lines[k].origin), slope = normal.dot(b - a);
        if (slope == 0.0) {
            if (at < 0.0) s0 = 1.0, s1 = 0.0;
            continue;
        }
        const double root = -at / slope;
        if (slope > 0.0) s0 = std::max(s0, root);
        else s1 = std::min(s1, root);
    }
    return {s0, s1};
}

std::array<double, 2> segment_in_polygon(const Vec3& a, const Vec3& b, const std::vector<Vec3>& poly) {
    double twice = 0.0;
    for (size_t k = 0; k < poly.size(); ++k)
        twice += poly[k].x() * poly[(k + 1) % poly.size()].y() - poly[(k + 1) % poly.size()].x() * poly[k].y();
    std::vector<CutLine> edges;  // each edge's inner side as a line's side 1
    for (size_t k = 0; k < poly.size(); ++k) {
        const Vec3 d = poly[(k + 1) % poly.size()] - poly[k];
        const Vec3 inward = twice >= 0.0 ? Vec3(-d.y(), d.x(), 0.0) : Vec3(d.y(), -d.x(), 0.0);
        edges.push_back({poly[k], inward});
    }
    if (poly.size() < 3) return {1.0, 0.0};
    const uint32_t all = ~0u;  // every edge bounds it, on its inner side (at most 16 edges)
    return segment_part(a, b, edges.data(), static_cast<int>(std::min<size_t>(edges.size(), kBoundBit)), all);
}

}  // namespace xcut
