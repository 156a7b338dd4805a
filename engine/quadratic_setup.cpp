#include "engine/quadratic_setup.h"

#include <algorithm>
#include <stdexcept>

namespace xcut {
namespace {

/// A whole element's mid-edge node share of rho V (HRZ: systems/kernels/quadratic_tet.h).
double edge_mass(const QuadraticElements& q) { return q.planar ? kTri6EdgeMass : kTet10EdgeMass; }

}  // namespace

bool has_quadratic_material(const World& world) {
    for (const Material& m : world.materials.list)
        if (m.quadratic) return true;
    return false;
}

void build_quadratic_elements(World& world) {
    QuadraticElements& q = world.quadratic;
    q = QuadraticElements{};
    if (!has_quadratic_material(world)) return;
    Elements& el = world.elements;
    q.planar = el.dim == 2;
    const int edges_per = q.edge_count();
    q.of_element.assign(world.mesh_elements, -1);
    // Every edge of a quadratic element, as (low node, high node), sorted: the mid-edge nodes are
    // numbered in this order, the same on any machine and thread count.
    std::vector<std::array<int, 2>> edges;
    for (int e = 0; e < world.mesh_elements; ++e) {
        if (!world.materials.list[el.material[e]].quadratic) continue;
        q.of_element[e] = q.count();
        q.element.push_back(e);
        for (int k = 0; k < edges_per; ++k) {
            const int a = el.nodes[e][kTet10Edges[k][0]], b = el.nodes[e][kTet10Edges[k][1]];
            edges.push_back({std::min(a, b), std::max(a, b)});
        }
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    // A linear element on a quadratic one's edge would leave that edge's mid node free to bend it
    // while the linear element holds it straight: the mesh would tear there.
    for (int e = 0; e < world.mesh_elements; ++e) {
        if (q.of_element[e] >= 0) continue;
        for (int k = 0; k < edges_per; ++k) {
            const int a = el.nodes[e][kTet10Edges[k][0]], b = el.nodes[e][kTet10Edges[k][1]];
            if (std::binary_search(edges.begin(), edges.end(), std::array<int, 2>{std::min(a, b), std::max(a, b)}))
                throw std::invalid_argument(
                    "a linear element shares an edge with a quadratic one (materials \"" +
                    world.materials.list[el.material[e]].name + "\" and a quadratic one touch): give touching "
                    "materials the same element");
        }
    }
    Nodes& n = world.nodes;
    q.first_edge_node = n.count();
    q.edge_of_node = edges;
    for (const auto& [a, b] : edges) {
        n.rest.push_back(0.5 * (n.rest[a] + n.rest[b]));
        n.position.push_back(0.5 * (n.position[a] + n.position[b]));
        n.velocity.push_back(0.5 * (n.velocity[a] + n.velocity[b]));
        n.mass.push_back(0.0);
        n.fixed.push_back(0);
    }
    world.mesh_nodes = n.count();
    q.nodes.resize(q.count());
    for (int t = 0; t < q.count(); ++t) {
        const auto& c = el.nodes[q.element[t]];
        for (int a = 0; a < 4; ++a) q.nodes[t][a] = c[a];
        for (int k = 0; k < edges_per; ++k) {
            const std::array<int, 2> key{std::min(c[kTet10Edges[k][0]], c[kTet10Edges[k][1]]), std::max(c[kTet10Edges[k][0]], c[kTet10Edges[k][1]])};
            q.nodes[t][4 + k] = q.first_edge_node + static_cast<int>(std::lower_bound(edges.begin(), edges.end(), key) - edges.begin());
        }
        fill_absent_slots(q, q.nodes[t]);
    }
    build_quadratic_incidence(world);
}

void build_quadratic_incidence(World& world) {
    QuadraticElements& q = world.quadratic;
    const int nodes = world.nodes.count();
    Incidence& inc = q.incidence;
    inc.offset.assign(nodes + 1, 0);
    for (const auto& ids : q.nodes)
        for (int k = 0; k < q.node_count(); ++k) ++inc.offset[ids[q.local(k)] + 1];
    for (int i = 0; i < nodes; ++i) inc.offset[i + 1] += inc.offset[i];
    inc.entry.resize(inc.offset.back());
    std::vector<int> fill(inc.offset.begin(), inc.offset.end() - 1);
    for (int t = 0; t < q.count(); ++t)  // elements in increasing order per node
        for (int k = 0; k < q.node_count(); ++k) {
            const int a = q.local(k);
            inc.entry[fill[q.nodes[t][a]]++] = t * 16 + a;
        }
}

double quadratic_node_mass(const World& world, int i) {
    const QuadraticElements& q = world.quadratic;
    if (q.count() == 0 || i + 1 >= static_cast<int>(q.incidence.offset.size())) return 0.0;
    const Elements& el = world.elements;
    double m = 0.0;
    for (int p = q.incidence.offset[i]; p < q.incidence.offset[i + 1]; ++p) {
        const int t = q.incidence.entry[p] >> 4, a = q.incidence.entry[p] & 15, e = q.element[t];
        const double rho = world.materials.list[el.material[e]].density;
        const int s = t < static_cast<int>(q.side_rule.size()) ? q.side_rule[t] : -1;
        if (s >= 0)
            m += q.side_masses[s][a] * rho * el.rest_volume[e];
        else if (a >= 4)
            m += edge_mass(q) * rho * el.rest_volume[e] * el.weight[e];
    }
    return m;
}

int quadratic_entry(const World& world, int e) {
    const QuadraticElements& q = world.quadratic;
    return q.count() > 0 && e >= 0 && e < static_cast<int>(q.of_element.size()) ? q.of_element[e] : -1;
}

int mid_edge_node(const World& world, int e, int i, int j) {
    const int t = quadratic_entry(world, e);
    if (t < 0) return -1;
    for (int k = 0; k < world.quadratic.edge_count(); ++k)
        if ((kTet10Edges[k][0] == i && kTet10Edges[k][1] == j) || (kTet10Edges[k][0] == j && kTet10Edges[k][1] == i))
            return world.quadratic.nodes[t][4 + k];
    return -1;
}

bool is_quadratic_side(const World& world, int e) {
    const QuadraticElements& q = world.quadratic;
    if (e < world.mesh_elements || e >= static_cast<int>(q.of_element.size())) return false;
    const int t = q.of_element[e];
    return t >= 0 && t < static_cast<int>(q.side_rule.size()) && q.side_rule[t] >= 0;
}

void constrain_edge_nodes(World& world) {
    const QuadraticElements& q = world.quadratic;
    Nodes& n = world.nodes;
    for (size_t k = 0; k < q.edge_of_node.size(); ++k) {
        const int i = q.first_edge_node + static_cast<int>(k), a = q.edge_of_node[k][0], b = q.edge_of_node[k][1];
        const uint8_t both = n.fixed[a] & n.fixed[b] & 7;
        n.fixed[i] |= both;
        for (int c = 0; c < 3; ++c)
            if ((both >> c) & 1) n.position[i][c] = 0.5 * (n.position[a][c] + n.position[b][c]);
    }
}

}  // namespace xcut
