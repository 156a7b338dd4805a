// The `auto` linear method (scene solver.linear): which of cholesky and amg a world's system gets.
#include "systems/solver/linear_solver.h"

#include <unistd.h>

#include <cmath>
#include <fmt/format.h>

#include "systems/solver/fill_estimate.h"

namespace xcut {
namespace {

constexpr int kAutoCholeskyDofs = 10000;  // auto: cholesky up to this many DOFs, amg beyond
/// The same with quadratic elements, whose mid-edge nodes the smoothed aggregation serves poorly:
/// scenes/cantilever.json with "element": "quadratic", 2 threads, 30 steps at 17.6k DOFs: cholesky
/// 12.1 / 13.7 steps/s at nu 0.3 / 0.49, amg 9.3 / 2.2 (60 CG iterations a step); 38.9k DOFs at
/// nu 0.49, 10 steps with the setup: 2.8 against 1.1 (docs/elements.md).
constexpr int kAutoCholeskyQuadraticDofs = 40000;
/// The same limit for nearly incompressible linear tissue (a material at nu >= this), whose
/// volumetric stiffness the smoothed aggregation serves poorly too: scenes/skin_slab.json at 1 mm
/// elements (22.5k DOFs), 2 threads, 200 steps: amg 17.4 / 14.7 / 10.9 steps/s at nu 0.45 / 0.48 /
/// 0.49 (19 / 24 / 38 CG iterations a step) against cholesky's 15.4 / 15.3 / 14.2; at 0.8 mm (48k
/// DOFs) and nu 0.49, 80 steps: cholesky 4.3 against 3.0 steps/s, at 506 MB peak against 272 MB.
constexpr double kAutoCholeskyPoisson = 0.48;

/// Past those DOF counts, cholesky still while the factor's estimated non-zeros stay within this
/// (systems/solver/fill_estimate.h): a thin layer's fill grows like a surface mesh's. Measured (2
/// threads, `xcut run`, 130 steps of the incision; 2026-12-06): the default skin at 1 mm elements
/// (22.5k DOFs, L 4.1 M) cholesky 20-21 ms a step against amg's 45-47; the tissue block at 17.5k
/// tets (10.8k DOFs, L 3.2 M, estimated 4.0) 135 against 93 steps/s; at 29k tets (17.4k DOFs, L
/// 6.3 M) 66 against 60 at 2.9x the memory; the skin at 0.7 mm (L 16.8 M) 120 against 147 ms
/// mean, but its slowest steps twice amg's and 2.3x the memory.
constexpr double kAutoCholeskyNonzeros = 5e6;

double physical_memory_bytes() {
    const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
    return pages > 0 && size > 0 ? double(pages) * double(size) : 8e9;
}

}  // namespace

std::string resolve_linear_method(const World& w, std::string* why) {
    const std::string& asked = w.solver.linear;
    if (asked != "auto") {
        if (why) *why = "set in the scene";
        return asked;
    }
    // Up to kAutoCholeskyDofs the kept factor's 1-5 iterations win (the default scene, 3.9k DOFs:
    // 283 steps/s with cholesky against 149 with amg, xcut bench --suite solver, 2 threads); past
    // it the triangular solves grow like the fill, and the factor's fill decides
    // (kAutoCholeskyNonzeros): a block's grows fast, a thin layer's slowly. Supernodal Cholesky
    // fill of a 3D tet mesh under nested dissection grows like n^(4/3): about 17 n^(4/3) non-zeros
    // for n DOFs, fitted on blocks of 2k-53k tets (15 M at 53k), 12 bytes each; it must fit in a
    // quarter of memory.
    const double dofs = 3.0 * w.nodes.count();
    const double bytes = 12.0 * 17.0 * std::pow(dofs, w.elements.dim == 3 ? 4.0 / 3.0 : 1.1);
    const double budget = 0.25 * physical_memory_bytes();
    bool incompressible = false;  // a linear material near nu 0.5
    for (const Material& m : w.materials.list)
        incompressible = incompressible || (!m.quadratic && m.poisson >= kAutoCholeskyPoisson);
    const int limit = w.quadratic.count() > 0 || incompressible ? kAutoCholeskyQuadraticDofs : kAutoCholeskyDofs;
    const bool small = dofs <= limit, fits = bytes <= budget;
    if (why) {
        *why = !small ? fmt::format("auto: {:.0f} DOFs, over {}", dofs, limit)
                      : fmt::format("auto: factor ~{:.0f} MB {} a quarter of memory ({:.0f} MB)", bytes / 1e6,
                                    fits ? "within" : "beyond", budget / 1e6);
        if (incompressible && dofs > kAutoCholeskyDofs)
            *why += fmt::format("; nu >= {}: cholesky up to {} DOFs", kAutoCholeskyPoisson, limit);
    }
    if (small && fits) return "cholesky";
    if (!small && w.quadratic.count() == 0) {  // a thin layer: its factor's own fill, estimated
        const double nonzeros = estimated_factor_nonzeros(w);
        const bool thin = nonzeros > 0.0 && nonzeros <= kAutoCholeskyNonzeros && 12.0 * nonzeros <= budget;
        if (why)
            *why += fmt::format("; the factor ~{:.1f} M non-zeros (estimated), {} {:.0f} M", nonzeros / 1e6,
                                thin ? "within" : "over", kAutoCholeskyNonzeros / 1e6);
        if (thin) return "cholesky";
    }
    return "amg";
}

}  // namespace xcut
