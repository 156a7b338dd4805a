#include "systems/cut/quad_reach.h"

#include <algorithm>
#include <cmath>

#include "engine/quadratic_setup.h"

namespace xcut {
namespace {

/// Whether element e's box at current positions meets the quad's box and straddles the plane of one
/// of its triangles: a necessary condition for the quad to cross it. A quadratic element's edge
/// p(s) = chord(s) + 4 s (1 - s) d (d: its mid-edge node's offset from the chord's midpoint) lies
/// within the corners' box grown by the largest |d|.
bool may_reach(const World& w, int e, const QuadReach& q) {
    const auto& n = w.elements.nodes[e];
    const Vec3* x = w.nodes.position.data();
    Vec3 elo = x[n[0]], ehi = elo;
    for (int a = 1; a < w.elements.nodes_per_element(); ++a) {
        elo = elo.cwiseMin(x[n[a]]);
        ehi = ehi.cwiseMax(x[n[a]]);
    }
    if (const int t = quadratic_entry(w, e); t >= 0) {
        const auto& qn = w.quadratic.nodes[t];
        double bulge = 0.0;
        for (int k = 0; k < w.quadratic.edge_count(); ++k)
            bulge = std::max(bulge, (x[qn[4 + k]] - 0.5 * (x[qn[kTet10Edges[k][0]]] + x[qn[kTet10Edges[k][1]]])).norm());
        elo.array() -= bulge, ehi.array() += bulge;
    }
    if (!((elo.array() <= q.hi.array()).all() && (ehi.array() >= q.lo.array()).all())) return false;
    const Vec3 centre = 0.5 * (elo + ehi), half = 0.5 * (ehi - elo);
    for (const auto& [point, normal] : q.planes) {
        const double reach = normal.cwiseAbs().dot(half), offset = normal.dot(centre - point);
        if (std::abs(offset) <= reach * (1.0 + 1e-9) + 1e-12 * normal.norm()) return true;
    }
    return false;
}

}  // namespace

std::vector<int> neighbourhood(const World& w, const std::vector<int>& seeds, int depth, const QuadReach& quad) {
    const Incidence& inc = w.incidence;
    const int npe = w.elements.nodes_per_element();
    std::vector<int> frontier = seeds, all = seeds;
    std::vector<uint8_t> seen(w.mesh_elements, 0);
    for (int e : seeds) seen[e] = 1;
    for (int level = 0; !frontier.empty(); ++level) {
        std::vector<int> next;
        for (int e : frontier) {
            // Past the depth, only from elements the quad may cross: the ring at the depth is checked
            // once each, not every neighbour of it.
            if (level == depth && !may_reach(w, e, quad)) continue;
            for (int a = 0; a < npe; ++a) {
                const int j = w.elements.nodes[e][a];
                for (int p = inc.offset[j]; p < inc.offset[j + 1]; ++p) {
                    const int f = inc.entry[p] >> 2;
                    if (!seen[f] && (level < depth || may_reach(w, f, quad))) seen[f] = 1, next.push_back(f);
                }
            }
        }
        all.insert(all.end(), next.begin(), next.end());
        frontier.swap(next);
    }
    std::sort(all.begin(), all.end());
    return all;
}


QuadReach quad_reach(const std::vector<const CutQuad*>& quads, const std::vector<std::array<Vec3, 2>>& normals) {
    QuadReach reach{quads[0]->corner[0], quads[0]->corner[0], {}};
    for (size_t k = 0; k < quads.size(); ++k) {
        for (const Vec3& v : quads[k]->corner) reach.lo = reach.lo.cwiseMin(v), reach.hi = reach.hi.cwiseMax(v);
        for (const Vec3& n : normals[k]) reach.planes.emplace_back(quads[k]->corner[0], n);
    }
    const Vec3 pad = Vec3::Constant(1e-9 * std::max(1.0, (reach.hi - reach.lo).norm()));  // rounding only
    reach.lo -= pad, reach.hi += pad;
    return reach;
}

}  // namespace xcut
