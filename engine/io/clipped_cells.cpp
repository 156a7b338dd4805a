#include "engine/io/clipped_cells.h"

#include <Eigen/Dense>
#include <algorithm>

#include "engine/fragment_geometry.h"
#include "engine/quadratic_setup.h"
#include "engine/tet10_shapes.h"

namespace xcut {

namespace {

/// The force element a cell is cut from, and what places its points: its own nodes (linear), or
/// its quadratic entry's 10 nodes. `made`: the points made for it, with their barycentric
/// coordinates in it (its nodes' are the unit vectors).
struct Source {
    int element = -1;
    const std::array<int, 10>* quadratic = nullptr;
    std::vector<std::pair<int, Eigen::Vector4d>> made;
};

Source source_of(const World& w, int e) {
    Source s;
    s.element = e;
    const int t = quadratic_entry(w, e);
    if (t >= 0) s.quadratic = &w.quadratic.nodes[t];
    return s;
}

/// sum_a N_a(L) f_a over the source's nodes: linear (N_a = L_a) or quadratic shape functions.
Vec3 interpolate(const World& w, const Source& s, const std::vector<Vec3>& f, const Eigen::Vector4d& L) {
    if (s.quadratic) return tet10_point(*s.quadratic, L, f.data());
    const auto& v = w.elements.nodes[s.element];
    Vec3 p = Vec3::Zero();
    for (int a = 0; a < w.elements.nodes_per_element(); ++a)
        if (L[a] != 0.0) p += L[a] * f[v[a]];
    return p;
}

/// Appends a point of source s at barycentric coordinates L, resting at X [m].
int add_point(ClippedCells& out, const World& w, Source& s, const Eigen::Vector4d& L, const Vec3& X) {
    out.position.push_back(interpolate(w, s, w.nodes.position, L));
    out.rest.push_back(X);
    out.velocity.push_back(interpolate(w, s, w.nodes.velocity, L));
    const int p = static_cast<int>(out.position.size()) - 1;
    s.made.push_back({p, L});
    return p;
}

/// Appends a cut point of source s on local edge (i, j) at rest position X.
int add_cut_point(ClippedCells& out, const World& w, Source& s, int i, int j, const Vec3& X) {
    const auto& v = w.elements.nodes[s.element];
    const Vec3 Xi = w.nodes.rest[v[i]], Xj = w.nodes.rest[v[j]];
    const double len2 = (Xj - Xi).squaredNorm();
    const double t = len2 > 0.0 ? std::clamp((X - Xi).dot(Xj - Xi) / len2, 0.0, 1.0) : 0.5;
    Eigen::Vector4d L = Eigen::Vector4d::Zero();
    L[i] = 1.0 - t, L[j] = t;
    return add_point(out, w, s, L, X);
}

/// Barycentric coordinates in source s of point p (one of its nodes, or one made for it).
Eigen::Vector4d coordinates_of(const World& w, const Source& s, int p) {
    const auto& v = w.elements.nodes[s.element];
    for (int a = 0; a < w.elements.nodes_per_element(); ++a)
        if (v[a] == p) return Eigen::Vector4d::Unit(a);
    for (const auto& [q, L] : s.made)
        if (q == p) return L;
    return Eigen::Vector4d::Constant(0.25);  // not reached: every corner is a node or a made point
}

/// Gives the cells [first, end) of a quadratic source their mid-edge points (an edge two cells
/// share gets one point); a linear source's cells stay linear.
void add_edge_points(ClippedCells& out, const World& w, Source& s, size_t first) {
    out.quadratic.resize(out.cells.size(), -1);
    if (!s.quadratic) return;
    const auto& v = w.elements.nodes[s.element];
    std::vector<std::pair<std::pair<int, int>, int>> made;
    const int npe = w.elements.nodes_per_element(), edges = w.quadratic.edge_count();
    for (size_t c = first; c < out.cells.size(); ++c) {
        std::array<int, 6> mid{};
        for (int k = 0; k < edges; ++k) {
            const int a = out.cells[c][kTet10Edges[k][0]], b = out.cells[c][kTet10Edges[k][1]];
            const std::pair<int, int> key(std::min(a, b), std::max(a, b));
            const auto it = std::find_if(made.begin(), made.end(), [&](const auto& m) { return m.first == key; });
            if (it != made.end()) {
                mid[k] = it->second;
                continue;
            }
            const Eigen::Vector4d L = 0.5 * (coordinates_of(w, s, a) + coordinates_of(w, s, b));
            Vec3 X = Vec3::Zero();
            for (int i = 0; i < npe; ++i) X += L[i] * w.nodes.rest[v[i]];
            mid[k] = add_point(out, w, s, L, X);
            made.push_back({key, mid[k]});
        }
        out.quadratic[c] = static_cast<int>(out.edge_points.size());
        out.edge_points.push_back(mid);
    }
}

double signed_measure(const ClippedCells& out, const std::array<int, 4>& c, int dim) {
    const Vec3 a = out.position[c[1]] - out.position[c[0]], b = out.position[c[2]] - out.position[c[0]];
    if (dim == 2) return a.x() * b.y() - a.y() * b.x();
    return a.cross(b).dot(out.position[c[3]] - out.position[c[0]]);
}

void add_cell(ClippedCells& out, std::array<int, 4> c, int dim, int element) {
    if (signed_measure(out, c, dim) < 0.0) std::swap(c[dim == 3 ? 2 : 1], c[dim == 3 ? 3 : 2]);
    out.cells.push_back(c);
    out.element.push_back(element);
}

/// A prism with bottom (a0, a1, a2) and top (b0, b1, b2), bk above ak, as three tetrahedra.
void add_prism(ClippedCells& out, const std::array<int, 3>& a, const std::array<int, 3>& b, int element) {
    add_cell(out, {a[0], a[1], a[2], b[0]}, 3, element);
    add_cell(out, {a[1], a[2], b[0], b[1]}, 3, element);
    add_cell(out, {a[2], b[0], b[1], b[2]}, 3, element);
}

void edge_nodes(int dim, int edge, int& i, int& j) {
    i = dim == 3 ? kTetEdges[edge][0] : kTriEdges[edge][0];
    j = dim == 3 ? kTetEdges[edge][1] : kTriEdges[edge][1];
}

/// Writes virtual element `ve` clipped to its side; false (nothing written) if its cut is not a
/// full crossing: every edge between the two sides crossed, and only those.
bool add_clipped(ClippedCells& out, const World& w, Source& src, int parent, int8_t side) {
    const int ve = src.element;
    const Elements& el = w.elements;
    const int dim = el.dim, npe = el.nodes_per_element();
    const int c = w.cuts.cut_of_element.empty() ? -1 : w.cuts.cut_of_element[parent];
    if (c < 0 || w.enriched.sign.empty()) return false;
    std::array<int, 6> slot_of_edge;  // index into the cut's points, per local edge
    slot_of_edge.fill(-1);
    int crossed = 0;
    for (int k = 0; k < 4; ++k)
        if (w.cuts.point_edge[c][k] >= 0) slot_of_edge[w.cuts.point_edge[c][k]] = k, ++crossed;
    auto edge_between = [&](int a, int b) {
        for (int e = 0; e < (dim == 3 ? 6 : 3); ++e) {
            int i, j;
            edge_nodes(dim, e, i, j);
            if ((i == a && j == b) || (i == b && j == a)) return e;
        }
        return -1;
    };
    std::vector<int> own, other;
    for (int a = 0; a < npe; ++a) (w.enriched.sign[el.nodes[parent][a]] == side ? own : other).push_back(a);
    if (own.empty() || other.empty() || crossed != static_cast<int>(own.size() * other.size())) return false;
    for (int a : own)
        for (int b : other)
            if (slot_of_edge[edge_between(a, b)] < 0) return false;
    std::array<int, 6> point_of_edge;
    point_of_edge.fill(-1);
    auto point = [&](int a, int b) {  // the cut point between local nodes a and b, made once
        const int e = edge_between(a, b);
        if (point_of_edge[e] < 0) {
            int i, j;
            edge_nodes(dim, e, i, j);
            point_of_edge[e] = add_cut_point(out, w, src, i, j, w.cuts.points[c][slot_of_edge[e]]);
        }
        return point_of_edge[e];
    };
    const auto& v = el.nodes[ve];
    if (dim == 2) {
        if (own.size() == 1) {
            add_cell(out, {v[own[0]], point(own[0], other[0]), point(own[0], other[1]), -1}, 2, ve);
        } else {
            const int p0 = point(own[0], other[0]), p1 = point(own[1], other[0]);
            add_cell(out, {v[own[0]], v[own[1]], p1, -1}, 2, ve);
            add_cell(out, {v[own[0]], p1, p0, -1}, 2, ve);
        }
        return true;
    }
    if (own.size() == 1) {
        add_cell(out, {v[own[0]], point(own[0], other[0]), point(own[0], other[1]), point(own[0], other[2])}, 3, ve);
    } else if (own.size() == 3) {
        add_prism(out, {v[own[0]], v[own[1]], v[own[2]]},
                  {point(other[0], own[0]), point(other[0], own[1]), point(other[0], own[2])}, ve);
    } else {  // two nodes a, b on this side: the prism (a, p_ac, p_ad) -> (b, p_bc, p_bd)
        add_prism(out, {v[own[0]], point(own[0], other[0]), point(own[0], other[1])},
                  {v[own[1]], point(own[1], other[0]), point(own[1], other[1])}, ve);
    }
    return true;
}

/// Writes virtual element v of a tetrahedron cut again: its fragment (a convex polyhedron) as the
/// tetrahedra from its centroid to its faces' triangles, each face fanned from its first vertex.
/// Points at one place (within 1e-12 of the element's size) are one.
void add_fragment_3d(ClippedCells& out, const World& w, Source& src, int v, int c) {
    const auto& pn = w.elements.nodes[w.virtual_elements.parent[v]];
    const std::array<Vec3, 4> X{w.nodes.rest[pn[0]], w.nodes.rest[pn[1]], w.nodes.rest[pn[2]], w.nodes.rest[pn[3]]};
    const auto& lines = w.cuts.lines[c];
    const std::vector<FragmentFace> faces =
        fragment_faces(X, lines.data(), static_cast<int>(lines.size()), w.virtual_elements.mask[v]);
    const double tiny = 1e-12 * (X[1] - X[0]).norm();
    std::vector<std::pair<Vec3, int>> made;
    const auto point = [&](const Vec3& p) {
        for (const auto& [at, index] : made)
            if ((at - p).norm() <= tiny) return index;
        int index = -1;
        for (int a = 0; a < 4 && index < 0; ++a)
            if ((p - X[a]).norm() <= tiny) index = w.elements.nodes[src.element][a];
        if (index < 0) index = add_point(out, w, src, tet_barycentric(X, p), p);
        made.push_back({p, index});
        return index;
    };
    Vec3 centre = Vec3::Zero();
    int count = 0;
    for (const FragmentFace& f : faces)
        for (const Vec3& p : f.polygon) centre += p, ++count;
    if (count == 0) return;
    centre /= count;
    const int mid = add_point(out, w, src, tet_barycentric(X, centre), centre);
    for (const FragmentFace& f : faces) {
        std::vector<int> ring;
        for (const Vec3& p : f.polygon) {
            const int q = point(p);
            if (ring.empty() || (ring.back() != q && ring.front() != q)) ring.push_back(q);
        }
        for (size_t k = 1; k + 1 < ring.size(); ++k) add_cell(out, {mid, ring[0], ring[k], ring[k + 1]}, 3, src.element);
    }
}

/// Writes virtual element v of an element cut again (CutElements::lines): a triangle's fragment's
/// polygon, fanned from its first corner, a tetrahedron's by add_fragment_3d; true if it has lines.
bool add_fragment(ClippedCells& out, const World& w, Source& src, int v) {
    const int parent = w.virtual_elements.parent[v];
    const int c = w.cuts.cut_of_element[parent];
    if (c < 0 || w.cuts.lines[c].empty()) return false;
    if (w.elements.dim == 3) {
        add_fragment_3d(out, w, src, v, c);
        return true;
    }
    const auto& pn = w.elements.nodes[parent];
    const std::array<Vec3, 3> X{w.nodes.rest[pn[0]], w.nodes.rest[pn[1]], w.nodes.rest[pn[2]]};
    const auto& lines = w.cuts.lines[c];
    const std::vector<Vec3> poly =
        fragment_polygon(X, lines.data(), static_cast<int>(lines.size()), w.virtual_elements.mask[v]);
    if (poly.size() < 3) return true;
    std::vector<int> points;
    for (const Vec3& p : poly) {
        int corner = -1;
        for (int a = 0; a < 3; ++a)
            if (p == X[a]) corner = a;
        if (corner >= 0) {
            points.push_back(w.elements.nodes[src.element][corner]);
            continue;
        }
        const Vec3 l = triangle_barycentric(X, p);  // in the parent (xy)
        points.push_back(add_point(out, w, src, Eigen::Vector4d(l.x(), l.y(), l.z(), 0.0), p));
    }
    for (size_t k = 1; k + 1 < points.size(); ++k) add_cell(out, {points[0], points[k], points[k + 1], -1}, 2, src.element);
    return true;
}

/// Mesh element e as the four triangles fanned from a crack tip inside it (CrackTips::shown_*).
void add_tip_fan(ClippedCells& out, const CrackTips& ct, int shown, int e) {
    const int base = static_cast<int>(out.position.size());
    for (int p = 0; p < 3; ++p) {
        out.position.push_back(ct.shown_position[shown][p]);
        out.rest.push_back(ct.shown_rest[shown][p]);
        out.velocity.push_back(ct.shown_velocity[shown][p]);
    }
    const std::array<int, 12>& c = ct.shown_cells[shown];
    auto point = [&](int v) { return v >= 0 ? v : base - 1 - v; };
    for (int t = 0; t < 4; ++t) add_cell(out, {point(c[3 * t]), point(c[3 * t + 1]), point(c[3 * t + 2]), -1}, 2, e);
}

}  // namespace

ClippedCells clipped_cells(const World& w) {
    const Elements& el = w.elements;
    ClippedCells out;
    out.position = w.nodes.position;
    out.rest = w.nodes.rest;
    out.velocity = w.nodes.velocity;
    std::vector<int> virtual_of(el.count(), -1);
    for (int v = 0; v < w.virtual_elements.count(); ++v) virtual_of[w.virtual_elements.element[v]] = v;
    const CrackTips& ct = w.tips;
    std::vector<int> shown_of;  // per mesh element: the tip shown inside it, -1 none
    if (ct.shown_step == w.step && !ct.shown_element.empty()) {
        shown_of.assign(w.mesh_elements, -1);
        for (size_t s = 0; s < ct.shown_element.size(); ++s) shown_of[ct.shown_element[s]] = static_cast<int>(s);
    }
    for (int e = 0; e < el.count(); ++e) {
        if (!(el.weight[e] > 0.0)) continue;
        if (e < static_cast<int>(shown_of.size()) && shown_of[e] >= 0) {
            add_tip_fan(out, ct, shown_of[e], e);
            out.quadratic.resize(out.cells.size(), -1);
            continue;
        }
        const int v = virtual_of[e];
        Source src = source_of(w, e);
        const size_t first = out.cells.size();
        if (v >= 0 && add_fragment(out, w, src, v)) {
            out.quadratic.resize(out.cells.size(), -1);
            continue;
        }
        if (v >= 0 && add_clipped(out, w, src, w.virtual_elements.parent[v], w.virtual_elements.side[v])) {
            add_edge_points(out, w, src, first);
            continue;
        }
        out.cells.push_back(el.nodes[e]);
        out.element.push_back(e);
        out.quadratic.push_back(-1);
        if (src.quadratic) {  // whole: its own mid-edge nodes
            out.quadratic.back() = static_cast<int>(out.edge_points.size());
            out.edge_points.push_back({});
            std::copy(src.quadratic->begin() + 4, src.quadratic->end(), out.edge_points.back().begin());
        }
    }
    return out;
}

}  // namespace xcut
