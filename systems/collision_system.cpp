#include "systems/collision_system.h"

#include <algorithm>
#include <limits>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/detail/gjk_solver_libccd.h>
#include <fcl/narrowphase/detail/traversal/collision/mesh_shape_collision_traversal_node.h>
#include <fcl/narrowphase/detail/traversal/collision_node.h>

#include "systems/kernels/solver/block_sparse.h"
#include "systems/kernels/tool_shape_depth.h"

namespace xcut {

using Bvh = fcl::BVHModel<fcl::AABBd>;  // AABB: a bottom-up refit merges child boxes, O(n)

/// The FCL shape that finds the surface triangles near a tool, and where its centre sits in the tool
/// frame. A mesh tool is found by its bounding box: a surface triangle deep inside a closed mesh meets
/// none of its triangles, so a mesh-mesh test would miss it; the exact inside test and depth come
/// after, per vertex (`penetration`).
struct BroadShape {
    std::shared_ptr<fcl::CollisionGeometryd> geometry;
    Vec3 centre = Vec3::Zero();
};

struct CollisionModel {
    std::shared_ptr<Bvh> surface;
    /// The triangles and vertex count the BVH was built with: FCL refits only the same mesh (an
    /// update with another vertex count writes past its arrays).
    std::vector<std::array<int, 3>> triangles;
    size_t vertices = 0;
    std::vector<BroadShape> tool_shape;  ///< per tool, made on first use
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

BroadShape broad_shape(const ToolShape& s) {
    switch (s.kind) {
        case ToolShape::kSphere: return {std::make_shared<fcl::Sphered>(s.radius), s.centre};
        case ToolShape::kCapsule: return {std::make_shared<fcl::Capsuled>(s.radius, s.length), s.centre};
        case ToolShape::kBox: return {std::make_shared<fcl::Boxd>(2.0 * s.half_extent), s.centre};
        case ToolShape::kMesh: {
            Vec3 lo = Vec3::Constant(std::numeric_limits<double>::max()), hi = -lo;
            for (const Vec3& v : s.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
            return {std::make_shared<fcl::Boxd>(hi - lo), 0.5 * (lo + hi)};
        }
        case ToolShape::kNone: break;
    }
    return {};
}

/// The surface BVH at the current positions: refitted, or rebuilt when its mesh changed (a cut adds
/// vertices and re-makes triangles, sometimes keeping their count: a count alone is no test).
void refit_surface(const SurfaceMesh& s, CollisionModel& m) {
    if (!m.surface || m.vertices != s.position.size() || m.triangles != s.triangles) {
        m.surface = std::make_shared<Bvh>();
        m.surface->beginModel();
        std::vector<fcl::Triangle> tris;
        tris.reserve(s.triangles.size());
        for (const auto& t : s.triangles) tris.emplace_back(t[0], t[1], t[2]);
        m.surface->addSubModel(s.position, tris);
        m.surface->endModel();
        m.triangles = s.triangles, m.vertices = s.position.size();
        return;
    }
    m.surface->beginUpdateModel();
    m.surface->updateSubModel(s.position);
    m.surface->endUpdateModel(true, true);
}

/// Surface triangles overlapping a primitive tool placed at `pose`. FCL's own `collide` copies the
/// whole surface BVH on every call for AABB trees (its generic mesh-shape path); the traversal node
/// is driven here on the model itself: the surface is already in world coordinates (identity tf1),
/// so `initialize` leaves it untouched.
template <typename Shape>
void collide_surface(Bvh& surface, const Shape& shape, const fcl::Transform3d& pose, fcl::CollisionResultd& result) {
    const fcl::detail::GJKSolver_libccd<double> solver;
    const fcl::CollisionRequestd request(1 << 20, false);
    fcl::detail::MeshShapeCollisionTraversalNode<fcl::AABBd, Shape, fcl::detail::GJKSolver_libccd<double>> node;
    fcl::Transform3d identity = fcl::Transform3d::Identity();
    fcl::detail::initialize(node, surface, identity, shape, pose, &solver, request, result);
    fcl::detail::collide(&node);
}

/// Surface triangles overlapping a tool's broad shape (the contacts' `b1` are triangle indices).
void collide_tool(Bvh& surface, const BroadShape& shape, const fcl::Transform3d& pose, fcl::CollisionResultd& result) {
    const fcl::CollisionGeometryd* g = shape.geometry.get();
    switch (g->getNodeType()) {
        case fcl::GEOM_SPHERE: return collide_surface(surface, *static_cast<const fcl::Sphered*>(g), pose, result);
        case fcl::GEOM_CAPSULE: return collide_surface(surface, *static_cast<const fcl::Capsuled*>(g), pose, result);
        case fcl::GEOM_BOX: return collide_surface(surface, *static_cast<const fcl::Boxd*>(g), pose, result);
        default: return;
    }
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
    m.tool_shape.resize(tb.count());
    refit_surface(s, m);
    for (int i = 0; i < tb.count(); ++i) {
        if (!shaped(tb, i)) continue;
        if (!m.tool_shape[i].geometry) m.tool_shape[i] = broad_shape(tb.shape[i]);
        fcl::Transform3d pose = fcl::Transform3d::Identity();
        pose.linear() = tb.orientation[i].toRotationMatrix();
        pose.translation() = tb.position[i];
        pose.translate(m.tool_shape[i].centre);  // FCL shapes are centred on their frame
        fcl::CollisionResultd result;
        collide_tool(*m.surface, m.tool_shape[i], pose, result);
        std::vector<int> candidates;
        for (size_t k = 0; k < result.numContacts(); ++k)
            for (int v : s.triangles[result.getContact(k).b1]) candidates.push_back(s.source_vertex(v));  // a copy: its vertex
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
    // The contacts add to the blades' cutting resistance (systems/cut/cutting_force.h), if any.
    const bool cutting = static_cast<int>(tb.cutting_force.size()) == tb.count();
    tb.reaction_force = cutting ? tb.cutting_force : std::vector<Vec3>(tb.count(), Vec3::Zero());
    tb.reaction_torque = cutting ? tb.cutting_torque : std::vector<Vec3>(tb.count(), Vec3::Zero());
    Eigen::VectorXd& f = w.forces.force;
    Eigen::VectorXd& held = w.forces.held_force;
    Eigen::VectorXd& diag = w.forces.stiffness_diagonal;
    const bool diagonal = stiffness_diagonal_used(w);  // else it is not made this step: nothing to add to
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
            if (held.size() == f.size()) held.segment<3>(3 * nodes[a]) += wa * c.force[k];
            if (diagonal) diag.segment<3>(3 * nodes[a]) += wa * wa * c.stiffness[k] * n.cwiseProduct(n);
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

namespace {

/// The penalty contacts' term of the step (systems/step_term.h): K_c between each contact's element
/// nodes, held at the step's start (contacts are found once a step).
class ContactTerm final : public SerialHeldTerm {
public:
    const char* name() const override { return "contact"; }
    bool active(const World& world) const override { return world.contacts.count() > 0; }
    void add_product(const World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out) const override {
        add_contact_stiffness_product(world, p, out);
    }
    /// K_c = k (w_a w_b) n n^T between the element's nodes, scaled.
    void add_scattered(const World& w, double scale, LinearSystem& A) const override {
        const Contacts& c = w.contacts;
        const int npe = w.elements.nodes_per_element();
        for (int k = 0; k < c.count(); ++k) {
            const auto& nodes = w.elements.nodes[c.element[k]];
            const Eigen::Matrix3d nn = c.stiffness[k] * c.normal[k] * c.normal[k].transpose();
            for (int a = 0; a < npe; ++a)
                for (int b = 0; b < npe; ++b) {
                    const int blk = find_block(A, nodes[a], nodes[b]);
                    if (blk < 0) throw std::logic_error("contact on an element outside the linear system's pattern");
                    block_at(A, blk) += scale * c.bary[k][a] * c.bary[k][b] * nn;
                }
        }
    }
};

}  // namespace

std::shared_ptr<StepTerm> contact_step_term() { return std::make_shared<ContactTerm>(); }

SystemDesc collision_system(std::shared_ptr<CollisionModel> model) {
    return {"CollisionSystem", kNodes | kElements | kForces | kShapedTools | kCollision, kForces | kTools | kContacts,
            [model](World& w) {
                detect_contacts(w, *model);
                apply_contact_forces(w);
            }};
}

}  // namespace xcut
