// A straight crack front in 3D enriched with branch functions (systems/cut/crack_tip_system.h,
// enrich_crack_front): the zone, its parts and their integrals. The step's term, the condensation of
// the amplitudes, is the 2D tip's (crack_tip_system.cpp) with three amplitudes a function.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/parallel.h"
#include "systems/cut/crack_tip_system.h"
#include "systems/kernels/cut_geometry.h"
#include "systems/kernels/front_enrichment.h"
#include "systems/xfem_queries.h"

namespace xcut {
namespace {

/// A cut whose normal is within this cosine of the crack's lies on the crack's plane: its sides are
/// the crack's lips (else each point's side of the plane decides) [-].
constexpr double kSameCrackCos = 0.99;

std::array<Vec3, 4> front_rest_tet(const World& w, int e) {
    const auto& n = w.elements.nodes[e];
    return {w.nodes.rest[n[0]], w.nodes.rest[n[1]], w.nodes.rest[n[2]], w.nodes.rest[n[3]]};
}

/// The lip of a node on the crack's plane behind the front, from its Heaviside sign; 0 elsewhere.
int front_node_lip(const World& w, const FrontFrame& f, int node) { return crack_node_lip(w, f.point, f.direction, f.normal(), node); }

struct FrontPart {
    int element;     ///< force element
    HalfSpace keep;  ///< its part of the mesh element (a zero normal: the whole)
    int lip;         ///< the crack's side it lies on (0: each point's own)
};

/// The force elements of mesh element e: e itself, or the two sides of its cut.
std::vector<FrontPart> front_parts(const World& w, int e, const FrontFrame& f) {
    const std::vector<int>& cut_of = w.cuts.cut_of_element;
    if (e >= static_cast<int>(cut_of.size()) || cut_of[e] < 0) return {{e, HalfSpace{}, 0}};
    const int c = cut_of[e];
    if (c < static_cast<int>(w.cuts.lines.size()) && !w.cuts.lines[c].empty())
        throw std::invalid_argument(fmt::format("crack-front enrichment: element {} is cut more than once (not with a front)", e));
    int count = 0;
    for (int k = 0; k < 4; ++k) count += w.cuts.point_edge[c][k] >= 0;
    const Vec3 normal = chord_normal(w.cuts.points[c].data(), count, 3), origin = w.cuts.points[c][0];
    const std::array<Vec3, 4> X = front_rest_tet(w, e);
    int orient = 1;  // the normal's sign that points to H = +1, from a node the cut did not pass through
    for (int k = 0; k < 4; ++k) {
        const int H = w.enriched.sign[w.elements.nodes[e][k]];
        const double level = (X[k] - origin).dot(normal);
        if (H != 0 && std::abs(level) > 1e-9 * (X[k] - origin).norm()) {
            orient = (level > 0.0) == (H > 0) ? 1 : -1;
            break;
        }
    }
    const double along = normal.dot(f.normal());
    std::vector<FrontPart> parts;
    for (int s = 0; s < 2; ++s) {
        const int ve = w.cuts.virtual_element[c][s], side = orient * w.virtual_elements.side[ve];
        const int lip = std::abs(along) >= kSameCrackCos ? (along * side > 0.0 ? 1 : -1) : 0;
        parts.push_back({w.virtual_elements.element[ve], HalfSpace{origin, side * normal}, lip});
    }
    return parts;
}

}  // namespace

void enrich_crack_front(World& w, const Vec3& point, const Vec3& direction, const Vec3& tangent, const TipZone& zone) {
    if (w.elements.dim != 3) throw std::invalid_argument("crack-front enrichment: 3D meshes only (a 2D mesh takes a tip: enrich_crack_tip)");
    if (w.snap.enabled) throw std::invalid_argument("crack-front enrichment is XFEM's: not with the snapping cutter");
    for (const Material& m : w.materials.list)
        if (m.quadratic) throw std::invalid_argument("crack-front enrichment: linear tetrahedra only (not quadratic ones)");
    if (!(tangent.norm() > 0.0)) throw std::invalid_argument("crack-front enrichment: the front's tangent is zero");
    const Vec3 t = tangent.normalized(), ahead = direction - direction.dot(t) * t;
    if (!(ahead.norm() > 1e-9 * direction.norm()))
        throw std::invalid_argument("crack-front enrichment: the crack's direction is zero or along the front");
    if (!(zone.radius >= 0.0)) throw std::invalid_argument("crack-front enrichment: the zone's radius must be >= 0 m");
    if (zone.front_rule_order < 1 || zone.front_slab_order < 1 || zone.front_conical_order < 1)
        throw std::invalid_argument("crack-front enrichment: the rule's orders must be >= 1");
    const FrontFrame f{point, ahead.normalized(), t};
    std::vector<int> nodes;
    double from = 0.0, to = 0.0;
    for (int e = 0; e < w.mesh_elements; ++e)
        if (w.elements.weight[e] > 0.0 && front_in_tet(front_rest_tet(w, e), f, from, to))
            for (int k = 0; k < 4; ++k) nodes.push_back(w.elements.nodes[e][k]);
    if (nodes.empty())
        throw std::invalid_argument(fmt::format("crack-front enrichment: the front through ({:.6g}, {:.6g}, {:.6g}) m "
                                                "misses the mesh", point.x(), point.y(), point.z()));
    for (int i = 0; i < w.mesh_nodes; ++i)
        if (front_distance(f, w.nodes.rest[i]) <= zone.radius) nodes.push_back(i);
    const std::vector<int> pair_of = add_tip(w, f.point, f.direction, f.tangent, nodes);
    struct Job {
        int e;
        std::vector<int> slots;
        std::array<int, 4> lip;
        FrontPart part;
    };
    std::vector<Job> jobs;  // the zone's parts in order; their integrals on the threads, appended in order
    for (int e = 0; e < w.mesh_elements; ++e) {
        std::vector<int> slots = enriched_slots(w, e, pair_of);
        if (slots.empty()) continue;
        std::array<int, 4> lip{};
        for (int k = 0; k < 4; ++k) lip[k] = front_node_lip(w, f, w.elements.nodes[e][k]);
        for (const FrontPart& part : front_parts(w, e, f)) jobs.push_back({e, slots, lip, part});
    }
    std::vector<FrontIntegrals> integrals(jobs.size());
    parallel_for_uneven(static_cast<int>(jobs.size()), [&](int j) {
        const Job& job = jobs[j];
        const std::array<Vec3, 4> X = front_rest_tet(w, job.e);
        integrals[j] = front_integrals(X, job.slots, job.lip, f, job.part.lip,
                                       front_tet_rule(X, job.part.keep, f, zone.front_rule_order, zone.front_slab_order,
                                                      zone.front_conical_order));
    });
    for (size_t j = 0; j < jobs.size(); ++j)
        add_zone_element(w, jobs[j].e, jobs[j].part.element, jobs[j].part.lip, jobs[j].slots, pair_of, integrals[j].G,
                         integrals[j].M);
}

Vec3 crack_enrichment_at(const World& w, const Eigen::VectorXd& b, int fe, const Vec3& X, const Eigen::Vector4d& bary) {
    Vec3 u = Vec3::Zero();
    for (int z = 0; z < w.tips.zone(); ++z)
        if (w.tips.element[z] == fe)
            u += w.elements.dim == 3 ? front_enrichment(w, b, z, X, bary)
                                     : tip_enrichment(w, b, z, X.head<2>(), bary.head<3>(), w.tips.lip[z]);
    return u;
}

}  // namespace xcut
