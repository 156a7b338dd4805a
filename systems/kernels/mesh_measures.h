#pragma once
// Measures of the mesh at rest that the cut's search and the tools' sampling are sized by.
#include <vector>

#include "components/cut_elements.h"
#include "components/elements.h"
#include "components/nodes.h"

namespace xcut {

/// Mean edge length of the mesh elements [0, mesh_elements) at their rest positions [m].
inline double mean_edge_length(const Elements& el, const std::vector<Vec3>& rest, int mesh_elements) {
    double sum = 0.0;
    long n = 0;
    const int edges = el.dim == 3 ? 6 : 3;
    for (int e = 0; e < mesh_elements; ++e)
        for (int k = 0; k < edges; ++k) {
            const int* ed = el.dim == 3 ? kTetEdges[k] : kTriEdges[k];
            sum += (rest[el.nodes[e][ed[0]]] - rest[el.nodes[e][ed[1]]]).norm();
            ++n;
        }
    return n > 0 ? sum / n : 0.0;
}

}  // namespace xcut
