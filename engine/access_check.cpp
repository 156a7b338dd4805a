#include "engine/access_check.h"

#include <fmt/format.h>

#include <stdexcept>

#include "engine/fnv_hash.h"

namespace xcut {
namespace {

void hash_surface(Hasher& h, const SurfaceMesh& s) {
    h.all(s.position, s.element, s.bary, s.side, s.triangles, s.triangle_owner, s.cut_face, s.bound_to,
          s.base_triangles, s.base_of, s.pieces_of, s.node_vertex, s.cuts_mapped, s.crossings_mapped, s.recuts_mapped, s.last_rebound);
}

void hash_component(Hasher& h, const World& w, uint32_t bit) {
    switch (bit) {
        case kNodes: return h.all(w.nodes.rest, w.nodes.position, w.nodes.velocity, w.nodes.mass, w.nodes.fixed, w.mesh_nodes);
        case kElements: {
            const Elements& e = w.elements;
            return h.all(e.nodes, e.rest_volume, e.dm_inv, e.rotation, e.material, e.region, e.body, e.weight,
                         w.incidence.offset, w.incidence.entry, w.virtual_incidence.offset, w.virtual_incidence.entry,
                         w.mesh_elements, w.quadratic.nodes, w.quadratic.incidence.offset, w.quadratic.incidence.entry);
        }
        case kForces: {
            const ForceState& f = w.forces;
            h.all(f.element_buffer, f.quadratic_buffer, f.elastic_energy, f.checked_gradient, f.checked_rotation);
            h.bytes(f.force.data(), sizeof(double) * f.force.size());
            h.bytes(f.stiffness_diagonal.data(), sizeof(double) * f.stiffness_diagonal.size());
            return h.bytes(f.last_dv.data(), sizeof(double) * f.last_dv.size());
        }
        case kMetrics: {  // not the systems' wall times, which the scheduler writes
            const StepMetrics& m = w.metrics.current;
            return h.all(m.step, m.time, m.dt, m.dofs, m.cg_iterations, m.newton_iterations, m.cg_residual, m.solve_flag,
                         m.substeps, m.kinetic_energy, m.elastic_energy, m.gravity_work, w.metrics.refactored_steps,
                         w.metrics.substepped_steps, w.metrics.max_substeps, w.metrics.energy_newton_steps, w.metrics.work_in,
                         w.time, w.step);
        }
        case kCutPlan:
            for (const ScriptedCut& c : w.cut_plan.cuts) h.all(c.applied);
            return;
        case kCutEvents:
            for (const CutEvent& e : w.pending_cuts) h.all(e.element, e.crossed, e.level, e.edge_t, e.edge_has_t, e.tool);
            return h.add(w.pending_cuts.size());
        case kXfem: {
            const CutElements& c = w.cuts;
            h.all(c.element, c.fraction_above, c.points, c.point_edge, c.virtual_element, c.crossed, c.opened, c.tool,
                  c.crossed_log, c.cut_of_element, c.lines, c.fragments, c.recut_log);
            h.all(w.virtual_elements.parent, w.virtual_elements.side, w.virtual_elements.element, w.virtual_elements.mask);
            const CrackTips& t = w.tips;
            h.all(t.point, t.direction, t.tangent, t.node, t.tip, t.element, t.lip, t.first, t.moment_first, t.function, t.gradient, t.moment);
            const EnrichedDofs& en = w.enriched;
            return h.all(en.sign, en.enriched, en.front_fixed, en.phantom, en.node_of_phantom, en.phantom_from, en.sign_normal);
        }
        case kTools: {
            const ToolBodies& t = w.tools;
            h.all(t.position, t.orientation, t.velocity, t.reaction_force, t.reaction_torque, t.pose_time);
            h.all(t.cutting_force, t.cutting_torque, t.blade_depth);
            return h.add(t.sweep);
        }
        case kVisual: return hash_surface(h, w.visual);
        case kCollision: return hash_surface(h, w.collision);
        case kLinear: {
            const LinearSystem& A = w.linear;
            return h.all(A.row_offset, A.column, A.diagonal, A.mesh_slot, A.virtual_slot, A.topology, A.value, A.factor_age,
                         A.factorizations, A.symbolic_factorizations, A.extensions, A.method, A.projected_guesses,
                         A.history.solutions.size(), reinterpret_cast<uintptr_t>(A.factor.get()),
                         reinterpret_cast<uintptr_t>(A.amg.get()));
        }
        case kContacts: {
            const Contacts& c = w.contacts;
            return h.all(c.tool, c.vertex, c.element, c.bary, c.normal, c.depth, c.stiffness, c.force);
        }
        case kCutState: {
            const CutState& c = w.cut_state;
            h.all(c.anchored, c.anchor_tip, c.anchor_heel, c.last_tip, c.last_heel, c.quads, c.queued, c.quads_built,
                  c.elements_tested, c.crossings_found, c.elements_split, c.delay_sim, c.split_by_tool, c.mean_edge);
            for (const BladeCut& b : c.blade) h.all(b.front, b.lists[0], b.lists[1], b.lists[2], b.crossing.size(), b.start_element, b.start_exit.mask);
            for (const std::vector<Vec3>& p : c.path) h.all(p);
            for (const std::array<MaterialPoint, 2>& m : c.anchor_material) h.all(m[0].element, m[0].bary, m[0].fragment, m[1].element, m[1].bary, m[1].fragment);
            h.all(c.path_time, c.loop_time, c.loop_with);
            for (const auto& [pair, meet] : c.paths_meet) h.all(meet);
            return;
        }
        case kSnap: {
            const SnapMesh& s = w.snap;
            return h.all(s.snapped, s.split, s.level, s.pieces, s.piece_parent, s.piece_side, s.piece_live, s.extra_root,
                         s.snaps, s.points, s.copies, s.mid_nodes, s.elements_split);
        }
        case kPieces: {
            const Pieces& p = w.pieces;
            h.all(p.topology, p.of_element, p.volume, p.anchored, p.body, p.sliver, p.count, p.initial);
            for (const PieceEvent& e : p.log) h.all(e.step, e.time, e.volume, e.body, e.anchored);
            return;
        }
        case kGrasps: {
            const Grasps& g = w.grasps;
            h.all(g.radius, g.centre, g.close, g.open, g.stiffness, g.state, g.surface, g.held_at_close, g.force,
                  g.peak_force, g.step_work);
            for (size_t i = 0; i < g.vertex.size(); ++i) h.all(g.vertex[i], g.anchor[i]);
            return;
        }
        default: return;
    }
}

/// What a declared write covers: a surfaces bit either surface, a shaped-tools bit the tools.
uint32_t covered(uint32_t writes) {
    if (writes & kSurfaces) writes |= kVisual | kCollision;
    if (writes & kShapedTools) writes |= kTools;
    return writes;
}

}  // namespace

std::vector<uint64_t> component_hashes(const World& world) {
    std::vector<uint64_t> out;
    for (uint32_t bit : kCheckedComponents) {
        Hasher h;
        hash_component(h, world, bit);
        out.push_back(h.h);
    }
    return out;
}

void check_declared_writes(const std::string& system, uint32_t writes, const std::vector<uint64_t>& before,
                           const std::vector<uint64_t>& after) {
    const uint32_t allowed = covered(writes);
    for (size_t k = 0; k < before.size(); ++k)
        if (before[k] != after[k] && !(allowed & kCheckedComponents[k]))
            throw std::logic_error(fmt::format("{} wrote {} without declaring it (it declares {})", system,
                                               component_name(kCheckedComponents[k]), component_list(writes)));
}

}  // namespace xcut
