#include "tools/studies/bridges.h"

#include <algorithm>
#include <numeric>

#include "engine/fragment_geometry.h"
#include "engine/trajectory.h"
#include "systems/cut/recut.h"
#include "systems/kernels/blade_pose.h"
#include "systems/kernels/mesh_measures.h"

namespace xcut {
namespace {

using Corners = std::array<Vec3, 4>;
using Region = BridgeCheck::Region;

/// Distance from p to triangle (a, b, c) [m]: its closest point by the triangle's Voronoi regions
/// (Ericson 2005, "Real-Time Collision Detection", §5.1.5). The triangle has area.
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0.0 && d2 <= 0.0) return ap.norm();
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0.0 && d4 <= d3) return bp.norm();
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0.0 && d5 <= d6) return cp.norm();
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
    const double den = 1.0 / (va + vb + vc);
    return (p - (a + ab * (vb * den) + ac * (vc * den))).norm();
}

/// Where segment p0 -> p1 meets triangle t (its plane between the ends or through one, the point
/// inside the triangle or on its border within `grow` of its barycentric coordinates: the pieces of
/// one sweep meet edge to edge, carried by maps of two steps a few micrometres apart), if it does.
std::optional<Vec3> segment_crosses(const Vec3& p0, const Vec3& p1, const std::array<Vec3, 3>& t, double grow) {
    const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
    const double s0 = n.dot(p0 - t[0]), s1 = n.dot(p1 - t[0]);
    if ((s0 > 0.0 && s1 > 0.0) || (s0 < 0.0 && s1 < 0.0) || s0 == s1) return std::nullopt;
    const Vec3 q = p0 + s0 / (s0 - s1) * (p1 - p0);
    const double nn = n.squaredNorm();
    for (int k = 0; k < 3; ++k)  // q's barycentric coordinate opposite corner k
        if (n.dot((t[(k + 1) % 3] - q).cross(t[(k + 2) % 3] - q)) / nn < -grow) return std::nullopt;
    return q;
}

/// Whether segment p0 -> p1 comes within `margin` of tetrahedron X (of the tetrahedron grown by
/// moving each face plane out by `margin`: a little more than that near its corners) [m].
bool segment_near(const Vec3& p0, const Vec3& p1, const Corners& X, double margin) {
    double lo = 0.0, hi = 1.0;
    for (int a = 0; a < 4; ++a) {
        const Vec3 &b = X[(a + 1) % 4], &c = X[(a + 2) % 4], &d = X[(a + 3) % 4];
        Vec3 n = (c - b).cross(d - b).normalized();
        if (n.dot(X[a] - b) < 0.0) n = -n;  // toward corner a: inside
        const double f0 = n.dot(p0 - b) + margin, f1 = n.dot(p1 - b) + margin;  // >= 0: within
        if (f0 < 0.0 && f1 < 0.0) return false;
        if (f0 < 0.0) lo = std::max(lo, f0 / (f0 - f1));
        if (f1 < 0.0) hi = std::min(hi, f0 / (f0 - f1));
    }
    return lo <= hi;
}

/// The affine map of an element from its corners now (x) to its rest corners (X): A, with
/// rest = X[0] + A (p - x[0]). False if the element is flat or inverted now.
bool rest_map(const Corners& x, const Corners& X, Mat3& A) {
    Mat3 Ds, Dm;
    for (int k = 0; k < 3; ++k) Ds.col(k) = x[k + 1] - x[0], Dm.col(k) = X[k + 1] - X[0];
    if (!(Ds.determinant() / Dm.determinant() > 1e-3)) return false;
    A = Dm * Ds.inverse();
    return true;
}

/// One map of a mesh element's material into its rest frame: the whole element's (uncut), or one
/// fragment's and where that fragment lies.
struct RestMap {
    Vec3 x0, X0;
    Mat3 A;
    Region region;
    Vec3 operator()(const Vec3& p) const { return X0 + A * (p - x0); }
};

Corners positions(const World& w, int element) {
    Corners x;
    for (int a = 0; a < 4; ++a) x[a] = w.nodes.position[w.elements.nodes[element][a]];
    return x;
}

/// Mesh element e's maps now: its own while uncut, one per fragment once cut (a fragment moves
/// with its own node copies). Empty if one is flat or inverted.
std::vector<RestMap> rest_maps(const World& w, int e) {
    const Corners X = tet_corners(w, e);
    const int c = w.cuts.cut_of_element[e];
    std::vector<std::pair<int, Region>> parts;  // force element, region
    if (c < 0) {
        parts.push_back({e, {}});
    } else if (w.cuts.lines[c].empty()) {
        const CutLine l = first_cut_line(w, c);
        parts.push_back({w.virtual_elements.element[w.cuts.virtual_element[c][0]], {{{l, true}}, {l}}});
        parts.push_back({w.virtual_elements.element[w.cuts.virtual_element[c][1]], {{{l, false}}, {l}}});
    } else {
        const auto& lines = w.cuts.lines[c];
        for (int v : w.cuts.fragments[c]) {
            Region r{{}, lines};
            const uint32_t mask = w.virtual_elements.mask[v];
            for (int k = 0; k < static_cast<int>(lines.size()); ++k)
                if (mask & bound_by(k)) r.bounds.push_back({lines[k], (mask >> k & 1u) != 0});
            parts.push_back({w.virtual_elements.element[v], r});
        }
    }
    std::vector<Corners> at;  // each part's corners now
    for (const auto& part : parts) at.push_back(positions(w, part.first));
    double open = 0.0;  // the most two copies of one corner lie apart
    for (const Corners& f : at)
        for (const Corners& g : at)
            for (int a = 0; a < 4; ++a) open = std::max(open, (f[a] - g[a]).norm());
    std::vector<RestMap> maps;
    for (size_t k = 0; k < parts.size(); ++k) {
        Region& region = parts[k].second;
        const Corners& x = at[k];
        region.open = open;
        RestMap m{x[0], X[0], Mat3::Identity(), std::move(region)};
        if (!rest_map(x, X, m.A)) return {};
        maps.push_back(std::move(m));
    }
    return maps;
}

bool in_region(const Region& r, const Vec3& q, double tol) {
    for (const auto& [l, bit] : r.bounds)
        if ((bit ? 1.0 : -1.0) * l.normal.dot(q - l.origin) < -tol) return false;
    for (const CutLine& l : r.cuts)
        if (std::abs(l.normal.dot(q - l.origin)) <= r.open + tol) return false;
    return true;
}

double shortest_edge(const Corners& X) {
    double h = 1e300;
    for (const auto& ed : kTetEdges) h = std::min(h, (X[ed[1]] - X[ed[0]]).norm());
    return h;
}

/// Blade i's edge (tip, heel) at time t on its trajectory [m].
std::array<Vec3, 2> edge_at(const ToolBodies& tb, int i, double t) {
    std::array<Vec3, 2> e;
    blade_at(tb, i, sample_trajectory(tb.trajectory[i], t), e[0], e[1]);
    return e;
}

bool traced(const ToolBodies& tb, int i) {
    return i < static_cast<int>(tb.has_blade.size()) && tb.has_blade[i] && !tb.trajectory[i].empty();
}

/// Mesh elements whose box now comes within `grow` of the box of `points` [m].
std::vector<int> elements_near(const World& w, const std::vector<Vec3>& points, double grow) {
    Eigen::AlignedBox3d box;
    for (const Vec3& p : points) box.extend(p);
    box.min().array() -= grow, box.max().array() += grow;
    std::vector<int> near;
    for (int e = 0; e < w.mesh_elements; ++e) {
        Eigen::AlignedBox3d eb;
        for (int a = 0; a < 4; ++a) eb.extend(w.nodes.position[w.elements.nodes[e][a]]);
        if (eb.intersects(box)) near.push_back(e);
    }
    return near;
}

constexpr double kNear = 1e-3;  ///< elements whose box comes this close to a blade's sweep's are traced [m]

/// Each mesh element's centroid travel since `last` (its mesh nodes' positions then) [m].
std::vector<Vec3> centroid_travel(const World& w, const std::vector<Vec3>& last) {
    std::vector<Vec3> d(w.mesh_elements, Vec3::Zero());
    for (int e = 0; e < w.mesh_elements; ++e)
        for (int a = 0; a < 4; ++a) {
            const int n = w.elements.nodes[e][a];
            d[e] += 0.25 * (w.nodes.position[n] - last[n]);
        }
    return d;
}

}  // namespace

void BridgeCheck::before_step(const World& w) {
    if (w.elements.dim != 3 || w.quadratic.count() > 0) return;
    if (started_) drift_.push_back(centroid_travel(w, last_));
    else mean_edge_ = mean_edge_length(w.elements, w.nodes.rest, w.mesh_elements);
    last_.assign(w.nodes.position.begin(), w.nodes.position.begin() + w.mesh_nodes);
    const int step = static_cast<int>(drift_.size());
    const ToolBodies& tb = w.tools;
    for (int i = 0; i < tb.count(); ++i) {
        if (!traced(tb, i)) continue;
        std::vector<std::array<Vec3, 2>> edge;
        std::vector<Vec3> points;
        for (int s = 0; s <= kSweepSamples; ++s) {
            edge.push_back(edge_at(tb, i, w.time + w.solver.dt * s / kSweepSamples));
            points.insert(points.end(), {edge.back()[0], edge.back()[1]});
        }
        const double travel = std::max((edge.back()[0] - edge[0][0]).norm(), (edge.back()[1] - edge[0][1]).norm());
        const int window = static_cast<int>(std::min(1e3, std::ceil(mean_edge_ / std::max(travel, 1e-12))));
        const double back = tb.blade_back.size() > static_cast<size_t>(i) ? tb.blade_back[i].norm() : 0.0;
        if (back > 0.0)  // the face reaches past the edge: its box too
            for (const auto& ed : edge) points.insert(points.end(), {ed[0] + back * Vec3::Ones(), ed[0] - back * Vec3::Ones()});
        for (int e : elements_near(w, points, kNear)) {
            Seen& s = seen_[e];
            s.left_out = s.left_out || back > 0.0;
            if (s.left_out) continue;
            const std::vector<RestMap> maps = rest_maps(w, e);
            if (maps.empty()) {
                s.left_out = true;
                continue;
            }
            if (travel > 0.0) s.end[i].clear();
            for (const RestMap& m : maps) {
                const auto rim = [&](const Vec3& p, const Vec3& q) { return Rim{{m(p), m(q)}, {step, window, (q - p).normalized()}}; };
                if (!started_) s.rim.push_back(rim(edge[0][0], edge[0][1]));  // where the blade began
                if (travel > 0.0) s.end[i].push_back(rim(edge.back()[0], edge.back()[1]));
                for (int k = 1; k <= kSweepSamples; ++k) {
                    const std::array<Vec3, 2> &p = edge[k - 1], &q = edge[k];
                    s.rim.push_back(rim(p[0], q[0]));
                    s.rim.push_back(rim(p[1], q[1]));
                    for (const std::array<Vec3, 3>& tri : {std::array<Vec3, 3>{p[0], p[1], q[1]}, std::array<Vec3, 3>{p[0], q[1], q[0]}}) {
                        const Vec3 n = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
                        if (n.norm() > 1e-18)
                            s.sweep.push_back({{m(tri[0]), m(tri[1]), m(tri[2])}, static_cast<int>(s.regions.size()), {step, window, n.normalized()}});
                    }
                }
                s.regions.push_back(m.region);
            }
        }
    }
    started_ = true;
}

namespace {

/// The lattice a tetrahedron is flood-filled on: kLattice steps along each edge.
constexpr int kLattice = 12;

/// Which part of tetrahedron X the sweep `s` leaves each corner in (equal: one part): a flood fill
/// of the lattice of points X0 + (i X01 + j X02 + k X03) / kLattice, i + j + k <= kLattice, whose
/// neighbours along an edge direction are joined unless the segment between them crosses a piece
/// (in its region, within `tol` of it). A folded sweep (a blade that turned inside the element)
/// crossed twice leaves a corner where it was.
std::array<int, 4> parts_of_corners(const Corners& X, const BridgeCheck::Seen& s, const std::vector<double>& tol) {
    constexpr int n = kLattice;
    const auto index = [](int i, int j, int k) { return (i * (n + 1) + j) * (n + 1) + k; };
    std::vector<int> parent((n + 1) * (n + 1) * (n + 1));
    std::iota(parent.begin(), parent.end(), 0);
    const auto root = [&](int a) {
        while (parent[a] != a) a = parent[a] = parent[parent[a]];
        return a;
    };
    const auto at = [&](int i, int j, int k) { return Vec3(X[0] + (i * (X[1] - X[0]) + j * (X[2] - X[0]) + k * (X[3] - X[0])) / n); };
    for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j)
            for (int k = 0; i + j + k <= n; ++k) {
                const Vec3 p = at(i, j, k);
                for (const std::array<int, 3>& d : {std::array<int, 3>{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}) {
                    if (i + j + k == n) break;
                    const Vec3 q = at(i + d[0], j + d[1], k + d[2]);
                    bool cut = false;
                    for (size_t m = 0; m < s.sweep.size() && !cut; ++m) {
                        const std::optional<Vec3> x = segment_crosses(p, q, s.sweep[m].tri, 2e-3);
                        cut = x && in_region(s.regions[s.sweep[m].region], *x, tol[m]);
                    }
                    if (!cut) parent[root(index(i, j, k))] = root(index(i + d[0], j + d[1], k + d[2]));
                }
            }
    return {root(index(0, 0, 0)), root(index(n, 0, 0)), root(index(0, n, 0)), root(index(0, 0, n))};
}

/// How far element e moved from `taken.step` within its window, the most over the window's ends:
/// along `taken.direction` (normal: off a piece) or across it (off a segment) [m].
double shift(const std::vector<std::vector<Vec3>>& drift, int e, const BridgeCheck::Taken& taken, bool normal) {
    Vec3 sum = Vec3::Zero();
    double most = 0.0;
    const int end = std::min(static_cast<int>(drift.size()), taken.step + taken.window);
    for (int j = taken.step; j < end; ++j) {
        sum += drift[j][e];
        const double along = sum.dot(taken.direction);
        most = std::max(most, normal ? std::abs(along) : (sum - along * taken.direction).norm());
    }
    return most;
}

}  // namespace

BridgeTally BridgeCheck::tally(const World& w) const {
    BridgeTally out;
    if (w.elements.dim != 3 || !started_) return out;
    const bool recut = recut_allowed(w);
    std::vector<std::vector<Vec3>> drift = drift_;
    drift.push_back(centroid_travel(w, last_));
    for (const auto& [e, s] : seen_) {
        if (s.left_out) {
            ++out.left_out;
            continue;
        }
        if (s.sweep.empty()) continue;
        const Corners X = tet_corners(w, e);
        const double h = shortest_edge(X);
        const auto near = [&](const Rim& r) { return segment_near(r.seg[0], r.seg[1], X, 0.1 * h + shift(drift, e, r.taken, false)); };
        if (std::any_of(s.rim.begin(), s.rim.end(), near)) continue;
        if (std::any_of(s.end.begin(), s.end.end(), [&](const auto& b) { return std::any_of(b.second.begin(), b.second.end(), near); }))
            continue;
        std::array<bool, 4> clear;  // farther from each piece than its tolerance
        std::vector<double> tol;
        for (const Piece& p : s.sweep) tol.push_back(0.02 * h + shift(drift, e, p.taken, true));
        for (int a = 0; a < 4; ++a) {
            clear[a] = true;
            for (size_t k = 0; k < s.sweep.size() && clear[a]; ++k)
                clear[a] = point_triangle_distance(X[a], s.sweep[k].tri[0], s.sweep[k].tri[1], s.sweep[k].tri[2]) >= tol[k];
        }
        if (std::count(clear.begin(), clear.end(), true) < 2) continue;
        const std::array<int, 4> part = parts_of_corners(X, s, tol);
        bool crossed = false, bridged = false;
        for (const auto& ed : kTetEdges) {
            const int a = ed[0], b = ed[1];
            if (!clear[a] || !clear[b] || part[a] == part[b]) continue;
            crossed = true;
            bridged = bridged || !(recut ? nodes_apart(w, e, a, b) : w.cuts.cut_of_element[e] >= 0);
        }
        out.crossed += crossed;
        out.bridged += bridged;
    }
    return out;
}

bool nodes_apart(const World& w, int e, int a, int b) {
    const int c = w.cuts.cut_of_element[e];
    if (c < 0) return false;
    const Corners X = tet_corners(w, e);
    if (!w.cuts.lines[c].empty()) {
        const auto& lines = w.cuts.lines[c];
        for (int v : w.cuts.fragments[c]) {
            const uint32_t mask = w.virtual_elements.mask[v];
            const int n = static_cast<int>(lines.size());
            if (in_fragment(lines.data(), n, mask, X[a]) && in_fragment(lines.data(), n, mask, X[b])) return false;
        }
        return true;
    }
    // Cut once: the corners joined by edges the cut does not split lie on one side.
    std::array<int, 4> group;
    std::iota(group.begin(), group.end(), 0);
    const auto root = [&](int k) {
        while (group[k] != k) k = group[k];
        return k;
    };
    for (int k = 0; k < 6; ++k) {
        const auto& pe = w.cuts.point_edge[c];
        if (std::find(pe.begin(), pe.end(), k) != pe.end()) continue;
        group[root(kTetEdges[k][0])] = root(kTetEdges[k][1]);
    }
    return root(a) != root(b);
}

}  // namespace xcut
