#include "systems/grasp_system.h"

#include <Eigen/Geometry>
#include <stdexcept>

#include "systems/kernels/solver/block_sparse.h"
#include "systems/xfem_queries.h"

namespace xcut {
namespace {

const SurfaceMesh& held_surface(const World& w, int tool) {
    return w.grasps.surface[tool] == 0 ? w.collision : w.visual;
}

/// The jaws of tool i close: every skin vertex within their reach, on material, is held where it is.
void close_jaws(World& w, int i) {
    Grasps& g = w.grasps;
    g.surface[i] = w.collision.vertex_count() > 0 ? 0 : 1;
    const SurfaceMesh& s = held_surface(w, i);
    const Eigen::Quaterniond& q = w.tools.orientation[i];
    const Vec3& p = w.tools.position[i];
    const Vec3 centre = p + q * g.centre[i];
    std::vector<uint8_t> skin(s.vertex_count(), 0);  // the skin as built, not a cut's faces
    for (const auto& t : s.base_triangles)
        for (int v : t) skin[v] = 1;
    for (int v = 0; v < s.vertex_count(); ++v) {
        if (!skin[v] || w.elements.weight[s.element[v]] < kMinHeldWeight) continue;
        const Vec3 x = bound_position(w, s.element[v], s.bary[v]);
        if ((x - centre).norm() > g.radius[i]) continue;
        g.vertex[i].push_back(v);
        g.anchor[i].push_back(q.conjugate() * (x - p));
    }
    g.held_at_close[i] = static_cast<int>(g.vertex[i].size());
    g.state[i] = Grasps::kHolding;
}

void open_jaws(Grasps& g, int i) {
    g.state[i] = Grasps::kReleased;
    g.vertex[i].clear();
    g.anchor[i].clear();
    g.force[i] = Vec3::Zero();
}

template <class F>
void for_held(const World& w, F&& f) {
    const Grasps& g = w.grasps;
    for (int i = 0; i < g.count(); ++i) {
        if (g.state[i] != Grasps::kHolding) continue;
        const SurfaceMesh& s = held_surface(w, i);
        for (size_t k = 0; k < g.vertex[i].size(); ++k)
            if (g.vertex[i][k] < s.vertex_count()) f(i, k, s, g.vertex[i][k]);  // the skin keeps its vertices
    }
}

/// out += K_g p, K_g = sum over held vertices of k w w^T (x) I.
void add_grasp_product(const World& w, const Eigen::VectorXd& p, Eigen::VectorXd& out) {
    const int npe = w.elements.nodes_per_element();
    for_held(w, [&](int i, size_t, const SurfaceMesh& s, int v) {
        const auto& nodes = w.elements.nodes[s.element[v]];
        Vec3 u = Vec3::Zero();
        for (int a = 0; a < npe; ++a) u += s.bary[v][a] * p.segment<3>(3 * nodes[a]);
        u *= w.grasps.stiffness[i];
        for (int a = 0; a < npe; ++a) out.segment<3>(3 * nodes[a]) += s.bary[v][a] * u;
    });
}

class GraspTerm final : public SerialHeldTerm {
public:
    const char* name() const override { return "grasp"; }
    bool active(const World& w) const override {
        for (int i = 0; i < w.grasps.count(); ++i)
            if (w.grasps.state[i] == Grasps::kHolding && !w.grasps.vertex[i].empty()) return true;
        return false;
    }
    void add_product(const World& w, const Eigen::VectorXd& p, Eigen::VectorXd& out) const override {
        add_grasp_product(w, p, out);
    }
    /// Its stiffness as a block (step_term.h): one row per held vertex and axis, C = w^T (x) e_axis
    /// over the vertex's element nodes, H = -1/k, so -C^T H^-1 C = k w w^T (x) I.
    bool gives_jump_block() const override { return true; }
    void jump_block(const World& w, BesideBlock& out) const override {
        const int npe = w.elements.nodes_per_element();
        for_held(w, [&](int i, size_t, const SurfaceMesh& s, int v) {
            const auto& nodes = w.elements.nodes[s.element[v]];
            for (int c = 0; c < 3; ++c, ++out.rows) {
                for (int a = 0; a < npe; ++a)
                    if (s.bary[v][a] != 0.0) out.coupling.emplace_back(out.rows, 3 * nodes[a] + c, s.bary[v][a]);
                out.stiffness.emplace_back(out.rows, out.rows, -1.0 / w.grasps.stiffness[i]);
            }
        });
    }
    /// The held set changes only as jaws close or open (a tool's state, and what it holds).
    uint64_t jump_version(const World& w) const override {
        uint64_t v = 0;
        for (int i = 0; i < w.grasps.count(); ++i) v = (v * 31u + static_cast<uint64_t>(w.grasps.state[i])) * 1000003u + w.grasps.vertex[i].size();
        return v;
    }
    /// k w_a w_b I between the held vertex's element nodes, scaled.
    void add_scattered(const World& w, double scale, LinearSystem& A) const override {
        const int npe = w.elements.nodes_per_element();
        for_held(w, [&](int i, size_t, const SurfaceMesh& s, int v) {
            const auto& nodes = w.elements.nodes[s.element[v]];
            for (int a = 0; a < npe; ++a)
                for (int b = 0; b < npe; ++b) {
                    const int blk = find_block(A, nodes[a], nodes[b]);
                    if (blk < 0) throw std::logic_error("grasp on an element outside the linear system's pattern");
                    block_at(A, blk).diagonal().array() += scale * w.grasps.stiffness[i] * s.bary[v][a] * s.bary[v][b];
                }
        });
    }
};

}  // namespace

void apply_grasps(World& w) {
    Grasps& g = w.grasps;
    ToolBodies& tb = w.tools;
    for (int i = 0; i < g.count(); ++i) {
        if (g.radius[i] > 0.0 && g.state[i] == Grasps::kWaiting && w.time + 1e-12 >= g.close[i]) close_jaws(w, i);
        if (g.state[i] == Grasps::kHolding && w.time + 1e-12 >= g.open[i]) open_jaws(g, i);
    }
    if (!(w.present() & kShapedTools)) {  // no CollisionSystem set the reaction this step: it starts here
        const bool cutting = static_cast<int>(tb.cutting_force.size()) == tb.count();
        tb.reaction_force = cutting ? tb.cutting_force : std::vector<Vec3>(tb.count(), Vec3::Zero());
        tb.reaction_torque = cutting ? tb.cutting_torque : std::vector<Vec3>(tb.count(), Vec3::Zero());
    }
    Eigen::VectorXd& f = w.forces.force;
    Eigen::VectorXd& held_force = w.forces.held_force;
    Eigen::VectorXd& diag = w.forces.stiffness_diagonal;
    const bool diagonal = stiffness_diagonal_used(w);
    const int npe = w.elements.nodes_per_element();
    const double dt = w.solver.dt, beta = w.solver.damping_stiffness;
    for (int i = 0; i < g.count(); ++i) g.force[i] = Vec3::Zero();
    g.step_work = 0.0;
    for_held(w, [&](int i, size_t k, const SurfaceMesh& s, int v) {  // serial, in order: deterministic sums
        const double stiffness = g.stiffness[i];
        const Vec3 held = tb.position[i] + tb.orientation[i] * g.anchor[i][k];
        // The held point's velocity over the step, from the pose it started at (the tool turns too).
        const Keyframe& from = tb.sweep[i].empty() ? Keyframe{0.0, tb.position[i], tb.orientation[i]} : tb.sweep[i].front();
        const Vec3 held_velocity = dt > 0.0 ? Vec3((held - (from.position + from.orientation * g.anchor[i][k])) / dt) : Vec3::Zero();
        const auto& nodes = w.elements.nodes[s.element[v]];
        const Vec3 x = bound_position(w, s.element[v], s.bary[v]);
        const Vec3 xv = bound_value(w, s.element[v], s.bary[v], w.nodes.velocity);
        // The spring, and its share of the Rayleigh damping beta K against the jaws' motion: the step
        // takes beta K v of the vertex (SolverSystem), so its force adds beta k v of the held point.
        const Vec3 spring = stiffness * (held - x);
        const Vec3 pull = spring + beta * stiffness * held_velocity;
        for (int a = 0; a < npe; ++a) {
            const double wa = s.bary[v][a];
            f.segment<3>(3 * nodes[a]) += wa * pull;
            if (held_force.size() == f.size()) held_force.segment<3>(3 * nodes[a]) += wa * pull;
            if (diagonal) diag.segment<3>(3 * nodes[a]).array() += wa * wa * stiffness;
        }
        // The pull on the jaws as the step starts: the spring to where the held point is now (the
        // force above reaches for where it will be) and the relative damping.
        const Vec3 on_jaws = -(spring - dt * stiffness * held_velocity + beta * stiffness * (held_velocity - xv));
        g.force[i] += on_jaws;
        g.step_work += std::abs(pull.dot(held_velocity)) * dt;
        tb.reaction_force[i] += on_jaws;
        tb.reaction_torque[i] += (x - tb.position[i]).cross(on_jaws);
    });
    for (int i = 0; i < g.count(); ++i) g.peak_force[i] = std::max(g.peak_force[i], g.force[i].norm());
}

std::shared_ptr<StepTerm> grasp_step_term() { return std::make_shared<GraspTerm>(); }

SystemDesc grasp_system() {
    return {"GraspSystem", kNodes | kElements | kForces | kTools | kGrasps | kSurfaces, kForces | kTools | kGrasps,
            [](World& w) { apply_grasps(w); }};
}

}  // namespace xcut
