#include "systems/force_system.h"

#include <stdexcept>

#include "engine/parallel.h"
#include "engine/vector_room.h"
#include "systems/kernels/corotational_kernel.h"
#include "systems/kernels/polar_decomposition.h"
#include "systems/kernels/quadratic_elastic.h"

namespace xcut {

LameParameters lame_of(const Material& m, int dim) {
    if (m.quadratic) return {0.0, 0.0};
    return {dim == 3 ? m.lambda() : m.lambda_plane_stress(), m.mu()};
}

namespace {

QuadraticView quadratic_view(const World& w) { return {w.quadratic, w.elements, w.materials}; }

std::array<Vec3, 4> gather_vectors(const std::array<int, 4>& ids, int npe, const Vec3* v) {
    std::array<Vec3, 4> out;
    for (int a = 0; a < 4; ++a) out[a] = a < npe ? v[ids[a]] : Vec3::Zero();
    return out;
}

/// Calls body(e, R_D, dm_inv_D) with the element's matrices at the mesh's dimension D.
template <int D, class Body>
void for_each_element(World& world, Body&& body) {
    Elements& el = world.elements;
    parallel_for(el.count(), [&](int e) {
        const MatD<D> dm_inv = el.dm_inv[e].template topLeftCorner<D, D>();
        body(e, dm_inv);
    });
}

/// The deformation gradients and rotations of tetrahedra first..first+n-1 (n <= 4; a short group
/// repeats its last) at positions x, for extract_rotations4.
void gather_group(const Elements& el, const Vec3* x, int first, int n, std::array<Mat3, 4>& F, std::array<Mat3, 4>& warm) {
    for (int k = 0; k < 4; ++k) {
        const int e = first + std::min(k, n - 1);
        F[k] = edge_matrix<3>(gather_vectors(el.nodes[e], 4, x)) * el.dm_inv[e];
        warm[k] = el.rotation[e];
    }
}

/// Whether the energy check computed the rotations of elements first..first+n-1 at exactly these
/// gradients F (a rotation of a gradient that is not inverted depends on it alone).
bool checked_here(const ForceState& fs, int first, int n, const std::array<Mat3, 4>& F) {
    if (static_cast<int>(fs.checked_gradient.size()) < first + n) return false;
    for (int k = 0; k < n; ++k)
        if (!(fs.checked_gradient[first + k].array() == F[k].array()).all()) return false;
    return true;
}

template <int D>
void update_rotations_dim(World& world) {
    Elements& el = world.elements;
    const Vec3* x = world.nodes.position.data();
    if constexpr (D == 3) {  // four tetrahedra at a time (extract_rotations4); a short last group is padded
        const int count = el.count(), groups = (count + 3) / 4;
        parallel_for(groups, [&](int g) {
            std::array<Mat3, 4> F, warm, R;
            const int first = 4 * g, n = std::min(4, count - first);
            gather_group(el, x, first, n, F, warm);
            if (checked_here(world.forces, first, n, F)) {  // the energy check's rotations of these gradients
                for (int k = 0; k < n; ++k) el.rotation[first + k] = world.forces.checked_rotation[first + k];
                return;
            }
            extract_rotations4(F, warm, R);
            for (int k = 0; k < n; ++k) el.rotation[first + k] = R[k];
        }, kParallelMin / 4);
    } else {
        for_each_element<D>(world, [&](int e, const MatD<D>& dm_inv) {
            const MatD<D> F = edge_matrix<D>(gather_vectors(el.nodes[e], D + 1, x)) * dm_inv;
            el.rotation[e].setIdentity();
            el.rotation[e].template topLeftCorner<2, 2>() = extract_rotation(F);
        });
    }
}

template <int D>
void compute_forces_dim(World& world, std::vector<double>& energy) {
    Elements& el = world.elements;
    auto& buf = world.forces.element_buffer;
    const Vec3* x = world.nodes.position.data();
    for_each_element<D>(world, [&](int e, const MatD<D>& dm_inv) {
        const MatD<D> R = el.rotation[e].template topLeftCorner<D, D>();
        const LameParameters lame = lame_of(world.materials.list[el.material[e]], D);
        energy[e] = corotational_forces<D>(gather_vectors(el.nodes[e], D + 1, x), dm_inv, R,
                                           el.rest_volume[e] * el.weight[e], lame, buf[e]);
    });
}

template <int D>
void stiffness_diagonal_dim(World& world) {
    Elements& el = world.elements;
    auto& buf = world.forces.element_buffer;
    for_each_element<D>(world, [&](int e, const MatD<D>& dm_inv) {
        const MatD<D> R = el.rotation[e].template topLeftCorner<D, D>();
        corotational_stiffness_diagonal<D>(dm_inv, R, el.rest_volume[e] * el.weight[e],
                                           lame_of(world.materials.list[el.material[e]], D), buf[e]);
    });
}

/// Element e's part of K p, into its buffer.
template <int D>
void stiffness_product_element(World& world, const Vec3* pv, int e) {
    Elements& el = world.elements;
    const MatD<D> dm_inv = el.dm_inv[e].template topLeftCorner<D, D>();
    const MatD<D> R = el.rotation[e].template topLeftCorner<D, D>();
    corotational_stiffness_product<D>(gather_vectors(el.nodes[e], D + 1, pv), dm_inv, R, el.rest_volume[e] * el.weight[e],
                                      lame_of(world.materials.list[el.material[e]], D), world.forces.element_buffer[e]);
}

template <int D>
void stiffness_product_dim(World& world, const Eigen::VectorXd& p) {
    const Vec3* pv = reinterpret_cast<const Vec3*>(p.data());
    parallel_for(world.elements.count(), [&](int e) { stiffness_product_element<D>(world, pv, e); });
}

/// Node i's sum of its elements' terms, in incidence order.
Vec3 gathered(const World& world, int i) {
    const Incidence& mesh = world.incidence;
    const Incidence& virt = world.virtual_incidence;
    const auto& buf = world.forces.element_buffer;
    Vec3 s = Vec3::Zero();
    if (i < world.mesh_nodes)
        for (int k = mesh.offset[i]; k < mesh.offset[i + 1]; ++k) s += buf[mesh.entry[k] >> 2][mesh.entry[k] & 3];
    for (int k = virt.offset[i]; k < virt.offset[i + 1]; ++k) s += buf[virt.entry[k] >> 2][virt.entry[k] & 3];
    if (world.quadratic.count() > 0) s += quadratic_gathered(world.quadratic, world.forces.quadratic_buffer, i);
    return s;
}

/// The strain energy at the current positions [J]; with `keep`, the 3D rotations it took and their
/// gradients go to keep's checked_gradient and checked_rotation.
template <int D>
double elastic_energy_dim(const World& world, ForceState* keep = nullptr) {
    const Elements& el = world.elements;
    const Vec3* x = world.nodes.position.data();
    const int count = el.count();
    std::vector<double> energy(count);
    const auto energy_of = [&](int e, const MatD<D>& F, const MatD<D>& R) {
        energy[e] = corotational_energy<D>(F, R, el.rest_volume[e] * el.weight[e], lame_of(world.materials.list[el.material[e]], D));
    };
    if constexpr (D == 3) {  // the rotations as update_rotations takes them, four at a time
        if (keep) resize_with_room(keep->checked_gradient, count), resize_with_room(keep->checked_rotation, count);
        parallel_for((count + 3) / 4, [&](int g) {
            std::array<Mat3, 4> F, warm, R;
            std::array<bool, 4> robust;
            const int first = 4 * g, n = std::min(4, count - first);
            gather_group(el, x, first, n, F, warm);
            extract_rotations4(F, warm, R, &robust);
            for (int k = 0; k < n; ++k) {
                energy_of(first + k, F[k], R[k]);
                if (!keep) continue;
                keep->checked_gradient[first + k] = robust[k] ? Mat3::Constant(std::nan("")) : F[k];
                keep->checked_rotation[first + k] = R[k];
            }
        }, kParallelMin / 4);
    } else {
        parallel_for(count, [&](int e) {
            const MatD<D> F = edge_matrix<D>(gather_vectors(el.nodes[e], D + 1, x)) * el.dm_inv[e].template topLeftCorner<D, D>();
            energy_of(e, F, extract_rotation(F));
        });
    }
    double quadratic = 0.0;
    if (world.quadratic.count() > 0) {  // each element's rotation as update_rotations takes it
        const QuadraticElements& q = world.quadratic;
        const QuadraticView view = quadratic_view(world);
        std::vector<double> part(q.count());
        parallel_for(q.count(), [&](int t) {
            part[t] = quadratic_element_energy(view, x, t, quadratic_rotation(view, x, t, el.rotation[q.element[t]]));
        });
        quadratic = deterministic_sum(q.count(), [&](int t) { return part[t]; });
    }
    return deterministic_sum(count, [&](int e) { return energy[e]; }) + quadratic;
}

void ensure_buffers(World& world) {
    const int n3 = 3 * world.nodes.count();
    ForceState& fs = world.forces;
    if (fs.force.size() != n3) fs.force.setZero(n3);
    if (fs.stiffness_diagonal.size() != n3) fs.stiffness_diagonal.setZero(n3);
    resize_with_room(fs.element_buffer, world.elements.count());  // grown by a split: room for the next few
    resize_with_room(fs.quadratic_buffer, world.quadratic.count());
}

}  // namespace

void gather_element_terms(const World& world, Eigen::VectorXd& out) {
    out.resize(3 * world.nodes.count());
    parallel_for(world.nodes.count(), [&](int i) { out.segment<3>(3 * i) = gathered(world, i); });
}

void update_rotations(World& world) {
    if (world.elements.dim == 3) {
        update_rotations_dim<3>(world);
    } else {
        update_rotations_dim<2>(world);
    }
    // One side of a cut quadratic element turns with its own material (quadratic_rotation).
    const QuadraticElements& q = world.quadratic;
    if (q.side_rule.empty()) return;
    Elements& el = world.elements;
    const QuadraticView view = quadratic_view(world);
    const Vec3* x = world.nodes.position.data();
    parallel_for(static_cast<int>(q.side_rule.size()), [&](int t) {
        if (q.side_rule[t] < 0) return;
        const int e = q.element[t];
        el.rotation[e] = quadratic_rotation(view, x, t, el.rotation[e]);
    });
}

void compute_forces(World& world) {
    ensure_buffers(world);
    ForceState& fs = world.forces;
    std::vector<double> energy(world.elements.count());
    if (world.elements.dim == 3) {
        compute_forces_dim<3>(world, energy);
    } else {
        compute_forces_dim<2>(world, energy);
    }
    const double quadratic = world.quadratic.count() > 0
                                 ? quadratic_forces(quadratic_view(world), world.nodes.position.data(), fs.quadratic_buffer)
                                 : 0.0;
    gather_element_terms(world, fs.force);
    fs.elastic_energy = deterministic_sum(static_cast<int>(energy.size()), [&](int e) { return energy[e]; }) + quadratic;
    const Nodes& nodes = world.nodes;
    parallel_for(nodes.count(), [&](int i) { fs.force.segment<3>(3 * i) += nodes.mass[i] * world.gravity; });

    if (stiffness_diagonal_used(world)) compute_stiffness_diagonal(world);
}

void compute_stiffness_diagonal(World& world) {
    ensure_buffers(world);
    if (world.elements.dim == 3) {
        stiffness_diagonal_dim<3>(world);
    } else {
        stiffness_diagonal_dim<2>(world);
    }
    if (world.quadratic.count() > 0) quadratic_diagonals(quadratic_view(world), world.forces.quadratic_buffer);
    gather_element_terms(world, world.forces.stiffness_diagonal);
}

double elastic_energy_now(const World& world) {
    return world.elements.dim == 3 ? elastic_energy_dim<3>(world) : elastic_energy_dim<2>(world);
}

double elastic_energy_checked(World& world) {
    return world.elements.dim == 3 ? elastic_energy_dim<3>(world, &world.forces) : elastic_energy_dim<2>(world);
}

void elastic_stiffness_product(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out) {
    ensure_buffers(world);
    if (world.elements.dim == 3) {
        stiffness_product_dim<3>(world, p);
    } else {
        stiffness_product_dim<2>(world, p);
    }
    if (world.quadratic.count() > 0)
        quadratic_products(quadratic_view(world), reinterpret_cast<const Vec3*>(p.data()), world.forces.quadratic_buffer);
    gather_element_terms(world, out);
}

namespace {

/// Per element, what its stiffness blocks are made of: the rotated shape gradients r_j = R g_j [1/m]
/// and stiff_scale V lambda, stiff_scale V mu. Since R is a rotation, g_j . g_k = r_j . r_k, so a
/// block needs nothing else (add_corotational_stiffness_block).
struct ElementTerms {
    std::array<Vec3, 4> r;
    double lambda_v = 0.0, mu_v = 0.0;
};

template <int D>
void element_terms(const World& w, double scale, std::vector<ElementTerms>& terms) {
    const Elements& el = w.elements;
    resize_with_room(terms, el.count());  // a split's virtual elements: no copy to fresh pages in its step
    parallel_for(el.count(), [&](int e) {
        ElementTerms& t = terms[e];
        const double volume = scale * el.rest_volume[e] * el.weight[e];
        const LameParameters lame = lame_of(w.materials.list[el.material[e]], D);
        t.lambda_v = volume * lame.lambda, t.mu_v = volume * lame.mu;
        const MatD<D> dm_inv = el.dm_inv[e].template topLeftCorner<D, D>();
        const MatD<D> R = el.rotation[e].template topLeftCorner<D, D>();
        for (int j = 0; j < 4; ++j) {
            t.r[j].setZero();
            if (j <= D) t.r[j].template head<D>() = R * shape_gradient<D>(dm_inv, j);
        }
    }, 2048);
}

/// The elastic term of the step (systems/step_term.h): the corotational stiffness of every element,
/// mesh and virtual, at the rotations of the step's start (paper App. B), and the elastic and
/// gravity forces.
class ElasticTerm final : public StepTerm {
public:
    const char* name() const override { return "elastic"; }
    bool active(const World&) const override { return true; }
    void linearize(World& world) override { update_rotations(world); }
    void force(World& world, bool first) override {
        if (!first) throw std::logic_error("the elastic term writes the step's force: it comes first");
        compute_forces(world);
    }
    void prepare_product(World& world) override { ensure_buffers(world); }
    double energy_now(World& world) override { return elastic_energy_checked(world); }
    void product(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out, bool first) override {
        if (first) return elastic_stiffness_product(world, p, out);
        Eigen::VectorXd own;
        elastic_stiffness_product(world, p, own);
        out += own;
    }
    void product_in_team(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out, bool first) override {
        const Vec3* pv = reinterpret_cast<const Vec3*>(p.data());
        const int elements = world.elements.count(), nodes = world.nodes.count();
#pragma omp for schedule(static)
        for (int e = 0; e < elements; ++e) {
            if (world.elements.dim == 3) stiffness_product_element<3>(world, pv, e);
            else stiffness_product_element<2>(world, pv, e);
        }
        // Every thread sees the same count, so all skip the loop (and its barrier) together when the
        // scene has no quadratic element: the common case adds nothing to each CG iteration.
        const int quadratic = world.quadratic.count();
        if (quadratic > 0) {
            const QuadraticView view = quadratic_view(world);
#pragma omp for schedule(static)
            for (int t = 0; t < quadratic; ++t) quadratic_product_element(view, pv, t, world.forces.quadratic_buffer);
        }
#pragma omp for schedule(static)
        for (int i = 0; i < nodes; ++i) {
            if (first) out.segment<3>(3 * i) = gathered(world, i);
            else out.segment<3>(3 * i) += gathered(world, i);
        }
    }
    bool by_rows() const override { return true; }
    void prepare_rows(const World& world, double stiff_scale) override {
        if (world.elements.dim == 3) element_terms<3>(world, stiff_scale, terms_);
        else element_terms<2>(world, stiff_scale, terms_);
        if (world.quadratic.count() > 0) quadratic_block_terms(quadratic_view(world), stiff_scale, quadratic_terms_);
    }
    /// Row i's blocks, each element's row summed in incidence order (the matrix-free gather's).
    void add_row(const World& world, int i, LinearSystem& A) const override {
        const int dim = world.elements.dim, npe = world.elements.nodes_per_element();
        for_incident(world, i, [&](bool virt, int k, int entry) {
            const ElementTerms& t = terms_[entry >> 2];
            if (t.lambda_v == 0.0 && t.mu_v == 0.0) return;
            const int a = entry & 3;
            const std::array<int, 4>& slot = virt ? A.virtual_slot[k] : A.mesh_slot[k];
            const Vec3 lambda_ra = t.lambda_v * t.r[a], mu_ra = t.mu_v * t.r[a];  // the scales folded in once per row
            for (int b = 0; b < npe; ++b)
                add_corotational_stiffness_block(lambda_ra, mu_ra, t.r[b], dim, A.value.data() + 9 * slot[b]);
        });
        if (world.quadratic.count() > 0) add_quadratic_row(world.quadratic, quadratic_terms_, i, A);
    }

private:
    std::vector<ElementTerms> terms_;
    QuadraticTerms quadratic_terms_;
};

}  // namespace

std::shared_ptr<StepTerm> elastic_step_term() { return std::make_shared<ElasticTerm>(); }

SystemDesc force_system() {
    SystemDesc s{"ForceSystem", kNodes | kElements | kMaterials, kForces | kElements, [](World& w) {
                     update_rotations(w);
                     compute_forces(w);
                     w.forces.held_force.setZero(w.forces.force.size());  // the contacts and grasps add theirs
                 }};
    return s.also_reads(kGravity);
}

}  // namespace xcut
