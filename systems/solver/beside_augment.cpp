#include "systems/solver/beside_augment.h"

#include <algorithm>
#include <array>
#include <utility>

#include "engine/parallel.h"
#include "systems/solver/beside_factor.h"

namespace xcut {
namespace {

/// Right-hand sides a sparse forward solve carries side by side. Each column's reach ends in the
/// large supernodes at the top, which a wider pass reads once for more columns but over a larger
/// joint reach: with a supernode's rows gathered (LowerFactor::eliminate_tail) the narrow passes
/// win. Measured (the solves of a blade's front over 130 steps summed, two runs each, 2026-12-07):
/// the 1 mm skin 151-164 ms at 2, 159-164 at 1, 166-190 at 4, 220-274 at 8, 315-341 at 16; the
/// default skin 19.5, 21.4 and 23.4 ms at 2, 4 and 8.
constexpr int kSolveWidth = 2;

/// X_S's column c . v (v dense, in the factor's order).
double column_dot(const BesideAugment& b, int c, const Eigen::VectorXd& v) { return sparse_column_dot(b.x_start, b.x_row, b.x_value, c, v); }

/// X_S = L^-1 P I_S for S = `rows` (sorted) and G = X_S^T X_S. The columns of rows S held before,
/// over the same factor (`same_factor`), are kept with their entries of G: a column's solve
/// depends on its row alone (SparseForward's elimination visits its reach in increasing order
/// whatever columns share the pass), so kept and solved again are the same bits. A tip entering
/// the next cell keeps the rows of the nodes the two cells share. The rest are solved kSolveWidth
/// columns a sparse solve (each column of L on their joint reach read once for all of them).
void solve_rows(const LowerFactor& lf, const std::vector<int>& rows, bool same_factor, BesideAugment& b) {
    const int n = static_cast<int>(rows.size());
    std::vector<int> was(n, -1), fresh;  // a row's column in the old S; the rows to solve
    for (int c = 0; c < n; ++c) {
        const auto it = std::lower_bound(b.s_rows.begin(), b.s_rows.end(), rows[c]);
        if (same_factor && it != b.s_rows.end() && *it == rows[c]) was[c] = static_cast<int>(it - b.s_rows.begin());
        else fresh.push_back(c);
    }
    // The fresh rows' solves, kSolveWidth columns a pass, the passes on the threads (each its own
    // work vectors), their columns then appended in the passes' order.
    const int passes = static_cast<int>((fresh.size() + kSolveWidth - 1) / kSolveWidth);
    std::vector<SparseColumns> solved(passes);
    parallel_for_uneven_scratch(passes, [&] { return SparseForward<kSolveWidth>(lf); }, [&](int q, SparseForward<kSolveWidth>& solver) {
        const size_t first = static_cast<size_t>(q) * kSolveWidth;
        const int width = static_cast<int>(std::min<size_t>(kSolveWidth, fresh.size() - first));
        for (int c = 0; c < width; ++c) {
            double entry[kSolveWidth] = {};
            entry[c] = 1.0;
            solver.add(rows[fresh[first + c]], entry);
        }
        solver.solve();
        take_columns(solver, width, solved[q]);
        solver.clear();
    });
    std::vector<int> solved_start{0}, solved_row;
    std::vector<double> solved_value;
    for (const SparseColumns& pass : solved) append_columns(pass, solved_start, solved_row, solved_value);
    const std::vector<int> old_start = std::move(b.x_start), old_row = std::move(b.x_row);
    const std::vector<double> old_value = std::move(b.x_value);
    const Eigen::MatrixXd old_G = std::move(b.G), old_F = std::move(b.F);
    b.s_rows = rows;
    b.x_start.assign(1, 0), b.x_row.clear(), b.x_value.clear();
    const auto append = [&](const std::vector<int>& start, const std::vector<int>& row, const std::vector<double>& value, int q) {
        b.x_row.insert(b.x_row.end(), row.begin() + start[q], row.begin() + start[q + 1]);
        b.x_value.insert(b.x_value.end(), value.begin() + start[q], value.begin() + start[q + 1]);
        b.x_start.push_back(static_cast<int>(b.x_row.size()));
    };
    for (int c = 0, next = 0; c < n; ++c)
        was[c] >= 0 ? append(old_start, old_row, old_value, was[c]) : append(solved_start, solved_row, solved_value, next++);
    // G's row c up to its diagonal on the threads: entry (c, d), d <= c, and its mirror are row c's
    // alone; a kept row whose columns so far are all kept copies them without a dot.
    std::vector<char> kept_so_far(n);
    for (int c = 0; c < n; ++c) kept_so_far[c] = was[c] >= 0 && (c == 0 || kept_so_far[c - 1]);
    b.G.resize(n, n);
    parallel_for_uneven_scratch(n, [&] { return Eigen::VectorXd(Eigen::VectorXd::Zero(lf.rows())); }, [&](int c, Eigen::VectorXd& w) {
        if (kept_so_far[c]) {
            for (int d = 0; d <= c; ++d) b.G(c, d) = b.G(d, c) = old_G(was[c], was[d]);
            return;
        }
        for (int p = b.x_start[c]; p < b.x_start[c + 1]; ++p) w[b.x_row[p]] = b.x_value[p];
        for (int d = 0; d <= c; ++d)
            b.G(c, d) = b.G(d, c) = was[c] >= 0 && was[d] >= 0 ? old_G(was[c], was[d]) : column_dot(b, d, w);
        for (int p = b.x_start[c]; p < b.x_start[c + 1]; ++p) w[b.x_row[p]] = 0.0;
    });
    // F's columns of the kept rows stay (the phantoms' columns of Y_g are kept as they were made
    // while the factor stays: extend_augment); the new rows' columns are left to phantom_products.
    b.f_fresh.clear();
    if (same_factor && b.f_columns > 0) {
        b.F.resize(b.f_columns, n);
        for (int c = 0; c < n; ++c) {
            if (was[c] >= 0) b.F.col(c) = old_F.col(was[c]);
            else b.f_fresh.push_back(c);
        }
    } else {
        b.f_columns = -1;
    }
    ++b.s_builds;
    b.s_solved += static_cast<int>(fresh.size());
}

/// F = Y_g^T X_S for the phantoms' block g: in full, or (F made before over the same factor) its
/// columns of the rows new in S (f_fresh) and its rows of the phantom columns new since. Each entry
/// is the same dot product whenever it is taken: the same bits as in full.
void phantom_products(const FactorAugment& g, int base, BesideAugment& b) {
    const int n = static_cast<int>(b.s_rows.size()), m = g.columns();
    std::vector<int> columns;  // F's columns to take for its kept rows [0, from)
    int from = b.f_columns;
    if (from < 0 || from > m) {
        from = 0;
        b.F.resize(m, n);
    } else {
        columns = b.f_fresh;
        b.F.conservativeResize(m, n);
    }
    Eigen::VectorXd w = Eigen::VectorXd::Zero(base);
    std::vector<char> fresh(n, 0);
    for (int c : columns) fresh[c] = 1;
    for (int c = 0; c < n; ++c) {
        if (!fresh[c] && from == m) continue;
        for (int p = b.x_start[c]; p < b.x_start[c + 1]; ++p) w[b.x_row[p]] = b.x_value[p];
        for (int q = fresh[c] ? 0 : from; q < m; ++q) b.F(q, c) = g.column_dot(q, w);
        for (int p = b.x_start[c]; p < b.x_start[c + 1]; ++p) w[b.x_row[p]] = 0.0;
    }
    b.f_columns = m;
    b.f_fresh.clear();
}

}  // namespace

void solve_beside_columns(const LowerFactor& lf, uint64_t factor, const std::vector<int>& rows, BesideAugment& b) {
    solve_rows(lf, rows, false, b);
    b.factor = factor;
}

void take_beside_columns(BesideAugment&& made, BesideAugment& b) {
    b.factor = made.factor;
    b.s_seeded += static_cast<int>(made.s_rows.size());
    b.s_rows = std::move(made.s_rows);
    b.x_start = std::move(made.x_start), b.x_row = std::move(made.x_row), b.x_value = std::move(made.x_value);
    b.G = std::move(made.G);
    b.f_columns = -1, b.f_fresh.clear();  // F is of the factor's phantoms, made at the build
    b.ok = false, b.unbuilt = true;
}

void append_block(BesideBlock& into, const BesideBlock& more, double h_sign) {
    for (const Eigen::Triplet<double>& t : more.coupling) into.coupling.emplace_back(into.rows + t.row(), t.col(), t.value());
    for (const Eigen::Triplet<double>& t : more.stiffness)
        into.stiffness.emplace_back(into.rows + t.row(), into.rows + t.col(), h_sign * t.value());
    into.rows += more.rows;
}

bool same_block(const BesideBlock& a, const BesideBlock& b) {
    const auto same = [](const std::vector<Eigen::Triplet<double>>& x, const std::vector<Eigen::Triplet<double>>& y) {
        return std::equal(x.begin(), x.end(), y.begin(), y.end(), [](const auto& p, const auto& q) {
            return p.row() == q.row() && p.col() == q.col() && p.value() == q.value();
        });
    };
    return a.rows == b.rows && same(a.coupling, b.coupling) && same(a.stiffness, b.stiffness);
}

bool build_beside_augment(const LinearSystem& A, const LowerFactor& lf, uint64_t factor, const FactorAugment* g,
                          const BesideBlock& block, double stiff_scale, const Eigen::VectorXd& mask, BesideAugment& b) {
    const int base = lf.rows(), m = g ? g->columns() : 0, k = block.rows;
    b.ok = false, b.unbuilt = false;
    if (base + m != 3 * A.rows()) return false;
    // E = T^T (s C^T) by columns: its base rows (a phantom's entry also on its mesh node's row, the
    // jump basis) and its phantom rows.
    std::vector<std::array<double, 3>> e_base;  // (row, amplitude, value)
    Eigen::MatrixXd Z = Eigen::MatrixXd::Zero(m, k);  // E_p, then E_p - Y_g^T Y_E
    std::vector<int> rows;
    const auto on_base = [&](int row, int i, double v) { e_base.push_back({double(row), double(i), v}), rows.push_back(row); };
    for (const Eigen::Triplet<double>& t : block.coupling) {
        const int col = t.col(), i = t.row();
        if (mask[col] == 0.0) continue;
        const double v = stiff_scale * t.value();
        if (col < base) {
            on_base(col, i, v);
            continue;
        }
        const int q = col - base;
        Z(q, i) += v;
        if (g->parent[q] >= 0) on_base(g->parent[q], i, v);
    }
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    if (rows != b.s_rows || factor != b.factor) {
        solve_rows(lf, rows, factor == b.factor, b);
        b.factor = factor;
    }
    const int n = static_cast<int>(rows.size());
    b.E = Eigen::MatrixXd::Zero(n, k);
    for (const auto& [row, i, v] : e_base)
        b.E(std::lower_bound(rows.begin(), rows.end(), int(row)) - rows.begin(), int(i)) += v;
    // D = s H' - Y_E^T Y_E = s H' - E^T G E (H' as the whole system's factor regularizes it:
    // beside_factor.h).
    Eigen::MatrixXd D = Eigen::MatrixXd::Zero(k, k);
    Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(k);
    for (const Eigen::Triplet<double>& t : block.stiffness) {
        D(t.row(), t.col()) += stiff_scale * t.value();
        if (t.row() == t.col()) diagonal[t.row()] += t.value();
    }
    for (int i = 0; i < k; ++i) D(i, i) += diagonal[i] != 0.0 ? stiff_scale * kBesideRegularization * diagonal[i] : 1.0;
    D.noalias() -= b.E.transpose() * (b.G * b.E);
    if (m > 0) {
        if (b.f_columns != m || !b.f_fresh.empty()) phantom_products(*g, base, b);
        Z.noalias() -= b.F * b.E;
        b.V = g->schur.matrixL().solve(Z);
        D.noalias() -= b.V.transpose() * b.V;
    } else {
        b.V.resize(0, k);
    }
    b.indefinite = k > 0 && diagonal.minCoeff() < 0.0;
    if (!b.indefinite) {
        b.schur.compute(D);
        return b.ok = b.schur.info() == Eigen::Success;
    }
    b.schur_indefinite.compute(D);
    // Singular to round-off (a pivot below 1e-14 of the largest) is refused as a failed LLT is.
    const Eigen::VectorXd pivots = b.schur_indefinite.vectorD().cwiseAbs();
    return b.ok = b.schur_indefinite.info() == Eigen::Success && pivots.minCoeff() > 1e-14 * pivots.maxCoeff();
}

void apply_augmented_in_team(const LowerFactor& lf, const FactorAugment* g, const BesideAugment* b, const Eigen::VectorXd& r,
                             Eigen::VectorXd& z, AugmentScratch& sh) {
    const int base = lf.rows(), m = g ? g->columns() : 0, n = b ? static_cast<int>(b->s_rows.size()) : 0;
    if (m > 0) {
#pragma omp single
        {
            sh.g1 = r.head(base);  // T^T r: each new DOF's residual also on its mesh node's
            for (int q = 0; q < m; ++q)
                if (g->parent[q] >= 0) sh.g1[g->parent[q]] += r[base + q];
        }
    }
    Eigen::VectorXd& p = sh.p;
    lf.solve_in_team(m > 0 ? sh.g1 : r, z, sh.lower, [&] {
        Eigen::VectorXd& t = sh.lower.t;  // L^-1 P T^T r
        Eigen::VectorXd y;
        p.resize(m);
        for (int q = 0; q < m; ++q) p[q] = r[base + q] - g->column_dot(q, t);
        if (m > 0) g->schur.matrixL().solveInPlace(p);
        if (b) {
            Eigen::VectorXd xs(n);
            for (int c = 0; c < n; ++c) xs[c] = column_dot(*b, c, t);
            y = -(b->E.transpose() * xs);  // -Y_E^T v: the amplitudes' residual is 0
            if (m > 0) y.noalias() -= b->V.transpose() * p;
            y = b->indefinite ? Eigen::VectorXd(b->schur_indefinite.solve(y)) : Eigen::VectorXd(b->schur.solve(y));
            if (m > 0) p -= b->V * y;
        }
        if (m > 0) {  // a = L_g^-T (p - V y)
            g->schur.matrixU().solveInPlace(p);
            for (int q = 0; q < m; ++q)
                for (int e = g->y_start[q]; e < g->y_start[q + 1]; ++e) t[g->y_row[e]] -= g->y_value[e] * p[q];
        }
        if (b) {
            const Eigen::VectorXd ey = b->E * y;  // Y_E y = X_S (E y)
            for (int c = 0; c < n; ++c)
                for (int e = b->x_start[c]; e < b->x_start[c + 1]; ++e) t[b->x_row[e]] -= b->x_value[e] * ey[c];
        }
    });
    if (m > 0) {
#pragma omp single
        for (int q = 0; q < m; ++q) z[base + q] = p[q] + (g->parent[q] >= 0 ? z[g->parent[q]] : 0.0);
    }
}

void apply_augmented(const LowerFactor& lf, const FactorAugment* g, const BesideAugment* b, const Eigen::VectorXd& r,
                     Eigen::VectorXd& z) {
    AugmentScratch sh;
    lf.prepare(sh.lower);
    z.resize(r.size());
    apply_augmented_in_team(lf, g, b, r, z, sh);
}

}  // namespace xcut
