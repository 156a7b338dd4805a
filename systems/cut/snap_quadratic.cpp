#include "systems/cut/snap_quadratic.h"

#include <Eigen/Dense>
#include <algorithm>
#include <limits>

#include "engine/quadratic_setup.h"
#include "engine/tet10_shapes.h"
#include "systems/cut/snap_cut_system.h"

namespace xcut {
namespace {

/// A point this far outside an element in barycentric terms still lies in it [-] (the pieces' rest
/// points are made from the elements' own corners, so only rounding puts them outside).
constexpr double kInside = -1e-9;

uint64_t pair_key(int a, int b) {
    return (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint32_t>(std::max(a, b));
}

/// Barycentric coordinates of X in the tetrahedron (`planar`: the triangle, L_3 = 0) of corners c at
/// the kept rest positions.
Eigen::Vector4d barycentric_in(const std::vector<Vec3>& rest, const std::array<int, 4>& c, const Vec3& X, bool planar) {
    if (planar) {
        Eigen::Matrix2d D;
        for (int k = 0; k < 2; ++k) D.col(k) = (rest[c[k + 1]] - rest[c[0]]).head<2>();
        const Eigen::Vector2d l = D.partialPivLu().solve((X - rest[c[0]]).head<2>());
        return {1.0 - l.sum(), l[0], l[1], 0.0};
    }
    Mat3 D;
    for (int k = 0; k < 3; ++k) D.col(k) = rest[c[k + 1]] - rest[c[0]];
    const Vec3 l = D.partialPivLu().solve(X - rest[c[0]]);
    return {1.0 - l.sum(), l[0], l[1], l[2]};
}

/// The side force element e lay on before the cut: a piece's own; a whole mesh element's from its
/// nodes' sides (0 where they differ or none has one: the field is continuous there).
int side_before(const SnapQuadraticField& b, const World& w, int e) {
    if (e >= w.mesh_elements) return b.piece_side[e - w.mesh_elements];
    bool above = false, below = false;
    for (int k = 0; k < w.elements.nodes_per_element(); ++k) {
        const int a = b.corners[e][k];
        if (a < static_cast<int>(b.sign.size())) above |= b.sign[a] > 0, below |= b.sign[a] < 0;
    }
    return above == below ? 0 : (above ? 1 : -1);
}

/// The quadratic element, among those that carried mesh element f before the cut (f while whole,
/// else its live pieces) on a side that agrees with `side` (0: any), that holds X best.
struct Holder {
    int entry = -1;
    Eigen::Vector4d L = Eigen::Vector4d::Zero();
    double inside = -std::numeric_limits<double>::infinity();  ///< the smallest barycentric coordinate
};

void consider(const SnapQuadraticField& b, const World& w, int f, int side, const Vec3& X, Holder& best) {
    auto test = [&](int e) {
        const int t = e < static_cast<int>(b.of_element.size()) ? b.of_element[e] : -1;
        if (t < 0 || side * side_before(b, w, e) < 0) return;
        const Eigen::Vector4d L = barycentric_in(b.rest, b.corners[e], X, w.quadratic.planar);
        if (L.minCoeff() > best.inside) best = {t, L, L.minCoeff()};
    };
    if (b.weight[f] > 0.0) {
        test(f);
        return;
    }
    // A mesh element's list of piece slots only grows, and the kept liveness covers the slots it had.
    for (int q : w.snap.pieces[f]) {
        const int slot = q - w.mesh_elements;
        if (slot < static_cast<int>(b.piece_live.size()) && b.piece_live[slot]) test(q);
    }
}

/// Considers the mesh elements around mesh node i.
void consider_around(const SnapQuadraticField& b, const World& w, int i, int side, const Vec3& X, Holder& best) {
    const Incidence& inc = w.incidence;
    for (int p = inc.offset[i]; p < inc.offset[i + 1]; ++p) consider(b, w, inc.entry[p] >> 2, side, X, best);
}

/// Node i takes the kept field's position and velocity at its rest point, from the element that
/// holds it best (unchanged if no quadratic element was found).
void take_field(World& w, const SnapQuadraticField& b, const Holder& h, int i) {
    if (h.entry < 0) return;
    w.nodes.position[i] = tet10_point(b.nodes[h.entry], h.L, b.position.data());
    w.nodes.velocity[i] = tet10_point(b.nodes[h.entry], h.L, b.velocity.data());
}

/// The mid-edge node of the edge u-v of a piece of mesh element f on `side`: the one the pieces
/// have there, moved to the edge's rest midpoint if a corner was snapped, or a new one. A node
/// placed anew takes the kept field at its rest point (f's carriers; where f's rest shape moved
/// out of its old one at a snapped corner, its neighbours' too).
int mid_node_of(World& w, const SnapQuadraticField& b, int f, int side, int u, int v) {
    SnapMesh& s = w.snap;
    const Vec3 X = 0.5 * (w.nodes.rest[u] + w.nodes.rest[v]);
    const uint64_t key = pair_key(u, v);
    const auto it = s.mid_node.find(key);
    if (it != s.mid_node.end() && w.nodes.rest[it->second] == X) return it->second;
    int m = -1;
    if (it != s.mid_node.end()) {
        m = it->second;
    } else {
        m = add_snap_node(w, u, v, 0.5);
        s.extra_edge.push_back({-1, -1});
        s.extra_root.push_back(m);
        s.mid_node[key] = m;
        ++s.mid_nodes;
    }
    w.nodes.rest[m] = X;
    Holder h;
    consider(b, w, f, side, X, h);
    if (h.inside < kInside)
        for (int k = 0; k < w.elements.nodes_per_element(); ++k) consider_around(b, w, w.elements.nodes[f][k], side, X, h);
    take_field(w, b, h, m);
    // Held axes: at the midpoint of the corners' prescribed positions (constrain_edge_nodes).
    const uint8_t held = w.nodes.fixed[u] & w.nodes.fixed[v] & 7;
    for (int c = 0; c < 3; ++c)
        if ((held >> c) & 1) w.nodes.position[m][c] = 0.5 * (w.nodes.position[u][c] + w.nodes.position[v][c]);
    return m;
}

}  // namespace

SnapQuadraticField keep_quadratic_field(const World& w) {
    SnapQuadraticField b;
    if (w.quadratic.count() == 0) return b;
    b.active = true;
    b.rest = w.nodes.rest, b.position = w.nodes.position, b.velocity = w.nodes.velocity;
    b.corners = w.elements.nodes, b.weight = w.elements.weight;
    b.of_element = w.quadratic.of_element, b.nodes = w.quadratic.nodes;
    b.piece_side = w.snap.piece_side, b.piece_live = w.snap.piece_live;
    b.sign = w.enriched.sign;
    return b;
}

void place_on_quadratic_field(World& w, const SnapQuadraticField& b, const std::vector<int>& moved, int first_point) {
    if (!b.active) return;
    auto place = [&](int i, int around) {
        Holder h;
        consider_around(b, w, around, 0, w.nodes.rest[i], h);
        take_field(w, b, h, i);
    };
    for (int a : moved) place(a, a);
    for (int p = first_point; p < w.nodes.count(); ++p) place(p, w.snap.extra_edge[p - w.mesh_nodes][0]);
}

void build_quadratic_pieces(World& w, const SnapQuadraticField& b, const std::vector<int>& pieces) {
    if (!b.active) return;
    QuadraticElements& q = w.quadratic;
    SnapMesh& s = w.snap;
    if (s.mid_node.empty())
        for (size_t k = 0; k < q.edge_of_node.size(); ++k)
            s.mid_node[pair_key(q.edge_of_node[k][0], q.edge_of_node[k][1])] = q.first_edge_node + static_cast<int>(k);
    q.of_element.resize(w.elements.count(), -1);
    for (int e : pieces) {
        const int slot = e - w.mesh_elements, f = s.piece_parent[slot];
        if (!s.piece_live[slot]) continue;
        int t = q.of_element[e];
        if (t < 0) {
            t = q.of_element[e] = q.count();
            q.element.push_back(e);
            q.nodes.emplace_back();
        }
        const std::array<int, 4> c = w.elements.nodes[e];
        for (int a = 0; a < w.elements.nodes_per_element(); ++a) q.nodes[t][a] = c[a];
        for (int k = 0; k < q.edge_count(); ++k)
            q.nodes[t][4 + k] = mid_node_of(w, b, f, s.piece_side[slot], c[kTet10Edges[k][0]], c[kTet10Edges[k][1]]);
        fill_absent_slots(q, q.nodes[t]);
    }
    build_quadratic_incidence(w);
}

}  // namespace xcut
