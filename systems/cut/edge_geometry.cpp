#include "systems/cut/edge_geometry.h"

#include <algorithm>

#include "engine/quadratic_setup.h"
#include "systems/kernels/intersection.h"
#include "systems/kernels/mesh_measures.h"

namespace xcut {

Vec3 edge_point(const World& w, int e, int k, double t, const std::vector<Vec3>* at) {
    const int* ed = edge_nodes(w.elements.dim, k);
    const Vec3* x = (at ? *at : w.nodes.position).data();
    const Vec3 &a = x[w.elements.nodes[e][ed[0]]], &b = x[w.elements.nodes[e][ed[1]]];
    const int m = w.elements.dim == 3 ? mid_edge_node(w, e, ed[0], ed[1]) : -1;
    return m >= 0 ? quadratic_edge_point(a, x[m], b, t) : Vec3(a + t * (b - a));
}

double plane_edge_param(const World& w, int e, int k, const Vec3& o, const Vec3& n, const std::vector<Vec3>* at) {
    const int* ed = edge_nodes(w.elements.dim, k);
    const Vec3* x = (at ? *at : w.nodes.position).data();
    const double li = (x[w.elements.nodes[e][ed[0]]] - o).dot(n), lj = (x[w.elements.nodes[e][ed[1]]] - o).dot(n);
    const int m = w.elements.dim == 3 ? mid_edge_node(w, e, ed[0], ed[1]) : -1;
    if (m >= 0) return quadratic_edge_root(li, (x[m] - o).dot(n), lj);
    return li != lj ? std::clamp(li / (li - lj), 0.0, 1.0) : 0.5;
}

}  // namespace xcut
