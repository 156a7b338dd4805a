#pragma once
// Element edges, and the measures of the mesh at rest that the cut's search and the tools' sampling
// are sized by.
#include <algorithm>
#include <vector>

#include "components/cut_elements.h"
#include "components/elements.h"
#include "components/nodes.h"

namespace xcut {

/// Edges of an element of the mesh's dimension: 6 of a tetrahedron, 3 of a triangle, and the local
/// nodes of edge k (components/cut_elements.h's tables).
inline int edge_count(int dim) { return dim == 3 ? 6 : 3; }
inline const int* edge_nodes(int dim, int k) { return dim == 3 ? kTetEdges[k] : kTriEdges[k]; }

/// Shortest edge of element e at positions x [m].
inline double shortest_edge(const Elements& el, const Vec3* x, int e) {
    double shortest = 1e300;
    for (int k = 0; k < edge_count(el.dim); ++k)
        shortest = std::min(shortest, (x[el.nodes[e][edge_nodes(el.dim, k)[0]]] - x[el.nodes[e][edge_nodes(el.dim, k)[1]]]).norm());
    return shortest;
}

/// Mean edge length of the mesh elements [0, mesh_elements) at their rest positions [m].
inline double mean_edge_length(const Elements& el, const std::vector<Vec3>& rest, int mesh_elements) {
    double sum = 0.0;
    long n = 0;
    for (int e = 0; e < mesh_elements; ++e)
        for (int k = 0; k < edge_count(el.dim); ++k) {
            const int* ed = edge_nodes(el.dim, k);
            sum += (rest[el.nodes[e][ed[0]]] - rest[el.nodes[e][ed[1]]]).norm();
            ++n;
        }
    return n > 0 ? sum / n : 0.0;
}

}  // namespace xcut
