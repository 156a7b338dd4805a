#include "systems/linear_solver.h"

#include <omp.h>
#include <unistd.h>

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>
#include <cmath>
#include <exception>
#include <fmt/format.h>

#include "systems/force_system.h"
#include "systems/kernels/team_cg.h"
#include "systems/linear_assembly.h"

namespace xcut {

/// CHOLMOD's supernodal factor of the scalar copy of A (symmetric: its CSR arrays are its CSC ones).
struct LinearFactor {
    Eigen::SparseMatrix<double> matrix;
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> llt;
    uint64_t topology = 0;     ///< pattern the symbolic analysis was made for
    bool ok = false;           ///< the last numeric factorization succeeded
    int last_iterations = 0;   ///< CG iterations of the last solve with this factor
};

namespace {

/// Runs f with CHOLMOD's own OpenMP loops kept serial. Debian's CHOLMOD 3 opens 4-thread parallel
/// regions inside its supernodal factorization (CHOLMOD_OMP_NUM_THREADS); on two cores beside the
/// engine's threads their wake-ups cost more than they save (the default scene ran 20-40 % slower).
/// With no parallel level allowed to be active, the runtime runs them on the calling thread.
template <class F>
void without_library_threads(F&& f) {
    const int levels = omp_get_max_active_levels();
    omp_set_max_active_levels(0);
    try {
        f();
    } catch (...) {
        omp_set_max_active_levels(levels);
        throw;
    }
    omp_set_max_active_levels(levels);
}

/// The scalar matrix of A: row 3i + r holds, block by block in column order, entries 3j + c.
void copy_to_scalar(const LinearSystem& A, Eigen::SparseMatrix<double>& S, bool structure) {
    const int n = A.rows();
    if (structure) {
        S.resize(3 * n, 3 * n);
        S.resizeNonZeros(9 * A.blocks());
        int* outer = S.outerIndexPtr();
        int* inner = S.innerIndexPtr();
        outer[0] = 0;
        for (int i = 0; i < n; ++i) {
            const int width = 3 * (A.row_offset[i + 1] - A.row_offset[i]);
            for (int r = 0; r < 3; ++r) {
                int at = outer[3 * i + r];
                for (int b = A.row_offset[i]; b < A.row_offset[i + 1]; ++b)
                    for (int c = 0; c < 3; ++c) inner[at++] = 3 * A.column[b] + c;
                outer[3 * i + r + 1] = outer[3 * i + r] + width;
            }
        }
    }
    double* value = S.valuePtr();
    const int* outer = S.outerIndexPtr();
    for (int i = 0; i < n; ++i)
        for (int r = 0; r < 3; ++r) {
            int at = outer[3 * i + r];
            for (int b = A.row_offset[i]; b < A.row_offset[i + 1]; ++b)
                for (int c = 0; c < 3; ++c) value[at++] = A.value[9 * b + 3 * r + c];
        }
}

/// Factors A (symbolically too when the pattern changed). False if CHOLMOD found it not SPD.
bool factorize(World& w) {
    LinearSystem& A = w.linear;
    if (!A.factor) A.factor = std::make_shared<LinearFactor>();
    LinearFactor& f = *A.factor;
    const bool fresh_pattern = f.topology != A.topology || f.matrix.rows() != 3 * A.rows();
    copy_to_scalar(A, f.matrix, fresh_pattern);
    without_library_threads([&] {
        if (fresh_pattern) f.llt.analyzePattern(f.matrix);
        f.llt.factorize(f.matrix);
    });
    if (fresh_pattern) {
        f.topology = A.topology;
        ++A.symbolic_factorizations;
        A.factor_nonzeros = f.llt.cholmod().lnz;
    }
    ++A.factorizations;
    A.factor_age = 0;
    f.ok = f.llt.info() == Eigen::Success;
    return f.ok;
}

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
    // Supernodal Cholesky fill of a 3D tet mesh under nested dissection grows like n^(4/3): about
    // 17 n^(4/3) non-zeros for n DOFs, fitted on blocks of 2k-53k tets (15 M at 53k), 12 bytes each.
    const double dofs = 3.0 * w.nodes.count();
    const double bytes = 12.0 * 17.0 * std::pow(dofs, w.elements.dim == 3 ? 4.0 / 3.0 : 1.1);
    const double budget = 0.25 * physical_memory_bytes();
    const bool fits = bytes <= budget;
    if (why)
        *why = fmt::format("auto: factor ~{:.0f} MB {} a quarter of memory ({:.0f} MB)", bytes / 1e6,
                           fits ? "within" : "beyond", budget / 1e6);
    return fits ? "cholesky" : "block_jacobi";
}

namespace {

/// The preconditioner a team_cg call does not use: the row-wise one, or the whole-vector one.
void no_rows(int, int, const Eigen::VectorXd&, Eigen::VectorXd&) {}
void no_whole(const Eigen::VectorXd&, Eigen::VectorXd&) {}

/// The jacobi method: matrix-free, A p = mass_scale M p + stiff_scale K p (stiffness_product_in_team),
/// preconditioned by diag(A)^-1 (the paper's solver).
CgResult jacobi_cg(World& w, double mass_scale, double stiff_scale, const Eigen::VectorXd& b, const Eigen::VectorXd& mask,
                   Eigen::VectorXd& x) {
    const int nodes = w.nodes.count();
    Eigen::VectorXd inverse(3 * nodes);
    for (int i = 0; i < 3 * nodes; ++i)
        inverse[i] = 1.0 / (mass_scale * w.nodes.mass[i / 3] + stiff_scale * w.forces.stiffness_diagonal[i]);
    prepare_stiffness_product(w);
    const auto product = [&](const Eigen::VectorXd& p, Eigen::VectorXd& q) {
        stiffness_product_in_team(w, p, q);
#pragma omp for schedule(static)
        for (int i = 0; i < 3 * nodes; ++i) q[i] = mass_scale * w.nodes.mass[i / 3] * p[i] + stiff_scale * q[i];
    };
    const auto jacobi_rows = [&](int lo, int hi, const Eigen::VectorXd& r, Eigen::VectorXd& z) {
        for (int i = 3 * lo; i < 3 * hi; ++i) z[i] = r[i] * inverse[i];
    };
    return team_cg(nodes, product, true, jacobi_rows, no_whole, b, mask, w.solver.cg_tolerance, w.solver.cg_max_iterations, x);
}

}  // namespace

LinearSolve solve_linear(World& w, double mass_scale, double stiff_scale, const Eigen::VectorXd& b,
                         const Eigen::VectorXd& mask, Eigen::VectorXd& x) {
    const SolverSettings& s = w.solver;
    LinearSystem& A = w.linear;
    if (A.method.empty()) A.method = resolve_linear_method(w);
    LinearSolve out;
    const auto accept = [&](const CgResult& cg) {
        out.cg = cg;
        out.converged = cg.relative_residual <= s.cg_tolerance;
        return out.converged;
    };
    const int nodes = w.nodes.count();
    if (A.method == "jacobi") {
        accept(jacobi_cg(w, mass_scale, stiff_scale, b, mask, x));
        return out;
    }
    const bool new_pattern = ensure_linear_pattern(w);
    assemble_step_matrix(w, mass_scale, stiff_scale);
    // CG runs as one team per solve (systems/kernels/team_cg.h): the product and the block Jacobi
    // preconditioner by rows, the Cholesky solve by one thread of the team.
    const auto product = [&](const Eigen::VectorXd& v, Eigen::VectorXd& q) {
#pragma omp for schedule(static)
        for (int i = 0; i < nodes; ++i) linear_multiply_rows(A, i, i + 1, v, q);
    };
    std::vector<double> block_inverse;
    const auto block_jacobi_rows = [&](int lo, int hi, const Eigen::VectorXd& r, Eigen::VectorXd& z) {
        for (int i = lo; i < hi; ++i)
            z.segment<3>(3 * i) =
                Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(block_inverse.data() + 9 * i) * r.segment<3>(3 * i);
    };
    const auto block_jacobi_cg = [&] {
        if (block_inverse.empty()) block_diagonal_inverse(A, block_inverse);
        return team_cg(A.rows(), product, true, block_jacobi_rows, no_whole, b, mask, s.cg_tolerance,
                       s.cg_max_iterations, x);
    };
    if (A.method == "block_jacobi") {
        accept(block_jacobi_cg());
        return out;
    }
    // cholesky / direct: a factor, renewed as the policy says; a failed factorization (not SPD)
    // falls back to block Jacobi for this solve.
    LinearFactor* f = A.factor.get();
    const bool stale = !f || new_pattern || !f->ok || A.method == "direct" || A.factor_age >= s.refactor_every ||
                       f->last_iterations > s.refactor_iterations;
    bool fresh = false;
    if (stale) fresh = factorize(w), f = A.factor.get();
    const auto cholesky = [&](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
        without_library_threads([&] { z = f->llt.solve(r); });
    };
    const auto cholesky_cg = [&] {
        return team_cg(A.rows(), product, false, no_rows, cholesky, b, mask, s.cg_tolerance, s.cg_max_iterations, x);
    };
    const Eigen::VectorXd x0 = x;
    if (f->ok && accept(cholesky_cg())) {
        f->last_iterations = out.cg.iterations;
        ++A.factor_age;
        return out;
    }
    if (!fresh && factorize(w)) {  // an old factor that no longer preconditions: renew it, retry
        x = x0;
        out.refactored = true;
        const int spent = out.cg.iterations;
        accept(cholesky_cg());
        out.cg.iterations += spent;
        f->last_iterations = out.cg.iterations - spent;
        ++A.factor_age;
        if (out.converged) return out;
    }
    if (!A.factor->ok) {  // CHOLMOD: not positive definite; block Jacobi still may converge
        x = x0;
        const int spent = out.cg.iterations;
        accept(block_jacobi_cg());
        out.cg.iterations += spent;
    }
    return out;
}

}  // namespace xcut
