#include "tools/studies/accuracy_problems.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "engine/io/generators.h"
#include "engine/setup.h"
#include "systems/cut/crack_tip_system.h"
#include "systems/cut/enrichment_system.h"
#include "systems/surface/mapping_system.h"
#include "systems/pipeline.h"
#include "systems/cut/scripted_cut_system.h"
#include "engine/quadratic_setup.h"
#include "systems/cut/snap_cut_system.h"
#include "systems/kernels/quadratic_tet.h"

namespace xcut {
namespace {

GridSpec grid_of(const Vec3& size, const Eigen::Vector3i& cells) {
    GridSpec g;
    g.size = size;
    g.cells = cells;
    return g;
}

World world_with(const MeshData& mesh, const Material& m) {
    World w;
    w.materials.list = {m};
    build_bodies(w, mesh);
    return w;
}

/// Barycentric coordinates of rest point X in element e (its nodes' rest positions).
Eigen::Vector4d barycentric(const World& w, int e, const Vec3& X) {
    const auto& n = w.elements.nodes[e];
    const Vec3& X0 = w.nodes.rest[n[0]];
    Eigen::Vector4d b = Eigen::Vector4d::Zero();
    if (w.elements.dim == 3) {
        Mat3 D;
        for (int k = 0; k < 3; ++k) D.col(k) = w.nodes.rest[n[k + 1]] - X0;
        b.tail<3>() = D.partialPivLu().solve(X - X0);
        b[0] = 1.0 - b[1] - b[2] - b[3];
    } else {
        Eigen::Matrix2d D;
        for (int k = 0; k < 2; ++k) D.col(k) = (w.nodes.rest[n[k + 1]] - X0).head<2>();
        b.segment<2>(1) = D.partialPivLu().solve((X - X0).head<2>());
        b[0] = 1.0 - b[1] - b[2];
    }
    return b;
}

}  // namespace

StaticResult solve_equilibrium(World& world, const Eigen::VectorXd& load) {
    return static_solve(world, xcut_step_terms(), 1e-6, 30, 1e-10, 50000, load);
}

// ---- Problem 3 ---------------------------------------------------------------------------------------

double cantilever_reference(const CantileverSpec& s) {
    const double q = s.density * s.gravity * s.width * s.height, I = s.width * std::pow(s.height, 3) / 12.0;
    const double A = s.width * s.height, G = s.young / 2.0;  // nu = 0
    return q * std::pow(s.length, 4) / (8.0 * s.young * I) + q * s.length * s.length / (2.0 * (5.0 / 6.0) * G * A);
}

World cantilever_world(const CantileverSpec& s, int n) {
    Material m;
    m.young = s.young;
    m.poisson = s.poisson;
    m.density = s.density;
    m.quadratic = s.quadratic;
    m.mean_dilatation = s.mean_dilatation;
    World w;
    w.materials.list = {m};
    w.constraints.boxes.push_back({Vec3(-1, -1, -1), Vec3(1e-9, 1, 1), 7});
    build_bodies(w, generate_box(grid_of(Vec3(s.length, s.width, s.height), Eigen::Vector3i(20 * n, n, n))));
    w.gravity = Vec3(0, 0, -s.gravity);
    return w;
}

double cantilever_tip_deflection(const World& w, const CantileverSpec& s) {
    double sum = 0.0;
    int count = 0;
    for (int i = 0; i < w.mesh_nodes; ++i)
        if (std::abs(w.nodes.rest[i].x() - s.length) < 1e-12) sum -= w.nodes.position[i].z() - w.nodes.rest[i].z(), ++count;
    return sum / count;
}

// ---- Probes --------------------------------------------------------------------------------------------

std::vector<Probe> locate_points(const World& w, const std::vector<Vec3>& points) {
    std::vector<int> candidates;
    if (w.snap.enabled) {
        candidates = live_elements(w);
    } else {
        for (int e = 0; e < w.mesh_elements; ++e) candidates.push_back(e);
    }
    const int npe = w.elements.nodes_per_element();
    std::vector<Eigen::AlignedBox3d> box(candidates.size());
    for (size_t k = 0; k < candidates.size(); ++k)
        for (int a = 0; a < npe; ++a) box[k].extend(w.nodes.rest[w.elements.nodes[candidates[k]][a]]);
    std::vector<Probe> out;
    for (const Vec3& X : points) {
        Probe p;
        p.rest = X;
        double best = -1e300;
        for (size_t k = 0; k < candidates.size(); ++k) {
            const double pad = 1e-6 * box[k].diagonal().norm();
            if (box[k].exteriorDistance(X) > pad) continue;
            const Eigen::Vector4d b = barycentric(w, candidates[k], X);
            double inside = b[0];
            for (int a = 1; a < npe; ++a) inside = std::min(inside, b[a]);
            if (inside > best) best = inside, p.element = candidates[k], p.bary = b;
        }
        if (p.element < 0 || best < -1e-6)
            throw std::runtime_error("locate_points: a sample point lies outside the body");
        const std::vector<int>& cut_of = w.cuts.cut_of_element;
        if (!w.snap.enabled && p.element < static_cast<int>(cut_of.size()) && cut_of[p.element] >= 0) {
            const int c = cut_of[p.element];
            p.element = side_element(w, c, cut_plane_info(w, c), p.bary);
        }
        out.push_back(p);
    }
    return out;
}

Vec3 probe_displacement(const World& w, const Probe& p) {
    const QuadraticElements& q = w.quadratic;  // a quadratic element, or a cut one's side: its 10 nodes
    const int t = p.element < static_cast<int>(q.of_element.size()) ? q.of_element[p.element] : -1;
    const Vec3 x = t >= 0 ? tet10_point(q.nodes[t], p.bary, w.nodes.position.data()) : bound_position(w, p.element, p.bary);
    return x - p.rest;
}

Vec3 probe_displacement(const World& w, const Probe& p, const Eigen::VectorXd& amplitudes) {
    const Vec3 u = probe_displacement(w, p);
    return w.tips.count() > 0 ? u + crack_enrichment_at(w, amplitudes, p.element, p.rest, p.bary) : u;
}

int cut_with_polygon(World& w, const std::vector<Vec3>& polygon, bool progressive) {
    if (w.snap.enabled) {
        prepare_snap_cut(w);
    } else {
        prepare_enrichment(w);
    }
    queue_polygon_cut(w, polygon, progressive && !w.snap.enabled);
    return w.snap.enabled ? apply_snap_events(w) : apply_cut_events(w);
}

// ---- Problem 5 -----------------------------------------------------------------------------------------

Eigen::Vector3i cut_block_cells(const CutBlockSpec& s, int n) {
    const Eigen::Vector3i c(n, std::max(1, static_cast<int>(std::lround(n * s.size.y() / s.size.x()))),
                            std::max(1, static_cast<int>(std::lround(n * s.size.z() / s.size.x()))));
    const double front = (s.size.z() - s.depth) / s.size.z() * c.z();
    if (!s.front_in_cell && std::abs(front - std::round(front)) > 1e-9)
        throw std::invalid_argument("cut block: the crack front must lie on a grid plane of the mesh");
    return c;
}

World cut_block_world(const CutBlockSpec& s, int n) {
    Material m;
    m.young = s.young;
    m.poisson = s.poisson;
    m.density = s.density;
    m.quadratic = s.quadratic;
    m.mean_dilatation = s.mean_dilatation;
    return world_with(generate_box(grid_of(s.size, cut_block_cells(s, n))), m);
}

std::vector<Vec3> cut_block_polygon(const CutBlockSpec& s) {
    const double x = s.cut_x, z0 = s.size.z() - s.depth, z1 = 2.0 * s.size.z(), y0 = -s.size.y(), y1 = 2.0 * s.size.y();
    return {Vec3(x, y0, z0), Vec3(x, y1, z0), Vec3(x, y1, z1), Vec3(x, y0, z1)};
}

void pull_block_ends(World& w, const CutBlockSpec& s) {
    const double eps = 1e-9 * s.size.x();
    for (int i = 0; i < w.nodes.count(); ++i) {
        const double x = w.nodes.rest[i].x();
        if (x > eps && x < s.size.x() - eps) continue;
        w.nodes.fixed[i] = 7;
        w.nodes.position[i] = w.nodes.rest[i] + Vec3(x < 0.5 * s.size.x() ? -s.pull : s.pull, 0.0, 0.0);
    }
}

std::vector<Vec3> pulled_block_displacements(World& w, const CutBlockSpec& spec) {
    pull_block_ends(w, spec);
    if (!solve_equilibrium(w).converged) throw std::runtime_error("the pulled block's static solve did not converge");
    const Eigen::VectorXd amplitudes = w.tips.count() > 0 ? crack_tip_amplitudes(w) : Eigen::VectorXd();
    std::vector<Vec3> u;
    for (const Probe& p : locate_points(w, cut_block_samples(spec))) u.push_back(probe_displacement(w, p, amplitudes));
    return u;
}

std::vector<Vec3> cut_block_samples(const CutBlockSpec& s) {
    std::vector<Vec3> p;
    const Eigen::Vector3i lattice(8, 2, 8);
    for (int k = 0; k < lattice.z(); ++k)
        for (int j = 0; j < lattice.y(); ++j)
            for (int i = 0; i < lattice.x(); ++i)
                p.push_back(s.size.cwiseProduct(Vec3(i + 0.5, j + 0.5, k + 0.5).cwiseQuotient(lattice.cast<double>())));
    const double e = 1e-6 * s.size.x();
    for (int k = 0; k < 4; ++k)
        for (double side : {-1.0, 1.0})
            p.emplace_back(s.cut_x + side * e, 0.5 * s.size.y(), s.size.z() - s.depth * (k + 0.5) / 4.0);
    return p;
}

// ---- Problem 6 -----------------------------------------------------------------------------------------


double edge_crack_reference_cmod(const EdgeCrackSpec& s) {
    const double x = s.crack / s.width, c = std::cos(std::numbers::pi * x / 2.0);
    const double V1 = (1.46 + 3.42 * (1.0 - c)) / (c * c);
    return 4.0 * s.stress * s.crack / s.young * V1;
}

Eigen::Vector3i edge_crack_cells(const EdgeCrackSpec& s, int n) {
    if (n % 2 != 0 || std::abs(s.crack / s.width * n - std::round(s.crack / s.width * n)) > 1e-9)
        throw std::invalid_argument("edge crack: the crack tip must lie on a grid line (even cells across, a / W = 1/2)");
    int rows = static_cast<int>(std::lround(n * s.height / s.width));
    if (rows % 2 == 0) ++rows;
    return Eigen::Vector3i(n, rows, 1);
}

World edge_crack_world(const EdgeCrackSpec& s, int n, bool quadratic) {
    Material m;
    m.young = s.young;
    m.poisson = s.poisson;
    m.density = s.density;
    m.thickness = s.thickness;
    m.quadratic = quadratic;
    return world_with(generate_plate(grid_of(Vec3(s.width, s.height, 0.0), edge_crack_cells(s, n))), m);
}

std::vector<Vec3> edge_crack_segment(const EdgeCrackSpec& s) {
    return {Vec3(-s.width, 0.5 * s.height, 0.0), Vec3(s.crack, 0.5 * s.height, 0.0)};
}

Eigen::VectorXd edge_crack_load(World& w, const EdgeCrackSpec& s) {
    const double eps = 1e-9 * s.height;
    int mid = -1, corner = -1;
    for (int i = 0; i < w.mesh_nodes; ++i) {
        const Vec3& X = w.nodes.rest[i];
        if (std::abs(X.x() - s.width) > eps) continue;
        if (X.y() < eps) corner = i;
        if (X.y() < 0.5 * s.height && (mid < 0 || X.y() > w.nodes.rest[mid].y())) mid = i;
    }
    w.nodes.fixed[mid] |= 3;
    w.nodes.fixed[corner] |= 1;
    Eigen::VectorXd load = Eigen::VectorXd::Zero(3 * w.nodes.count());
    for (int e = 0; e < w.mesh_elements; ++e)
        for (const int* ed : kTriEdges) {
            const int i = w.elements.nodes[e][ed[0]], j = w.elements.nodes[e][ed[1]];
            const double yi = w.nodes.rest[i].y(), yj = w.nodes.rest[j].y();
            const bool top = yi > s.height - eps && yj > s.height - eps, bottom = yi < eps && yj < eps;
            if (!top && !bottom) continue;
            // sigma t times the edge's length, lumped as the edge's shape functions weigh it: 1/2 to each
            // corner of a straight edge; 1/6, 2/3, 1/6 along a quadratic one (its mid-edge node).
            const double f = (top ? 1.0 : -1.0) * s.stress * s.thickness * std::abs(w.nodes.rest[i].x() - w.nodes.rest[j].x());
            const int m = mid_edge_node(w, e, ed[0], ed[1]);
            load[3 * i + 1] += f * (m >= 0 ? 1.0 / 6.0 : 0.5);
            load[3 * j + 1] += f * (m >= 0 ? 1.0 / 6.0 : 0.5);
            if (m >= 0) load[3 * m + 1] += f * 2.0 / 3.0;
        }
    return load;
}

double edge_crack_cmod(World& w, const EdgeCrackSpec& s) {
    const double e = 1e-6 * s.width, y = 0.5 * s.height;
    const auto p = locate_points(w, {Vec3(0.0, y + e, 0.0), Vec3(0.0, y - e, 0.0)});
    const Eigen::VectorXd amplitudes = w.tips.count() > 0 ? step_tip_amplitudes(w) : Eigen::VectorXd();
    return probe_displacement(w, p[0], amplitudes).y() - probe_displacement(w, p[1], amplitudes).y();
}

}  // namespace xcut
