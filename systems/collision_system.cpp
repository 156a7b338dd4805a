#include "systems/collision_system.h"

#include <algorithm>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/collision_object.h>

#include "systems/mapping_system.h"
#include "systems/tool_shape_depth.h"

namespace xcut {

using Bvh = fcl::BVHModel<fcl::AABBd>;  // AABB: a bottom-up refit merges child boxes, O(n)

struct CollisionModel {
    std::shared_ptr<Bvh> surface;
    size_t triangles = 0;  ///< triangle count the BVH was built with
    std::vector<std::shared_ptr<fcl::CollisionGeometryd>> tool_geometry;
};

std::shared_ptr<CollisionModel> make_collision_model() { return std::make_shared<CollisionModel>(); }

namespace {

/// Contacts on a virtual element carrying less than this fraction of its parent (a sliver side, left
/// by a cut through nodes or faces) are dropped: no material is there to push, and its phantom DOFs
/// have almost no mass or stiffness, so a push would fling them.
constexpr double kMinContactWeight = 1e-6;

bool shaped(const ToolBodies& tb, int i) {
    return i < static_cast<int>(tb.shape.size()) && tb.shape[i].kind != ToolShape::kNone;
}

std::shared_ptr<fcl::CollisionGeometryd> fcl_geometry(const ToolShape& s) {
    switch (s.kind) {
        case ToolShape::kSphere: return std::make_shared<fcl::Sphered>(s.radius);
        case ToolShape::kCapsule: return std::make_shared<fcl::Capsuled>(s.radius, s.length);
        case ToolShape::kBox: return std::make_shared<fcl::Boxd>(2.0 * s.half_extent);
        case ToolShape::kMesh: {
            auto m = std::make_shared<Bvh>();
            m->beginModel();
            std::vector<fcl::Triangle> tris;
            for (const auto& t : s.triangles) tris.emplace_back(t[0], t[1], t[2]);
            m->addSubModel(s.vertices, tris);
            m->endModel();
            return m;
        }
        case ToolShape::kNone: break;
    }
    return nullptr;
}

/// The surface BVH at the current positions: refitted, or rebuilt when its triangles changed.
void refit_surface(const SurfaceMesh& s, CollisionModel& m) {
    if (!m.surface || m.triangles != s.triangles.size()) {
        m.surface = std::make_shared<Bvh>();
        m.surface->beginModel();
        std::vector<fcl::Triangle> tris;
        tris.reserve(s.triangles.size());
        for (const auto& t : s.triangles) tris.emplace_back(t[0], t[1], t[2]);
        m.surface->addSubModel(s.position, tris);
        m.surface->endModel();
        m.triangles = s.triangles.size();
        return;
    }
    m.surface->beginUpdateModel();
    m.surface->updateSubModel(s.position);
    m.surface->endUpdateModel(true, true);
}

/// Velocity of a surface vertex from its element's DOF velocities.
Vec3 vertex_velocity(const World& w, const SurfaceMesh& s, int v) {
    Vec3 u = Vec3::Zero();
    for (int a = 0; a < w.elements.nodes_per_element(); ++a) u += s.bary[v][a] * w.nodes.velocity[w.elements.nodes[s.element[v]][a]];
    return u;
}

}  // namespace

void detect_contacts(World& w, CollisionModel& m) {
    Contacts& c = w.contacts;
    c.clear();
    ToolBodies& tb = w.tools;
    SurfaceMesh& s = w.collision;
    if (s.vertex_count() == 0) return;
    m.tool_geometry.resize(tb.count());
    map_cuts(w, s);  // bindings follow this step's splits before any force lands on them
    update_surface_positions(w, s);
    refit_surface(s, m);
    fcl::CollisionObjectd surface(m.surface);
    for (int i = 0; i < tb.count(); ++i) {
        if (!shaped(tb, i)) continue;
        if (!m.tool_geometry[i]) m.tool_geometry[i] = fcl_geometry(tb.shape[i]);
        fcl::Transform3d pose = fcl::Transform3d::Identity();
        pose.linear() = tb.orientation[i].toRotationMatrix();
        pose.translation() = tb.position[i];
        if (tb.shape[i].kind != ToolShape::kMesh) pose.translate(tb.shape[i].centre);  // FCL shapes are centred
        fcl::CollisionObjectd tool(m.tool_geometry[i], pose);
        fcl::CollisionRequestd request(1 << 20, false);
        fcl::CollisionResultd result;
        fcl::collide(&surface, &tool, request, result);
        std::vector<int> candidates;
        for (size_t k = 0; k < result.numContacts(); ++k)
            for (int v : s.triangles[result.getContact(k).b1]) candidates.push_back(v);
        std::sort(candidates.begin(), candidates.end());
        candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
        const Eigen::Matrix3d R = tb.orientation[i].toRotationMatrix();
        for (int v : candidates) {
            if (w.elements.weight[s.element[v]] < kMinContactWeight) continue;
            const Penetration p = penetration(tb.shape[i], R.transpose() * (s.position[v] - tb.position[i]));
            if (!(p.depth > 0.0)) continue;
            c.tool.push_back(i);
            c.vertex.push_back(v);
            c.element.push_back(s.element[v]);
            c.bary.push_back(s.bary[v]);
            c.normal.push_back(R * p.normal);
            c.depth.push_back(p.depth);
            c.stiffness.push_back(tb.contact_stiffness[i]);
            c.force.push_back(Vec3::Zero());
        }
    }
}

void apply_contact_forces(World& w) {
    ToolBodies& tb = w.tools;
    Contacts& c = w.contacts;
    tb.reaction_force.assign(tb.count(), Vec3::Zero());
    tb.reaction_torque.assign(tb.count(), Vec3::Zero());
    Eigen::VectorXd& f = w.forces.force;
    Eigen::VectorXd& diag = w.forces.stiffness_diagonal;
    const int npe = w.elements.nodes_per_element();
    for (int k = 0; k < c.count(); ++k) {  // serial, in contact order: deterministic sums
        const int i = c.tool[k];
        const Vec3& n = c.normal[k];
        const double tool_speed = i < static_cast<int>(tb.velocity.size()) ? n.dot(tb.velocity[i]) : 0.0;
        const double vn = n.dot(vertex_velocity(w, w.collision, c.vertex[k])) - tool_speed;
        const double magnitude = std::max(0.0, c.stiffness[k] * c.depth[k] - tb.contact_damping[i] * vn);
        c.force[k] = magnitude * n;
        const auto& nodes = w.elements.nodes[c.element[k]];
        for (int a = 0; a < npe; ++a) {
            const double wa = c.bary[k][a];
            f.segment<3>(3 * nodes[a]) += wa * c.force[k];
            diag.segment<3>(3 * nodes[a]) += wa * wa * c.stiffness[k] * n.cwiseProduct(n);
        }
        tb.reaction_force[i] -= c.force[k];
        tb.reaction_torque[i] -= (w.collision.position[c.vertex[k]] - tb.position[i]).cross(c.force[k]);
    }
}

void add_contact_stiffness_product(const World& w, const Eigen::VectorXd& p, Eigen::VectorXd& out) {
    const Contacts& c = w.contacts;
    const int npe = w.elements.nodes_per_element();
    for (int k = 0; k < c.count(); ++k) {
        const auto& nodes = w.elements.nodes[c.element[k]];
        Vec3 u = Vec3::Zero();
        for (int a = 0; a < npe; ++a) u += c.bary[k][a] * p.segment<3>(3 * nodes[a]);
        const Vec3 t = c.stiffness[k] * c.normal[k].dot(u) * c.normal[k];
        for (int a = 0; a < npe; ++a) out.segment<3>(3 * nodes[a]) += c.bary[k][a] * t;
    }
}

SystemDesc collision_system(std::shared_ptr<CollisionModel> model) {
    return {"CollisionSystem", kNodes | kElements | kForces | kShapedTools | kCollision, kForces | kTools,
            [model](World& w) {
                detect_contacts(w, *model);
                apply_contact_forces(w);
            }};
}

}  // namespace xcut
