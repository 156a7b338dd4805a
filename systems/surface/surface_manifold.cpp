// The vertices of edges where wounds touch, split so the surface stays a 2-manifold
// (systems/surface/surface_manifold.h).
#include "systems/surface/surface_manifold.h"

#include <algorithm>
#include <map>
#include <numeric>

#include "systems/surface/surface_arrays.h"
#include "systems/xfem_queries.h"

namespace xcut {
namespace {

/// A triangle's use of an undirected edge: the triangle and whether it runs low -> high.
struct EdgeUse {
    int triangle;
    bool forward;
};

/// The triangles of an edge used more than twice, paired one each way: those of one owner and one
/// kind (skin or wound) first, then of one owner, then in order. partner[k] is the pair of uses[k].
std::vector<int> pair_uses(const SurfaceMesh& s, const std::vector<EdgeUse>& uses) {
    std::vector<int> partner(uses.size(), -1);
    const auto match = [&](size_t i, size_t j, int level) {
        const int a = uses[i].triangle, b = uses[j].triangle;
        const bool owner = s.triangle_owner[a] == s.triangle_owner[b], kind = s.cut_face[a] == s.cut_face[b];
        return level == 0 ? owner && kind : level == 1 ? owner : true;
    };
    for (int level = 0; level < 3; ++level)
        for (size_t i = 0; i < uses.size(); ++i) {
            if (!uses[i].forward || partner[i] >= 0) continue;
            for (size_t j = 0; j < uses.size(); ++j)
                if (!uses[j].forward && partner[j] < 0 && match(i, j, level)) {
                    partner[i] = static_cast<int>(j), partner[j] = static_cast<int>(i);
                    break;
                }
        }
    return partner;
}

int find_root(std::vector<int>& parent, int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}

/// The pinched edges' pairs: (edge, triangle) -> the triangle it is paired with.
using Pairs = std::map<std::pair<std::pair<int, int>, int>, int>;

/// Two triangles on the same three vertices, one each way, enclose nothing (both lips of a wound
/// made of the same vertices, or a piece of skin two fragments both made): both go, which leaves
/// every edge as closed as it was. Per triangle: whether it goes.
std::vector<uint8_t> coincident_pairs(const SurfaceMesh& s, const std::vector<uint8_t>& near) {
    const int triangles = static_cast<int>(s.triangles.size());
    std::vector<uint8_t> gone(triangles, 0);
    std::vector<std::pair<std::array<int, 4>, int>> keyed;  // (sorted corners, orientation) -> triangle
    for (int t = 0; t < triangles; ++t) {
        std::array<int, 3> c = s.triangles[t];
        if (!near[c[0]] || !near[c[1]] || !near[c[2]]) continue;
        const int parity = (c[0] < c[1]) + (c[1] < c[2]) + (c[0] < c[2]);  // 3 or 1 ascending pairs: even
        std::sort(c.begin(), c.end());
        keyed.push_back({{c[0], c[1], c[2], parity % 2}, t});
    }
    std::sort(keyed.begin(), keyed.end());  // deterministic: by corners, orientation, triangle
    for (size_t i = 0; i < keyed.size();) {
        size_t j = i;
        while (j < keyed.size() && std::equal(keyed[j].first.begin(), keyed[j].first.begin() + 3, keyed[i].first.begin())) ++j;
        size_t odd = i;  // the first of the other orientation
        while (odd < j && keyed[odd].first[3] == 0) ++odd;
        for (size_t k = 0; i + k < odd && odd + k < j; ++k) gone[keyed[i + k].second] = gone[keyed[odd + k].second] = 1;
        i = j;
    }
    return gone;
}

/// The pairs of every edge between `near` vertices used more than twice, as often each way (an
/// open edge is left as it is); marks both ends `pinched`.
Pairs pinched_pairs(const SurfaceMesh& s, const std::vector<uint8_t>& near, const std::vector<uint8_t>& gone,
                    std::vector<uint8_t>& pinched) {
    std::vector<std::pair<std::pair<int, int>, EdgeUse>> keyed;  // (edge, use), sorted: deterministic
    for (int t = 0; t < static_cast<int>(s.triangles.size()); ++t)
        for (int k = 0; k < 3 && !gone[t]; ++k) {
            const int a = s.triangles[t][k], b = s.triangles[t][(k + 1) % 3];
            if (near[a] && near[b]) keyed.push_back({{std::min(a, b), std::max(a, b)}, {t, a < b}});
        }
    std::sort(keyed.begin(), keyed.end(), [](const auto& l, const auto& r) {
        return l.first != r.first ? l.first < r.first : l.second.triangle < r.second.triangle;
    });
    Pairs pair_of;
    std::vector<EdgeUse> uses;
    for (size_t i = 0; i < keyed.size();) {
        size_t j = i;
        uses.clear();
        for (; j < keyed.size() && keyed[j].first == keyed[i].first; ++j) uses.push_back(keyed[j].second);
        const std::pair<int, int> edge = keyed[i].first;
        i = j;
        const auto forward = std::count_if(uses.begin(), uses.end(), [](const EdgeUse& u) { return u.forward; });
        if (uses.size() <= 2 || 2 * forward != static_cast<long>(uses.size())) continue;  // manifold, or open
        const std::vector<int> partner = pair_uses(s, uses);
        for (size_t k = 0; k < uses.size(); ++k) pair_of[{edge, uses[k].triangle}] = uses[partner[k]].triangle;
        pinched[edge.first] = pinched[edge.second] = 1;
    }
    return pair_of;
}

/// The fans round vertex v (its triangles `tris`, joined through an edge at v, by their pair where
/// it is pinched): the fan of v's first triangle keeps v, each other one takes a copy.
void split_fans(SurfaceMesh& s, int v, const std::vector<int>& tris, const Pairs& pair_of) {
    std::vector<int> parent(tris.size());
    std::iota(parent.begin(), parent.end(), 0);
    std::map<int, std::vector<int>> by_other;  // the edge's other end -> the triangles (local)
    for (size_t i = 0; i < tris.size(); ++i)
        for (int x : s.triangles[tris[i]])
            if (x != v) by_other[x].push_back(static_cast<int>(i));
    for (const auto& [x, local] : by_other) {
        const std::pair<int, int> edge{std::min(v, x), std::max(v, x)};
        for (size_t a = 0; a < local.size(); ++a)
            for (size_t b = a + 1; b < local.size(); ++b) {
                const auto p = pair_of.find({edge, tris[local[a]]});
                if (p == pair_of.end() || p->second == tris[local[b]])
                    parent[find_root(parent, local[a])] = find_root(parent, local[b]);
            }
    }
    std::map<int, int> copy_of_root;
    copy_of_root[find_root(parent, 0)] = v;
    for (size_t i = 0; i < tris.size(); ++i) {
        const int root = find_root(parent, static_cast<int>(i));
        auto it = copy_of_root.find(root);
        if (it == copy_of_root.end()) {
            it = copy_of_root.emplace(root, s.vertex_count()).first;
            s.position.push_back(s.position[v]), s.element.push_back(s.element[v]);
            s.bary.push_back(s.bary[v]), s.side.push_back(s.side[v]);
            s.manifold_source.push_back(v);
        }
        for (int& corner : s.triangles[tris[i]])
            if (corner == v) corner = it->second;
    }
}

/// Whether triangle `tri` runs along `edge` from its first end to its second.
bool runs_forward(const std::array<int, 3>& tri, const std::pair<int, int>& edge) {
    for (int k = 0; k < 3; ++k)
        if (tri[k] == edge.first && tri[(k + 1) % 3] == edge.second) return true;
    return false;
}

/// The pinched edges of four triangles the fans left pinched (three of them still share the copies
/// of its ends: their pairs are joined round both ends by other edges) paired the other way.
/// `made`: the triangles as the cut made them. Whether any was.
bool pair_other_way(const SurfaceMesh& s, const std::vector<std::array<int, 3>>& made, Pairs& pair_of) {
    std::map<std::pair<int, int>, std::vector<int>> of_edge;  // in order of (edge, triangle)
    for (const auto& [key, partner] : pair_of) of_edge[key.first].push_back(key.second);
    bool any = false;
    for (const auto& [edge, tris] : of_edge) {
        std::map<std::pair<int, int>, int> shared;  // the copies of its ends -> triangles using them
        int most = 0;
        for (int t : tris) {
            std::pair<int, int> ends{-1, -1};
            for (int c : s.triangles[t]) {
                if (s.source_vertex(c) == edge.first) ends.first = c;
                if (s.source_vertex(c) == edge.second) ends.second = c;
            }
            most = std::max(most, ++shared[ends]);
        }
        if (most <= 2 || tris.size() != 4) continue;
        const int t0 = tris[0], p = pair_of.at({edge, t0});
        int q = -1, r = -1;  // of the other two: q runs against t0, r with it
        for (int t : tris)
            if (t != t0 && t != p) (runs_forward(made[t], edge) != runs_forward(made[t0], edge) ? q : r) = t;
        if (q < 0 || r < 0) continue;
        pair_of[{edge, t0}] = q, pair_of[{edge, q}] = t0, pair_of[{edge, p}] = r, pair_of[{edge, r}] = p;
        any = true;
    }
    return any;
}

}  // namespace

void split_pinched_edges(const World& w, SurfaceMesh& s) {
    // Elements cut once leave closed 2-manifolds by their vertex keys alone (systems/surface/surface_cut.h):
    // only where elements are cut again can wounds touch so.
    if (w.elements.dim != 3 || w.snap.enabled || !recut_allowed(w) || s.manifold_first_vertex >= 0) return;
    const int vertices = s.vertex_count(), triangles = static_cast<int>(s.triangles.size());
    // Only a cut element's pieces can meet more than one other triangle at an edge: the edges whose
    // both ends a cut element's triangle uses hold every such edge, and every triangle using one.
    std::vector<uint8_t> near(vertices, 0);
    const auto cut = [&](int e) { return e < static_cast<int>(w.cuts.cut_of_element.size()) && w.cuts.cut_of_element[e] >= 0; };
    for (int t = 0; t < triangles; ++t)
        if (cut(s.triangle_owner[t]))
            for (int v : s.triangles[t]) near[v] = 1;
    const std::vector<uint8_t> gone = coincident_pairs(s, near);
    std::vector<uint8_t> pinched(vertices, 0);
    Pairs pair_of = pinched_pairs(s, near, gone, pinched);
    if (pair_of.empty() && std::find(gone.begin(), gone.end(), 1) == gone.end()) return;
    s.manifold_first_vertex = vertices;
    s.manifold_saved_triangles = s.triangles, s.manifold_saved_owner = s.triangle_owner, s.manifold_saved_cut_face = s.cut_face;
    std::map<int, std::vector<int>> around;  // pinched vertex -> its triangles, in order
    for (int t = 0; t < triangles; ++t)
        for (int v : s.triangles[t])
            if (pinched[v] && !gone[t]) around[v].push_back(t);
    for (const auto& [v, tris] : around) split_fans(s, v, tris, pair_of);
    // Where the preferred pairs leave an edge pinched (each pair's lens joined to the other's round
    // both ends), the other pairing (one wound through the face) is tried once, from the cut's own.
    if (pair_other_way(s, s.manifold_saved_triangles, pair_of)) {
        s.triangles = s.manifold_saved_triangles;
        keep_vertices(s, static_cast<size_t>(vertices));
        s.manifold_source.clear();
        for (const auto& [v, tris] : around) split_fans(s, v, tris, pair_of);
    }
    drop_triangles(s, gone);
}

void take_off_pinch_split(World& w, SurfaceMesh& s) {
    if (s.manifold_first_vertex < 0) return;
    Grasps& g = w.grasps;
    for (size_t i = 0; i < std::min(g.surface.size(), g.vertex.size()); ++i)
        if ((g.surface[i] == 0 ? &w.collision : &w.visual) == &s)
            for (int& v : g.vertex[i]) v = s.source_vertex(v);
    s.triangles.swap(s.manifold_saved_triangles);
    s.triangle_owner.swap(s.manifold_saved_owner);
    s.cut_face.swap(s.manifold_saved_cut_face);
    s.manifold_saved_triangles.clear(), s.manifold_saved_owner.clear(), s.manifold_saved_cut_face.clear();
    keep_vertices(s, static_cast<size_t>(s.manifold_first_vertex));
    s.manifold_first_vertex = -1;
    s.manifold_source.clear();
}

}  // namespace xcut
