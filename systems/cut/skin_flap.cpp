#include "systems/cut/skin_flap.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "systems/cut/edge_geometry.h"
#include "systems/kernels/mesh_measures.h"

namespace xcut {

bool lies_on_skin(const World& w, int e, const CutEvent& ev) {
    const Elements& el = w.elements;
    const int dim = el.dim, npe = el.nodes_per_element();
    const Vec3* x = w.nodes.position.data();
    const auto& n = el.nodes[e];
    const double tolerance = kThinFlapFraction * shortest_edge(el, x, e);
    std::vector<Vec3> points;
    bool off_nodes = false;
    for (int k = 0; k < edge_count(dim); ++k) {
        const int* ed = edge_nodes(dim, k);
        const double li = ev.level[ed[0]], lj = ev.level[ed[1]];
        if ((li >= 0.0) == (lj >= 0.0)) continue;
        // Where the enrichment will put the point: the event's parameter, else where the levels
        // change sign (a progressive front's edges ahead of the blade).
        const double t = ev.edge_has_t[k] ? ev.edge_t[k] : li / (li - lj);
        const Vec3 &a = x[n[ed[0]]], &b = x[n[ed[1]]];
        points.push_back(edge_point(w, e, k, t));
        off_nodes = off_nodes || std::min(t, 1.0 - t) * (b - a).norm() > tolerance;
    }
    if (!off_nodes) return false;
    for (int skip = 0; skip < npe; ++skip) {  // the face opposite local node `skip`
        std::array<int, 3> face{};
        int m = 0;
        for (int a = 0; a < npe; ++a)
            if (a != skip) face[m++] = n[a];
        int holders = 0;  // elements holding the whole face
        for (int p = w.incidence.offset[face[0]]; p < w.incidence.offset[face[0] + 1]; ++p) {
            const auto& f = el.nodes[w.incidence.entry[p] >> 2];
            bool all = true;
            for (int b = 1; b < m; ++b) all = all && std::find(f.begin(), f.begin() + npe, face[b]) != f.begin() + npe;
            holders += all;
        }
        if (holders != 1) continue;
        const Vec3 o = x[face[0]], u = x[face[1]] - o;
        Vec3 normal = dim == 3 ? Vec3(u.cross(x[face[2]] - o)) : Vec3(-u.y(), u.x(), 0.0);
        if (normal.norm() == 0.0) continue;
        normal.normalize();
        bool on = true;
        for (const Vec3& q : points) on = on && std::abs((q - o).dot(normal)) < tolerance;
        if (on) return true;
    }
    return false;
}

}  // namespace xcut
