#include "systems/xfem_queries.h"

#include <algorithm>
#include <cmath>

#include "systems/kernels/front_enrichment.h"
#include "systems/kernels/mesh_measures.h"

namespace xcut {

bool edge_crossed(const World& w, int a, int b) {
    for (int p = w.incidence.offset[a]; p < w.incidence.offset[a + 1]; ++p) {
        const int f = w.incidence.entry[p] >> 2, c = w.cuts.cut_of_element[f];
        bool from_a = true;
        const int k = c < 0 ? -1 : local_edge_of(w, f, a, b, from_a);
        if (k >= 0 && (w.cuts.crossed[c] >> k & 1)) return true;
    }
    return false;
}

double crack_edge_param(const World& w, int a, int b) {
    const Elements& el = w.elements;
    const int dim = el.dim;
    // An element cut by its own line (another incision's, systems/cut/recut.h) is asked last: an
    // edge two incisions cross has a point of each, and an element cut once along the nodes' sides
    // takes its own incision's.
    for (int pass = 0; pass < 2; ++pass) {
        for (int p = w.incidence.offset[a]; p < w.incidence.offset[a + 1]; ++p) {
            const int f = w.incidence.entry[p] >> 2;
            const int c = w.cuts.cut_of_element[f];
            if (c < 0 || w.cuts.lines[c].empty() != (pass == 0)) continue;
            for (int k = 0; k < 4 && w.cuts.point_edge[c][k] >= 0; ++k) {
                const int* ed = (dim == 3 ? kTetEdges : kTriEdges)[w.cuts.point_edge[c][k]];
                const int n0 = el.nodes[f][ed[0]], n1 = el.nodes[f][ed[1]];
                if (!((n0 == a && n1 == b) || (n0 == b && n1 == a))) continue;
                const Vec3 &Xa = w.nodes.rest[a], &Xb = w.nodes.rest[b];
                return std::clamp((w.cuts.points[c][k] - Xa).dot(Xb - Xa) / (Xb - Xa).squaredNorm(), 0.0, 1.0);
            }
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

int crack_node_lip(const World& w, const Vec3& point, const Vec3& direction, const Vec3& normal, int node) {
    const Vec3 rel = w.nodes.rest[node] - point;
    if (rel.dot(direction) >= 0.0 || std::abs(rel.dot(normal)) > 1e-12 * rel.norm()) return 0;
    const int H = node < static_cast<int>(w.enriched.sign.size()) ? w.enriched.sign[node] : 0;
    if (H == 0) return 1;
    return w.enriched.sign_normal[node].dot(normal) >= 0.0 ? H : -H;
}

int tip_node_lip(const World& w, const Vec2& tip_point, const Vec2& tip_direction, int node) {
    const Vec3 point(tip_point.x(), tip_point.y(), w.nodes.rest[node].z());  // the node's own plane
    return crack_node_lip(w, point, Vec3(tip_direction.x(), tip_direction.y(), 0.0),
                          Vec3(-tip_direction.y(), tip_direction.x(), 0.0), node);
}

Vec3 tip_enrichment(const World& w, const Eigen::VectorXd& b, int z, const Vec2& X, const Vec3& L, int lip) {
    const CrackTips& ct = w.tips;
    Vec3 u = Vec3::Zero();
    if (ct.first[z + 1] == ct.first[z]) return u;
    const auto& dof = w.elements.nodes[ct.element[z]];  // a virtual element's corners may be phantoms
    std::array<int, 3> corner;
    for (int k = 0; k < 3; ++k) corner[k] = mesh_node(w, dof[k]);
    const int tip = ct.tip[ct.function[ct.first[z]] / 4];  // a zone element's functions are one tip's
    const TipFrame f{ct.point[tip].head<2>(), ct.direction[tip].head<2>()};
    const BranchValues F = branch_functions(f, X, lip);
    for (int a = ct.first[z]; a < ct.first[z + 1]; a += 4) {  // (slot, l): four functions a slot
        const int pair = ct.function[a] / 4, node = ct.node[pair];
        const int k = static_cast<int>(std::find(corner.begin(), corner.end(), node) - corner.begin());
        if (k == 3) continue;  // (a zone element's functions are its corners')
        const BranchValues Fk = branch_functions(f, w.nodes.rest[node].head<2>(), tip_node_lip(w, f.point, f.direction, node));
        for (int l = 0; l < 4; ++l) u.head<2>() += L[k] * (F.f[l] - Fk.f[l]) * b.segment<2>(2 * (4 * pair + l));
    }
    return u;
}

Vec3 front_enrichment(const World& w, const Eigen::VectorXd& b, int z, const Vec3& X, const Eigen::Vector4d& bary, int lip_in) {
    const CrackTips& ct = w.tips;
    Vec3 u = Vec3::Zero();
    if (w.elements.dim != 3 || ct.first[z + 1] == ct.first[z]) return u;
    std::array<int, 4> corner;
    for (int k = 0; k < 4; ++k) corner[k] = mesh_node(w, w.elements.nodes[ct.element[z]][k]);  // a virtual element's may be phantoms
    const int tip = ct.tip[ct.function[ct.first[z]] / 4];  // a zone element's functions are one front's
    const FrontFrame f{ct.point[tip], ct.direction[tip], ct.tangent[tip]};
    const int lip = lip_in != 0 ? lip_in : ct.lip[z] != 0 ? ct.lip[z] : ((X - f.point).dot(f.normal()) >= 0.0 ? 1 : -1);
    const FrontValues F = front_functions(f, X, lip);
    for (int a = ct.first[z]; a < ct.first[z + 1]; a += 4) {  // (slot, l): four functions a slot
        const int pair = ct.function[a] / 4, node = ct.node[pair];
        const int k = static_cast<int>(std::find(corner.begin(), corner.end(), node) - corner.begin());
        if (k == 4) continue;
        const FrontValues Fk = front_functions(f, w.nodes.rest[node], crack_node_lip(w, f.point, f.direction, f.normal(), node));
        for (int l = 0; l < 4; ++l) u += bary[k] * (F.f[l] - Fk.f[l]) * b.segment<3>(3 * (4 * pair + l));
    }
    return u;
}

Vec3 tip_field(const World& w, const Eigen::VectorXd& b, int fe, const Vec2& X, const Vec3& L, int tip, int lip) {
    const CrackTips& ct = w.tips;
    Vec3 x = Vec3::Zero();
    for (int k = 0; k < 3; ++k) x += L[k] * w.nodes.position[w.elements.nodes[fe][k]];
    for (int z = 0; z < ct.zone(); ++z)
        if (ct.element[z] == fe) x += tip_enrichment(w, b, z, X, L, ct.tip[ct.function[ct.first[z]] / 4] == tip ? lip : ct.lip[z]);
    return x;
}

std::array<double, 6> first_edge_params(const World& w, int c) {
    std::array<double, 6> t;
    t.fill(-1.0);
    const auto& n = w.elements.nodes[w.cuts.element[c]];
    for (int p = 0; p < 4; ++p) {
        const int k = w.cuts.point_edge[c][p];
        if (k < 0) continue;
        const Vec3 &a = w.nodes.rest[n[kTetEdges[k][0]]], &b = w.nodes.rest[n[kTetEdges[k][1]]];
        t[k] = (w.cuts.points[c][p] - a).dot(b - a) / (b - a).squaredNorm();
    }
    return t;
}

std::array<double, 6> line_edge_params(const World& w, int c, size_t l) {
    return l < w.cuts.line_edge_t[c].size() ? w.cuts.line_edge_t[c][l] : first_edge_params(w, c);
}

int local_edge_of(const World& w, int f, int a, int b, bool& from_a) {
    const auto& m = w.elements.nodes[f];
    for (int k = 0; k < edge_count(w.elements.dim); ++k) {
        const int i = m[edge_nodes(w.elements.dim, k)[0]], j = m[edge_nodes(w.elements.dim, k)[1]];
        if ((i == a && j == b) || (i == b && j == a)) return from_a = i == a, k;
    }
    return -1;
}

bool recut_allowed(const World& w) {
    const bool wanted = w.cut_state.recut < 0 ? w.elements.dim == 2 : w.cut_state.recut > 0;
    return wanted && (w.elements.dim == 2 || w.elements.dim == 3) && w.quadratic.count() == 0 && !w.snap.enabled && w.tips.follow_radius < 0.0 &&
           w.tips.point.empty();
}

bool cuts_at_turns(const World& w) { return w.elements.dim == 3 && !recut_allowed(w); }

}  // namespace xcut
