#include "engine/setup.h"

#include <Eigen/LU>

#include "engine/quadratic_setup.h"

namespace xcut {

void build_bodies(World& world, const MeshData& mesh, const std::vector<uint16_t>& material_of_cell) {
    Nodes& nodes = world.nodes;
    const int n = static_cast<int>(mesh.points.size());
    nodes.rest = mesh.points;
    nodes.position = mesh.points;
    nodes.velocity.assign(n, Vec3::Zero());
    nodes.mass.assign(n, 0.0);
    nodes.fixed.assign(n, 0);

    Elements& el = world.elements;
    el.dim = mesh.dim;
    el.nodes = mesh.cells;
    const int m = static_cast<int>(mesh.cells.size());
    el.rest_volume.resize(m);
    el.dm_inv.assign(m, Mat3::Identity());
    el.rotation.assign(m, Mat3::Identity());
    el.material = material_of_cell.empty() ? std::vector<uint16_t>(m, 0) : material_of_cell;
    el.region = mesh.cell_region.empty() ? std::vector<int>(m, 0) : mesh.cell_region;
    el.body.assign(m, 0);
    el.weight.assign(m, 1.0);
    for (int e = 0; e < m; ++e) compute_rest_shape(world, e);
    world.mesh_nodes = n;
    world.mesh_elements = m;
    build_quadratic_elements(world);
    lump_masses(world);
    build_incidence(world);
    apply_constraints(world);
}

int append_element_copy(Elements& el, int e, double weight) {
    const int added = el.count();
    el.nodes.push_back(el.nodes[e]);
    el.rest_volume.push_back(el.rest_volume[e]);
    el.dm_inv.push_back(el.dm_inv[e]);
    el.rotation.push_back(el.rotation[e]);
    el.material.push_back(el.material[e]);
    el.region.push_back(el.region[e]);
    el.body.push_back(el.body[e]);
    el.weight.push_back(weight);
    return added;
}

void compute_rest_shape(World& world, int e) {
    Elements& el = world.elements;
    const Vec3* X = world.nodes.rest.data();
    const auto& c = el.nodes[e];
    if (el.dim == 3) {
        Mat3 Dm;
        for (int k = 0; k < 3; ++k) Dm.col(k) = X[c[k + 1]] - X[c[0]];
        el.rest_volume[e] = Dm.determinant() / 6.0;
        el.dm_inv[e] = Dm.inverse();
    } else {
        Eigen::Matrix2d Dm;
        for (int k = 0; k < 2; ++k) Dm.col(k) = (X[c[k + 1]] - X[c[0]]).head<2>();
        el.rest_volume[e] = 0.5 * Dm.determinant() * world.materials.list[el.material[e]].thickness;
        el.dm_inv[e].setIdentity();
        el.dm_inv[e].topLeftCorner<2, 2>() = Dm.inverse();
    }
}

double element_mass_share(const World& world, int e) {
    const Elements& el = world.elements;
    const Material& m = world.materials.list[el.material[e]];
    // A quadratic element's corners take the HRZ share (systems/kernels/quadratic_tet.h), its
    // mid-edge nodes the rest (quadratic_node_mass); a side of a cut one has all its masses there.
    if (m.quadratic && is_quadratic_side(world, e)) return 0.0;
    const double mass = m.density * el.rest_volume[e] * el.weight[e];
    if (m.quadratic) return mass / (el.dim == 3 ? 36.0 : 19.0);  // kTet10CornerMass, kTri6CornerMass
    return mass / el.nodes_per_element();
}

void relump_nodes(World& world, const std::vector<int>& nodes) {
    const Incidence& mesh = world.incidence;
    const Incidence& virt = world.virtual_incidence;
    for (int i : nodes) {
        double m = 0.0;
        if (i < world.mesh_nodes)
            for (int p = mesh.offset[i]; p < mesh.offset[i + 1]; ++p) m += element_mass_share(world, mesh.entry[p] >> 2);
        for (int p = virt.offset[i]; p < virt.offset[i + 1]; ++p) m += element_mass_share(world, virt.entry[p] >> 2);
        world.nodes.mass[i] = m + quadratic_node_mass(world, i);
    }
}

void lump_masses(World& world) {
    Nodes& nodes = world.nodes;
    const Elements& el = world.elements;
    const int npe = el.nodes_per_element();
    nodes.mass.assign(nodes.count(), 0.0);
    for (int e = 0; e < el.count(); ++e) {
        const double share = element_mass_share(world, e);
        for (int a = 0; a < npe; ++a) nodes.mass[el.nodes[e][a]] += share;
    }
    if (world.quadratic.count() > 0)  // mid-edge nodes, and every vertex of a cut quadratic element's sides
        for (int i = 0; i < nodes.count(); ++i) nodes.mass[i] += quadratic_node_mass(world, i);
}

void apply_constraints(World& world) {
    Nodes& nodes = world.nodes;
    for (int i = 0; i < nodes.count(); ++i) {
        uint8_t flags = world.elements.dim == 2 ? 4 : 0;
        for (const FixedBox& b : world.constraints.boxes) {
            const Vec3& p = nodes.rest[i];
            if ((p.array() >= b.min.array()).all() && (p.array() <= b.max.array()).all()) {
                flags |= b.axes;
                for (int k = 0; k < 3; ++k)
                    if ((b.axes >> k) & 1) nodes.position[i][k] = p[k] + b.displacement[k];
            }
        }
        nodes.fixed[i] = flags;
    }
    for (const FixedSet& set : world.constraints.sets)
        for (int i : set.nodes) {
            nodes.fixed[i] |= set.axes;
            for (int k = 0; k < 3; ++k)
                if ((set.axes >> k) & 1) nodes.position[i][k] = nodes.rest[i][k] + set.displacement[k];
        }
    for (int i : world.constraints.nodes) nodes.fixed[i] = 7;
    constrain_edge_nodes(world);
    // A node no element touches would have zero mass: hold it so the system stays SPD.
    for (int i = 0; i < nodes.count(); ++i)
        if (nodes.mass[i] <= 0.0) nodes.fixed[i] = 7;
}

int add_scalpel(World& world, const std::string& name, const std::vector<Keyframe>& trajectory, const Vec3& tip,
                const Vec3& heel) {
    ToolBodies& tb = world.tools;
    tb.name.push_back(name);
    tb.trajectory.push_back(trajectory);
    tb.position.push_back(trajectory.front().position);
    tb.orientation.push_back(trajectory.front().orientation);
    tb.has_blade.push_back(1);
    tb.blade_tip.push_back(tip);
    tb.blade_heel.push_back(heel);
    tb.blade_back.push_back(Vec3::Zero());
    return tb.count() - 1;
}

}  // namespace xcut
