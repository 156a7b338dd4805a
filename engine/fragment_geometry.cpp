#include "engine/fragment_geometry.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>


namespace xcut {

int clip_to_side(const Vec3* poly, int n, const CutLine& l, bool bit, Vec3* out, int room) {
    const double s = bit ? 1.0 : -1.0;
    int m = 0;
    const auto put = [&](const Vec3& x) {
        if (m == room) throw std::length_error("clip_to_side: the clipped polygon outgrew its room");
        out[m++] = x;
    };
    for (int k = 0; k < n; ++k) {
        const Vec3& p = poly[k];
        const Vec3& q = poly[(k + 1) % n];
        const double dp = s * l.normal.dot(p - l.origin), dq = s * l.normal.dot(q - l.origin);
        if (dp >= 0.0) put(p);
        if ((dp > 0.0 && dq < 0.0) || (dp < 0.0 && dq > 0.0)) put(p + dp / (dp - dq) * (q - p));
    }
    return m;
}

std::vector<Vec3> clip_to_side(const std::vector<Vec3>& poly, const CutLine& l, bool bit) {
    std::vector<Vec3> out(2 * poly.size());  // each vertex gives at most itself and one crossing
    out.resize(clip_to_side(poly.data(), static_cast<int>(poly.size()), l, bit, out.data(), static_cast<int>(out.size())));
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
    return clip_by_planes({tri.begin(), tri.end()}, lines, n, mask);
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

namespace xcut {

double polygon_area_3d(const Vec3* poly, int count) {
    Vec3 n = Vec3::Zero();
    for (int k = 0; k < count; ++k) n += poly[k].cross(poly[(k + 1) % count]);
    return 0.5 * n.norm();
}

double polygon_area_3d(const std::vector<Vec3>& poly) { return polygon_area_3d(poly.data(), static_cast<int>(poly.size())); }

std::vector<Vec3> clip_by_planes(std::vector<Vec3> poly, const CutLine* planes, int n, uint32_t mask) {
    for (int k = 0; k < n && poly.size() >= 3; ++k)
        if (mask & bound_by(k)) poly = clip_to_side(poly, planes[k], mask >> k & 1u);
    return poly;
}

namespace {

/// Room for a face of a fragment as it is clipped: a square (4) clipped by the tetrahedron's faces
/// and by every plane, each clip of a convex polygon adding at most one vertex, with room to spare
/// for round-off near a vertex (clip_to_side says if it is ever outgrown).
constexpr int kFaceRoom = 64;

/// A polygon held in place while it is clipped (fragment_faces clips dozens per fragment).
struct ClipBuffer {
    std::array<Vec3, kFaceRoom> v;
    int n = 0;
    void clip(const CutLine& l, bool bit) {
        std::array<Vec3, kFaceRoom> out;
        n = clip_to_side(v.data(), n, l, bit, out.data(), kFaceRoom);
        std::copy(out.begin(), out.begin() + n, v.begin());
    }
};

/// Each face of fragment_faces, in its order, to emit(vertices, count, outward normal, plane):
/// the same values, without a vector per clip.
template <class Emit>
void each_fragment_face(const std::array<Vec3, 4>& X, const CutLine* planes, int n, uint32_t mask, Emit emit) {
    // The tetrahedron's faces as half-spaces: face a (opposite corner a), its normal toward a.
    std::array<CutLine, 4> inside;
    double size = 0.0;
    for (int a = 0; a < 4; ++a) {
        const Vec3 &p = X[(a + 1) % 4], &q = X[(a + 2) % 4], &r = X[(a + 3) % 4];
        Vec3 normal = (q - p).cross(r - p).normalized();
        if (normal.dot(X[a] - p) < 0.0) normal = -normal;
        inside[a] = {p, normal};
        for (int b = a + 1; b < 4; ++b) size = std::max(size, (X[b] - X[a]).norm());
    }
    ClipBuffer poly;
    for (int a = 0; a < 4; ++a) {  // the tetrahedron's faces, wound outward, clipped by the planes
        poly.v[0] = X[(a + 1) % 4], poly.v[1] = X[(a + 2) % 4], poly.v[2] = X[(a + 3) % 4], poly.n = 3;
        if ((poly.v[1] - poly.v[0]).cross(poly.v[2] - poly.v[0]).dot(inside[a].normal) > 0.0) std::swap(poly.v[1], poly.v[2]);
        for (int k = 0; k < n && poly.n >= 3; ++k)
            if (mask & bound_by(k)) poly.clip(planes[k], mask >> k & 1u);
        if (poly.n >= 3 && polygon_area_3d(poly.v.data(), poly.n) > 0.0) emit(poly.v.data(), poly.n, Vec3(-inside[a].normal), -1 - a);
    }
    const Vec3 centroid = 0.25 * (X[0] + X[1] + X[2] + X[3]);
    for (int k = 0; k < n; ++k) {  // each bounding plane: a square on it round the tetrahedron, clipped
        if (!(mask & bound_by(k))) continue;
        const Vec3 out = (mask >> k & 1u) ? Vec3(-planes[k].normal) : planes[k].normal;
        const Vec3 c = centroid - out.dot(centroid - planes[k].origin) * out;
        const Vec3 u = out.unitOrthogonal(), v = out.cross(u);  // u x v = out: counter-clockwise from outside
        poly.v[0] = c + 4.0 * size * u, poly.v[1] = c + 4.0 * size * v, poly.v[2] = c - 4.0 * size * u;
        poly.v[3] = c - 4.0 * size * v, poly.n = 4;
        for (int a = 0; a < 4 && poly.n >= 3; ++a) poly.clip(inside[a], true);
        for (int m = 0; m < n && poly.n >= 3; ++m)
            if (m != k && (mask & bound_by(m))) poly.clip(planes[m], mask >> m & 1u);
        if (poly.n >= 3 && polygon_area_3d(poly.v.data(), poly.n) > 0.0) emit(poly.v.data(), poly.n, out, k);
    }
}

}  // namespace

std::vector<FragmentFace> fragment_faces(const std::array<Vec3, 4>& X, const CutLine* planes, int n, uint32_t mask) {
    std::vector<FragmentFace> faces;
    each_fragment_face(X, planes, n, mask, [&](const Vec3* v, int count, const Vec3& normal, int plane) {
        faces.push_back({std::vector<Vec3>(v, v + count), normal, plane});
    });
    return faces;
}

double fragment_volume(const std::array<Vec3, 4>& X, const CutLine* planes, int n, uint32_t mask) {
    // polyhedron_volume's sum, face by face as they are made (o: the first face's first vertex).
    Vec3 o = Vec3::Zero();
    bool first = true;
    double volume = 0.0;
    each_fragment_face(X, planes, n, mask, [&](const Vec3* v, int count, const Vec3& normal, int) {
        if (first) o = v[0], first = false;
        volume += polygon_area_3d(v, count) * normal.dot(v[0] - o);
    });
    return first ? 0.0 : std::max(volume / 3.0, 0.0);
}

Eigen::Vector4d tet_barycentric(const std::array<Vec3, 4>& X, const Vec3& x) {
    Eigen::Matrix3d D;
    D << X[1] - X[0], X[2] - X[0], X[3] - X[0];
    const Vec3 l = D.partialPivLu().solve(x - X[0]);
    return {1.0 - l.sum(), l.x(), l.y(), l.z()};
}

double polyhedron_volume(const std::vector<FragmentFace>& faces) {
    if (faces.empty()) return 0.0;
    const Vec3 o = faces[0].polygon[0];
    double v = 0.0;
    for (const FragmentFace& f : faces) v += polygon_area_3d(f.polygon) * f.normal.dot(f.polygon[0] - o);
    return std::max(v / 3.0, 0.0);
}

}  // namespace xcut
