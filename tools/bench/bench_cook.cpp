// Cook's membrane (Cook 1974; the standard test of locking under bending and near incompressibility)
// for `xcut bench --suite locking`: the tapered panel in plane strain, a one-cell-thick slab with
// every node's z held, clamped on its left edge, a shear load on its right edge; against CalculiX's
// CPE8R (tools/reference/calculix_reference.py, problem 14).
#include <Eigen/Geometry>
#include <chrono>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "engine/io/generators.h"
#include "engine/setup.h"
#include "systems/kernels/quadratic_tet.h"
#include "tools/bench/bench_accuracy.h"
#include "tools/bench/bench_locking.h"
#include "tools/studies/accuracy_problems.h"
#include "tools/studies/calculix_reference.h"

namespace xcut {
namespace {

struct CookSpec {
    double scale = 1e-3;      ///< the panel's corners are (0,0), (48,44), (48,60), (0,44) x scale [m]
    double young = 1e5;       ///< [Pa]
    double thickness = 1e-3;  ///< the slab's [m]
    double load = 2.5e-4;     ///< total shear on the right edge [N]: the corner moves ~0.1 % of the panel
};

Vec3 cook_point(const CookSpec& c, double xi, double eta, double z) {
    return Vec3(48.0 * c.scale * xi, c.scale * (44.0 * xi + eta * (44.0 - 28.0 * xi)), z);
}

/// The consistent load of the right edge's faces: a linear face's to its corners, a quadratic
/// face's to its mid-edge nodes (its corners' share is zero for a 6-node triangle), each A tau / 3.
Eigen::VectorXd right_edge_load(const World& w, const CookSpec& c) {
    const double x = 48.0 * c.scale, tau = c.load / (16.0 * c.scale * c.thickness);
    Eigen::VectorXd load = Eigen::VectorXd::Zero(3 * w.nodes.count());
    constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
    for (int e = 0; e < w.mesh_elements; ++e) {
        const auto& n = w.elements.nodes[e];
        for (const auto& f : kFaces) {
            bool on = true;
            for (int a : f) on = on && std::abs(w.nodes.rest[n[a]].x() - x) < 1e-12;
            if (!on) continue;
            const Vec3 &p0 = w.nodes.rest[n[f[0]]], &p1 = w.nodes.rest[n[f[1]]], &p2 = w.nodes.rest[n[f[2]]];
            const double share = 0.5 * (p1 - p0).cross(p2 - p0).norm() * tau / 3.0;
            const int t = w.quadratic.count() > 0 ? w.quadratic.of_element[e] : -1;
            for (int k = 0; k < 3; ++k) {
                if (t < 0) {
                    load[3 * n[f[k]] + 1] += share;
                    continue;
                }
                const int a = f[k], b = f[(k + 1) % 3];
                for (int m = 0; m < 6; ++m)
                    if ((kTet10Edges[m][0] == a && kTet10Edges[m][1] == b) || (kTet10Edges[m][0] == b && kTet10Edges[m][1] == a))
                        load[3 * w.quadratic.nodes[t][4 + m] + 1] += share;
            }
        }
    }
    return load;
}

LockingBenchRow cook_run(const CookSpec& c, double poisson, bool quadratic, int n, double reference) {
    GridSpec g;
    g.size = Vec3(1.0, 1.0, 1.0);
    g.cells = Eigen::Vector3i(n, n, 1);
    MeshData mesh = generate_box(g);
    for (Vec3& p : mesh.points) p = cook_point(c, p.x(), p.y(), p.z() * c.thickness);
    Material m;
    m.young = c.young, m.poisson = poisson, m.quadratic = quadratic;
    World w;
    w.materials.list = {m};
    w.constraints.boxes.push_back({Vec3(-1, -1, -1), Vec3(1e-12, 1, 1), 7});
    w.constraints.boxes.push_back({Vec3(-1, -1, -1), Vec3(1, 1, 1), 4});  // plane strain: z held everywhere
    build_bodies(w, mesh);
    const Eigen::VectorXd load = right_edge_load(w, c);
    const auto wall0 = std::chrono::steady_clock::now();
    const double cpu0 = process_cpu_seconds();
    const StaticResult r = solve_equilibrium(w, load);
    LockingBenchRow row;
    row.cpu_s = process_cpu_seconds() - cpu0;
    row.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    if (!r.converged)
        throw std::runtime_error(fmt::format("Cook's membrane ({}, nu {}, n {}): no static equilibrium (residual {:.3g})",
                                             quadratic ? "quadratic" : "linear", poisson, n, r.residual));
    const Vec3 corner = cook_point(c, 1.0, 1.0, 0.0);
    double sum = 0.0;
    int count = 0;
    for (int i = 0; i < w.nodes.count(); ++i)
        if ((w.nodes.rest[i] - corner).head<2>().norm() < 1e-12) sum += w.nodes.position[i].y() - w.nodes.rest[i].y(), ++count;
    row.problem = "cook";
    row.element = quadratic ? "quadratic" : "linear";
    row.poisson = poisson, row.n = n, row.dofs = 3 * w.nodes.count();
    row.newton = r.newton_iterations, row.cg = r.cg_iterations;
    row.value = sum / count, row.reference = reference, row.error = row.value / reference - 1.0;
    return row;
}

}  // namespace

void cook_rows(const LockingBenchOptions& o, const std::string& cache, std::vector<LockingBenchRow>& rows,
               std::vector<std::string>* notes) {
    const CookSpec c;
    const std::vector<double> ratios = o.tiny ? std::vector<double>{0.49} : std::vector<double>{0.3, 0.49};
    const std::vector<int> linear = o.tiny ? std::vector<int>{2, 4} : std::vector<int>{2, 4, 8, 16, 32};
    const std::vector<int> quadratic = o.tiny ? std::vector<int>{2, 4} : std::vector<int>{2, 4, 8, 16};
    const std::vector<int> levels = o.tiny ? std::vector<int>{4, 8, 16} : std::vector<int>{8, 16, 32, 64};
    for (double nu : ratios) {
        const nlohmann::json params = {{"scale", c.scale}, {"young", c.young}, {"poisson", nu}, {"thickness", c.thickness},
                                       {"load", c.load}};
        const ExternalReference ref = calculix_reference(14, params, levels, cache);
        if (!ref.available) {
            if (notes) notes->push_back(fmt::format("Cook nu {}: no reference ({}): not run", nu, ref.why));
            continue;
        }
        const std::string source = fmt::format("CalculiX CPE8R levels {}, extrapolated (own error {:.2g} %)",
                                               fmt::join(ref.levels, " "), 100 * ref.error_estimate);
        if (notes) notes->push_back(fmt::format("Cook nu {}: reference {:.6e} m, {}", nu, ref.values[0], source));
        for (int n : linear) rows.push_back(cook_run(c, nu, false, n, ref.values[0])), rows.back().reference_source = source;
        for (int n : quadratic) rows.push_back(cook_run(c, nu, true, n, ref.values[0])), rows.back().reference_source = source;
    }
}

}  // namespace xcut
