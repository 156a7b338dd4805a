#pragma once
// The step-operator seam: how a contribution to the implicit Euler step (paper §4.3) offers itself to
// the SolverSystem, which never names the system it comes from (SOFA's force fields: addForce,
// addDForce, addKToMatrix, walked by the ODE solver).
//
//   A = mass_scale M + stiff_scale sum_t K_t,   b from f = sum_t f_t,
//
// with mass_scale = 1 + h alpha and stiff_scale = h^2 + h beta (Rayleigh damping D = alpha M + beta
// K). Each term gives its force, its product K_t p (matrix-free, on the calling thread or inside an
// OpenMP team) and its part of the assembled A. The elastic term comes from the ForceSystem
// (systems/force_system.h), the penalty contacts from the CollisionSystem (systems/collision_system.h);
// the mass M is the nodes' own (no system's). The pipeline (systems/pipeline.h) hands the list to
// the solver.
//
// Order is part of the contract, so a step gives the same bits as before the seam: the first term
// writes the force and the product, the others add; in the assembled A the row terms fill each
// block row (the first writes), the mass is added to the diagonal, then the scattered terms add.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "engine/world.h"

namespace xcut {

/// The sparse system a term kept beside the assembly is the Schur complement of: its stiffness is
/// K_t = -C^T H^-1 C, with C (rows x 3 per DOF node) and H (rows x rows, symmetric positive
/// semi-definite) sparse, as the term is linearized now. The full matrix [A, s C^T; s C, s H] has
/// A + s K_t as its Schur complement, so its factor preconditions CG on A + s K_t exactly
/// (systems/solver/beside_factor.h). Entries as triplets (row, column, value); H's both triangles.
struct BesideBlock {
    int rows = 0;
    std::vector<Eigen::Triplet<double>> coupling;  ///< C [N/m^1.5 or the term's units]
    std::vector<Eigen::Triplet<double>> stiffness; ///< H
};

class StepTerm {
public:
    virtual ~StepTerm() = default;
    virtual const char* name() const = 0;
    /// Whether it contributes to this world now (contacts: this step has some).
    virtual bool active(const World& world) const = 0;
    /// Held terms keep the linearization of the step's start when the state moves within the step
    /// (Newton iterations, substeps): their force is f_0 - K_t (x - x_n) (penalty contact, whose
    /// contacts are found once a step); the others are re-evaluated at the current positions.
    virtual bool held() const { return false; }
    /// Re-evaluates what the term is linearized about at the current positions (the rotations).
    virtual void linearize(World&) {}
    /// Its force at the current positions and linearization into world.forces.force (and the
    /// energy): written when `first`, else added. Not called for held terms.
    virtual void force(World&, bool /*first*/) {}
    /// Sizes what its products need before a team calls product_in_team.
    virtual void prepare_product(World&) {}
    /// out = K_t p when `first` (out sized here), else out += K_t p.
    virtual void product(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out, bool first) = 0;
    /// The same, called by every thread of an OpenMP team (out sized by the caller).
    virtual void product_in_team(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out, bool first) = 0;
    /// Assembly: a row term fills block row i (zeroed by the first) after prepare_rows; a scattered
    /// term adds stiff_scale K_t after the mass.
    virtual bool by_rows() const { return false; }
    virtual void prepare_rows(const World&, double /*stiff_scale*/) {}
    virtual void add_row(const World&, int /*row*/, LinearSystem&) const {}
    virtual void add_scattered(const World&, double /*stiff_scale*/, LinearSystem&) const {}
    /// A term whose stiffness is of low rank but couples many nodes (the crack tips' condensed
    /// amplitudes) stays out of the assembled A: the assembled methods add its product beside A's
    /// (CG's operator is then the whole A, its preconditioner A's without the term).
    virtual bool beside_assembly() const { return false; }
    /// Such a term may say which sparse system it is the Schur complement of (BesideBlock), at its
    /// current linearization; false if it cannot.
    virtual bool beside_block(World&, BesideBlock&) const { return false; }
    /// Whether it gives one (beside_block), without building it.
    virtual bool gives_beside_block() const { return false; }
    /// A number that changes when the term's own unknowns change (the crack tips' zones are built
    /// again): a factor knows which block it was made for.
    virtual uint64_t beside_version(const World&) const { return 0; }
    /// An assembled term whose stiffness jumps between steps by a change of low rank (the grasps'
    /// jaws closing or opening, a held vertex re-bound by a cut) gives its whole stiffness as a
    /// block, K_t = -C^T H^-1 C (H negative definite for a stiffness that adds): a kept factor made
    /// with another block solves the step's A through the difference beside it
    /// (systems/solver/beside_augment.h), so the jump costs the step no factorization.
    virtual bool gives_jump_block() const { return false; }
    /// Appends its block now to `out` (its rows after out's).
    virtual void jump_block(const World&, BesideBlock&) const {}
    /// A number that changes whenever its jump_block does, but for a change of A's pattern (a cut
    /// re-binds what the block couples only where it adds DOFs): the solver builds the block and
    /// compares it only when this number or the pattern changed.
    virtual uint64_t jump_version(const World&) const { return 0; }
    /// Whether a scheduled system computes its force at the step's start (the elastic term's: the
    /// ForceSystem; the contacts': the CollisionSystem). A term without one (the crack tips) has it
    /// added by the SolverSystem as the step begins (StepOperator::add_start_forces).
    virtual bool from_system() const { return true; }
    /// Once the step is taken (positions final, world.step counted): what the term keeps of the
    /// step's end for the systems after the solver (the crack tips' amplitudes at the new positions,
    /// through the step's own factor).
    virtual void finish_step(World&) {}
    /// Its stored energy at the current positions [J] (a term that is not held: the elements' strain
    /// energy with each rotation taken from the positions, the crack tips' condensed part through
    /// the step's factor), changing nothing stored: the step's energy check
    /// (systems/solver/energy_check.h). Held terms act as external forces, their work bounded apart.
    virtual double energy_now(World&) { return 0.0; }
};

/// A held term whose stiffness product is one serial pass over its own entries (the penalty
/// contacts, the grasps): `add_product` adds K_t p; inside a team one thread makes it.
class SerialHeldTerm : public StepTerm {
public:
    bool held() const override { return true; }
    void product(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out, bool first) override {
        if (first) out.setZero(p.size());
        add_product(world, p, out);
    }
    void product_in_team(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out, bool first) override {
#pragma omp single
        {
            if (first) out.setZero();
            add_product(world, p, out);
        }
    }

protected:
    virtual void add_product(const World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out) const = 0;
};

/// The terms of a step, in order.
struct StepOperator {
    std::vector<std::shared_ptr<StepTerm>> terms;

    /// Every term's linearize (rotations) at the current positions.
    void linearize(World& world) const;
    /// world.forces.force from the terms that are not held (the first writes), at their current
    /// linearization.
    void forces(World& world) const;
    /// linearize, then forces.
    void relinearize(World& world) const;
    /// out = sum_t K_t p over the active terms (p and out 3 per DOF node).
    void stiffness_product(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out) const;
    /// The same from within an OpenMP team, after prepare_product.
    void stiffness_product_in_team(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out) const;
    void prepare_product(World& world) const;
    /// out += sum over the active held terms of K_t p.
    void add_held_product(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out) const;
    /// Whether an active held term contributes now.
    bool any_held(const World& world) const;
    /// Linearizes and adds the force of every active term that no scheduled system computes
    /// (from_system false), at the step's start.
    void add_start_forces(World& world) const;
    /// Every active term's finish_step, once the step is taken.
    void finish_step(World& world) const;
    /// The sum of the active terms' energy_now that are not held [J].
    double energy_now(World& world) const;
    /// Whether an active term is kept beside the assembly now.
    bool any_beside(const World& world) const;
    /// out += scale mask (K_t (mask p)) over the active terms kept beside the assembly; whether any is.
    bool add_beside_product(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out, double scale,
                            const Eigen::VectorXd& mask) const;
    /// The blocks of the active terms that give one (jump_block), stacked in order: the jumping
    /// part of the stiffness A is assembled with now.
    BesideBlock jump_blocks(const World& world) const;
    /// The jumping terms' versions (jump_version) combined, in order.
    uint64_t jump_version(const World& world) const;
    /// The active term kept beside the assembly, if it is the only one and gives its block
    /// (several are not combined); null otherwise.
    StepTerm* block_term(const World& world) const;
};

/// The scales of a backward Euler step of length h [s]: A = mass M + stiffness K, with Rayleigh
/// damping, mass = 1 + h alpha [-], stiffness = h^2 + h beta [s^2].
struct StepScales {
    double mass = 1.0, stiffness = 0.0;
};
inline StepScales step_scales(const SolverSettings& s, double h) {
    return {1.0 + h * s.damping_mass, h * h + h * s.damping_stiffness};
}

/// The 3N mask (1 free, 0 held) from the nodes' fixed flags.
inline Eigen::VectorXd free_mask(const World& world) {
    const Nodes& nodes = world.nodes;
    Eigen::VectorXd mask(3 * nodes.count());
    for (int i = 0; i < nodes.count(); ++i)
        for (int k = 0; k < 3; ++k) mask[3 * i + k] = (nodes.fixed[i] >> k) & 1 ? 0.0 : 1.0;
    return mask;
}

/// Whether the step uses world.forces.stiffness_diagonal, diag(sum_t K_t): the matrix-free jacobi
/// method's preconditioner (or no method chosen yet); the assembled methods take theirs from the
/// matrix. The terms' systems add their part of it on this condition (ForceSystem, CollisionSystem).
inline bool stiffness_diagonal_used(const World& world) {
    const std::string& method = world.linear.method;
    return method.empty() || method == "jacobi";
}

/// Calls f(virtual, k, entry) for every incidence entry of DOF node i: the mesh incidence (k indexes
/// LinearSystem::mesh_slot), then the virtual one (k indexes virtual_slot). Entry: element << 2 | local node.
template <class F>
void for_incident(const World& w, int i, F&& f) {
    if (i < w.mesh_nodes)
        for (int k = w.incidence.offset[i]; k < w.incidence.offset[i + 1]; ++k) f(false, k, w.incidence.entry[k]);
    for (int k = w.virtual_incidence.offset[i]; k < w.virtual_incidence.offset[i + 1]; ++k)
        f(true, k, w.virtual_incidence.entry[k]);
}

}  // namespace xcut
