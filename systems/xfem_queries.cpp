#include "systems/xfem_queries.h"

#include <algorithm>

#include "systems/kernels/mesh_measures.h"

namespace xcut {

bool edge_crossed(const World& w, int a, int b) {
    const Elements& el = w.elements;
    for (int p = w.incidence.offset[a]; p < w.incidence.offset[a + 1]; ++p) {
        const int f = w.incidence.entry[p] >> 2, c = w.cuts.cut_of_element[f];
        if (c < 0) continue;
        for (int k = 0; k < edge_count(el.dim); ++k) {
            const int i = el.nodes[f][edge_nodes(el.dim, k)[0]], j = el.nodes[f][edge_nodes(el.dim, k)[1]];
            if (((i == a && j == b) || (i == b && j == a)) && (w.cuts.crossed[c] >> k & 1)) return true;
        }
    }
    return false;
}

double crack_edge_param(const World& w, int a, int b) {
    const Elements& el = w.elements;
    const int dim = el.dim;
    for (int p = w.incidence.offset[a]; p < w.incidence.offset[a + 1]; ++p) {
        const int f = w.incidence.entry[p] >> 2;
        const int c = w.cuts.cut_of_element[f];
        if (c < 0) continue;
        for (int k = 0; k < 4 && w.cuts.point_edge[c][k] >= 0; ++k) {
            const int* ed = (dim == 3 ? kTetEdges : kTriEdges)[w.cuts.point_edge[c][k]];
            const int n0 = el.nodes[f][ed[0]], n1 = el.nodes[f][ed[1]];
            if (!((n0 == a && n1 == b) || (n0 == b && n1 == a))) continue;
            const Vec3 &Xa = w.nodes.rest[a], &Xb = w.nodes.rest[b];
            return std::clamp((w.cuts.points[c][k] - Xa).dot(Xb - Xa) / (Xb - Xa).squaredNorm(), 0.0, 1.0);
        }
    }
    return -1.0;
}

Vec3 enriched_displacement(const World& w, int j) {
    const int p = j < static_cast<int>(w.enriched.phantom.size()) ? w.enriched.phantom[j] : -1;
    if (p < 0) return Vec3::Zero();
    const Vec3 d = w.nodes.position[p] - w.nodes.position[j];
    return w.enriched.sign[j] > 0 ? Vec3(-d) : d;
}

Vec3 enriched_velocity(const World& w, int j) {
    const int p = j < static_cast<int>(w.enriched.phantom.size()) ? w.enriched.phantom[j] : -1;
    if (p < 0) return Vec3::Zero();
    const Vec3 d = w.nodes.velocity[p] - w.nodes.velocity[j];
    return w.enriched.sign[j] > 0 ? Vec3(-d) : d;
}

}  // namespace xcut
