#include "systems/kernels/snap_split_patterns.h"

#include <algorithm>

#include "components/cut_elements.h"

namespace xcut {

std::vector<std::array<int, 4>> bisect_simplex(const std::array<int, 4>& nodes, int dim, std::vector<EdgeSplit> splits) {
    const int npe = dim == 3 ? 4 : 3;
    std::sort(splits.begin(), splits.end(), [](const EdgeSplit& a, const EdgeSplit& b) { return a.order < b.order; });
    std::vector<std::array<int, 4>> pieces{nodes};
    for (const EdgeSplit& s : splits) {
        const int* ed = dim == 3 ? kTetEdges[s.edge] : kTriEdges[s.edge];
        const int a = nodes[ed[0]], b = nodes[ed[1]];
        std::vector<std::array<int, 4>> next;
        next.reserve(pieces.size() + 4);
        for (const auto& p : pieces) {
            int ia = -1, ib = -1;
            for (int k = 0; k < npe; ++k) {
                if (p[k] == a) ia = k;
                if (p[k] == b) ib = k;
            }
            if (ia < 0 || ib < 0) {
                next.push_back(p);
                continue;
            }
            std::array<int, 4> half_a = p, half_b = p;
            half_a[ib] = s.node;  // keeps a: the half between a and the point
            half_b[ia] = s.node;
            next.push_back(half_a);
            next.push_back(half_b);
        }
        pieces.swap(next);
    }
    return pieces;
}

}  // namespace xcut
