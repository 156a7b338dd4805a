// Setup of the smoothed-aggregation hierarchy (systems/kernels/solver/amg.h): strength, aggregation,
// tentative and smoothed prolongators, Galerkin products (their sparse products on the systems'
// threads, the same bits for any count).
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "engine/parallel.h"
#include "systems/kernels/solver/amg.h"
#include "systems/kernels/solver/block_sparse.h"

namespace xcut {
namespace {

constexpr int kModes = 6;           // rigid-body modes in 3D: 3 translations, 3 rotations
constexpr int kMaxLevels = 8;
// Strength threshold on the finest level, halved on each coarser one. Vaněk et al. take 0.08; on
// this project's meshes that made aggregates of ~10 nodes and a first coarse level denser than the
// fine one (53k-tet block: 6,030 DOFs, 320 non-zeros a row); 0.04 gives ~25-node aggregates
// (2,430 DOFs, 183 a row) and fewer CG iterations on the thin membrane (xcut bench --suite solver).
constexpr double kTheta = 0.04;
constexpr double kStallRatio = 0.7; // stop when a level keeps more than this share of the DOFs
using NearNull = Eigen::Matrix<double, Eigen::Dynamic, kModes, Eigen::RowMajor>;

/// A level's DOFs grouped in nodes (3 per mesh node on the finest; an aggregate's kept modes below).
struct Grouping {
    std::vector<int> start;  ///< node k's DOFs: [start[k], start[k+1])
    int nodes() const { return static_cast<int>(start.size()) - 1; }
};

/// A level's operator read row by row, `row(i, f)` calling f(column, value) for each stored entry of
/// scalar row i in order. ScalarRows reads a CSR matrix; BlockRows reads the finest level straight
/// from the block system (row 3k + r: block row k's blocks in order, three columns each), the entries
/// and order of its scalar copy (copy_to_scalar), which the setup no longer makes: 15 MB at 53k tets,
/// alive at the setup's peak. Every sum below runs over a row in this order, so both give the same bits.
struct ScalarRows {
    const CsrMatrix& m;
    int rows() const { return static_cast<int>(m.rows()); }
    template <class F>
    void row(int i, F&& f) const {
        for (CsrMatrix::InnerIterator it(m, i); it; ++it) f(static_cast<int>(it.col()), it.value());
    }
    double diagonal(int i) const { return m.coeff(i, i); }
};

struct BlockRows {
    const LinearSystem& m;
    int rows() const { return 3 * m.rows(); }
    template <class F>
    void row(int i, F&& f) const {
        const int k = i / 3, r = i % 3;
        for (int b = m.row_offset[k]; b < m.row_offset[k + 1]; ++b)
            for (int c = 0; c < 3; ++c) f(3 * m.column[b] + c, m.value[9 * b + 3 * r + c]);
    }
    double diagonal(int i) const { return m.value[9 * m.diagonal[i / 3] + 4 * (i % 3)]; }
};

/// The strong neighbours of each node: |A_ij|_F^2 >= theta^2 |A_ii|_F |A_jj|_F (blocks summed over
/// the nodes' DOFs); a node with no coupling at all (a held node) has none.
template <class Rows>
std::vector<std::vector<int>> strong_neighbours(const Rows& A, const Grouping& g, double theta) {
    const int nn = g.nodes();
    std::vector<int> node_of(A.rows());
    for (int k = 0; k < nn; ++k)
        for (int i = g.start[k]; i < g.start[k + 1]; ++i) node_of[i] = k;
    std::vector<double> diagonal(nn, 0.0), sum(nn, 0.0);
    std::vector<int> touched;
    std::vector<std::vector<std::pair<int, double>>> coupling(nn);
    for (int k = 0; k < nn; ++k) {
        touched.clear();
        for (int i = g.start[k]; i < g.start[k + 1]; ++i)
            A.row(i, [&](int col, double value) {
                const int j = node_of[col];
                if (sum[j] == 0.0) touched.push_back(j);
                sum[j] += value * value + 1e-300;  // marks a structural entry
            });
        std::sort(touched.begin(), touched.end());
        for (int j : touched) {
            if (j == k) diagonal[k] = std::sqrt(sum[j]);
            else coupling[k].push_back({j, sum[j]});
            sum[j] = 0.0;
        }
    }
    std::vector<std::vector<int>> out(nn);
    for (int k = 0; k < nn; ++k)
        for (const auto& c : coupling[k])
            if (c.second >= theta * theta * diagonal[k] * diagonal[c.first]) out[k].push_back(c.first);
    return out;
}

/// Standard aggregation (Vaněk et al. 1996, §3): -1 for a node left out (no strong neighbour).
std::vector<int> aggregate(const std::vector<std::vector<int>>& strong, int& count) {
    const int nn = static_cast<int>(strong.size());
    std::vector<int> agg(nn, -1);
    count = 0;
    for (int k = 0; k < nn; ++k) {  // pass 1: roots whose neighbourhood is free
        if (agg[k] >= 0 || strong[k].empty()) continue;
        if (std::any_of(strong[k].begin(), strong[k].end(), [&](int j) { return agg[j] >= 0; })) continue;
        agg[k] = count;
        for (int j : strong[k]) agg[j] = count;
        ++count;
    }
    std::vector<int> first(agg);  // pass 2: join a pass-1 neighbour's aggregate
    for (int k = 0; k < nn; ++k) {
        if (agg[k] >= 0) continue;
        for (int j : strong[k])
            if (first[j] >= 0) {
                agg[k] = first[j];
                break;
            }
    }
    for (int k = 0; k < nn; ++k) {  // pass 3: what is left roots its own with its free neighbours
        if (agg[k] >= 0 || strong[k].empty()) continue;
        agg[k] = count;
        for (int j : strong[k])
            if (agg[j] < 0) agg[j] = count;
        ++count;
    }
    return agg;
}

/// The tentative prolongator and the next level's near-null space and grouping: per aggregate,
/// the members' near-null rows orthonormalised (modified Gram-Schmidt, twice).
CsrMatrix tentative(const NearNull& B, const Grouping& g, const std::vector<int>& agg, int count,
                    NearNull& coarse_B, Grouping& coarse) {
    std::vector<std::vector<int>> members(count);
    for (int k = 0; k < g.nodes(); ++k)
        if (agg[k] >= 0)
            for (int i = g.start[k]; i < g.start[k + 1]; ++i) members[agg[k]].push_back(i);
    std::vector<Eigen::Triplet<double>> entries;
    std::vector<Eigen::VectorXd> q;
    std::vector<Eigen::Matrix<double, 1, kModes>> rrows;
    coarse.start.assign(1, 0);
    for (int a = 0; a < count; ++a) {
        const std::vector<int>& m = members[a];
        Eigen::MatrixXd local(m.size(), kModes);
        for (size_t i = 0; i < m.size(); ++i) local.row(i) = B.row(m[i]);
        q.clear();
        for (int c = 0; c < kModes; ++c) {
            Eigen::VectorXd v = local.col(c);
            const double length = v.norm();
            for (int pass = 0; pass < 2; ++pass)
                for (const auto& u : q) v -= u.dot(v) * u;
            if (length == 0.0 || v.norm() < 1e-8 * length) continue;
            q.push_back(v / v.norm());
        }
        const int col0 = coarse.start.back();
        for (size_t j = 0; j < q.size(); ++j) {
            for (size_t i = 0; i < m.size(); ++i)
                if (q[j][i] != 0.0) entries.emplace_back(m[i], col0 + static_cast<int>(j), q[j][i]);
            rrows.push_back(q[j].transpose() * local);
        }
        coarse.start.push_back(col0 + static_cast<int>(q.size()));
    }
    CsrMatrix P(B.rows(), coarse.start.back());
    P.setFromTriplets(entries.begin(), entries.end());
    coarse_B.resize(static_cast<int>(rrows.size()), kModes);
    for (size_t i = 0; i < rrows.size(); ++i) coarse_B.row(i) = rrows[i];
    return P;
}

/// lambda_max(D^-1 A) [-]: the largest Ritz value of 20 steps of Jacobi-preconditioned CG from a
/// fixed right-hand side (the Lanczos tridiagonal from CG's coefficients: Saad, "Iterative methods
/// for sparse linear systems", 2nd ed., §6.7.3), which approaches it from below far faster than
/// power iteration; capped by Gershgorin's bound max_i sum_j |a_ij| / a_ii, which lies above it.
template <class Rows>
double largest_eigenvalue(const Rows& A, const Eigen::VectorXd& inverse_diagonal) {
    const int n = A.rows();
    double gershgorin = 0.0;
    for (int i = 0; i < n; ++i) {
        double sum = 0.0;
        A.row(i, [&](int, double value) { sum += std::abs(value); });
        gershgorin = std::max(gershgorin, sum * inverse_diagonal[i]);
    }
    Eigen::VectorXd r(n), z(n), p(n), q(n);
    for (int i = 0; i < n; ++i) r[i] = 1.0 + 0.5 * std::sin(1.7 * i);  // fixed, not an eigenvector
    const int steps = std::min(20, n);
    std::vector<double> alpha, beta;
    z = inverse_diagonal.cwiseProduct(r), p = z;
    double rz = r.dot(z);
    for (int k = 0; k < steps && rz > 0.0 && std::isfinite(rz); ++k) {
        parallel_for(n, [&](int i) {  // q = A p, each row summed in its order
            double sum = 0.0;
            A.row(i, [&](int col, double value) { sum += value * p[col]; });
            q[i] = sum;
        });
        const double pq = p.dot(q);
        if (!(pq > 0.0)) break;
        alpha.push_back(rz / pq);
        r -= alpha.back() * q, z = inverse_diagonal.cwiseProduct(r);
        const double next = r.dot(z);
        beta.push_back(next / rz);
        p = z + beta.back() * p;
        rz = next;
    }
    const int m = static_cast<int>(alpha.size());
    if (m == 0) return gershgorin;
    Eigen::MatrixXd T = Eigen::MatrixXd::Zero(m, m);
    for (int j = 0; j < m; ++j) {
        T(j, j) = 1.0 / alpha[j] + (j > 0 ? beta[j - 1] / alpha[j - 1] : 0.0);
        if (j + 1 < m) T(j, j + 1) = T(j + 1, j) = std::sqrt(beta[j]) / alpha[j];
    }
    const double ritz = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(T, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
    return std::min(ritz, gershgorin);
}

template <class Rows>
void smoother_data(AmgLevel& L, const Rows& A) {
    L.inverse_diagonal.resize(A.rows());
    for (int i = 0; i < A.rows(); ++i) L.inverse_diagonal[i] = 1.0 / A.diagonal(i);
    L.lambda_max = largest_eigenvalue(A, L.inverse_diagonal);
}

/// The near-null space of the finest level: rigid-body modes about the centroid, rows of held
/// axes zero.
NearNull rigid_modes(const std::vector<Eigen::Vector3d>& position, int rows, const Eigen::VectorXd& mask) {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (int k = 0; k < rows; ++k) centre += position[k];
    centre /= std::max(1, rows);
    NearNull B = NearNull::Zero(3 * rows, kModes);
    for (int k = 0; k < rows; ++k) {
        const Eigen::Vector3d x = position[k] - centre;
        for (int a = 0; a < 3; ++a) {
            B(3 * k + a, a) = 1.0;
            B.block<3, 1>(3 * k, 3 + a) = Eigen::Vector3d::Unit(a).cross(x);
        }
        for (int a = 0; a < 3; ++a) B.row(3 * k + a) *= mask[3 * k + a];
    }
    return B;
}

/// Frees m's storage. Assigning an empty matrix does not: Eigen 3.4's sparse assignment keeps the
/// storage's capacity (CompressedStorage::resize never shrinks), so each "freed" matrix of the setup
/// lived to its end.
void release(CsrMatrix& m) { CsrMatrix().swap(m); }

/// The cycle's vectors of a level with n DOFs.
void size_vectors(AmgLevel& L, int n) { L.x.setZero(n), L.b.setZero(n), L.r.setZero(n), L.d.setZero(n), L.t.setZero(n); }

/// C = A B, row by row with a dense accumulator (Gustavson, ACM TOMS 4(3), 1978), in two passes (the
/// pattern, then the values straight into C's storage), the rows shared among the threads. Each entry sums its terms in the order
/// Eigen's conservative product does (A's row order, the first term assigned, the others added),
/// so the values are the same bits; Eigen's product of row-major operands builds its result in
/// another storage and converts it, two copies of C at once, and its conversions were a third of
/// the setup's time at 53k tets.
template <class Rows>
CsrMatrix product_of(const Rows& A, const CsrMatrix& B) {
    const int rows = A.rows(), cols = static_cast<int>(B.cols());
    CsrMatrix C(rows, cols);
    // The rows split in one contiguous share per thread, each with its own accumulator: a row's
    // entries do not depend on the split, so the bits do not depend on the thread count.
    const int shares = std::max(1, std::min(thread_count(), rows / 1024));
    const auto share_rows = [&](int s, int& lo, int& hi) {
        lo = static_cast<int>(static_cast<long>(rows) * s / shares);
        hi = static_cast<int>(static_cast<long>(rows) * (s + 1) / shares);
    };
    int* outer = C.outerIndexPtr();
    parallel_for(shares, [&](int s) {  // the pattern: each row's count
        int lo = 0, hi = 0;
        share_rows(s, lo, hi);
        std::vector<int> seen(cols, -1);
        for (int i = lo; i < hi; ++i) {
            int n = 0;
            A.row(i, [&](int k, double) {
                for (CsrMatrix::InnerIterator b(B, k); b; ++b)
                    if (seen[b.col()] != i) seen[b.col()] = i, ++n;
            });
            outer[i + 1] = n;
        }
    }, 1);
    outer[0] = 0;
    for (int i = 0; i < rows; ++i) outer[i + 1] += outer[i];
    C.resizeNonZeros(outer[rows]);
    outer = C.outerIndexPtr();
    parallel_for(shares, [&](int s) {  // the values, straight into C
        int lo = 0, hi = 0;
        share_rows(s, lo, hi);
        std::vector<int> seen(cols, -1);
        std::vector<double> sum(cols);
        for (int i = lo; i < hi; ++i) {
            int* row_cols = C.innerIndexPtr() + outer[i];
            int n = 0;
            A.row(i, [&](int k, double a) {
                for (CsrMatrix::InnerIterator b(B, k); b; ++b) {
                    const int j = static_cast<int>(b.col());
                    if (seen[j] != i) {
                        seen[j] = i, row_cols[n++] = j;
                        sum[j] = b.value() * a;
                    } else {
                        sum[j] += b.value() * a;
                    }
                }
            });
            std::sort(row_cols, row_cols + n);
            double* row_values = C.valuePtr() + outer[i];
            for (int k = 0; k < n; ++k) row_values[k] = sum[row_cols[k]];
        }
    }, 1);
    return C;
}

}  // namespace

CsrMatrix sparse_product(const CsrMatrix& A, const CsrMatrix& B) { return product_of(ScalarRows{A}, B); }

RunMatrix to_runs(const CsrMatrix& M) {
    RunMatrix out;
    out.row_count = static_cast<int>(M.rows()), out.column_count = static_cast<int>(M.cols());
    out.value.reserve(M.nonZeros());
    for (int i = 0; i < M.outerSize(); ++i) {
        int next = -1;  // the column that would continue the current run
        for (CsrMatrix::InnerIterator it(M, i); it; ++it) {
            if (it.col() != next) {  // a new run; the previous one ends here
                if (!out.run_column.empty()) out.run_start.push_back(static_cast<int>(out.value.size()));
                out.run_column.push_back(it.col());
            }
            out.value.push_back(static_cast<float>(it.value()));
            next = it.col() + 1;
        }
        out.row_start.push_back(static_cast<int>(out.run_column.size()));
    }
    if (!out.run_column.empty()) out.run_start.push_back(static_cast<int>(out.value.size()));
    return out;
}

namespace {

/// One level of the setup on operator A (rows: ScalarRows or BlockRows): its smoother's data and,
/// unless it is the coarsest, its prolongator and restriction and the next level's operator
/// (returned in `coarse_A`; B and g become the next level's). `owned`, if given, is A's storage:
/// freed as soon as the next operator no longer needs it. Returns false at the coarsest level.
template <class Rows>
bool coarsen(const Rows& A, CsrMatrix* owned, AmgHierarchy& h, NearNull& B, Grouping& g, double theta,
             CsrMatrix& coarse_A) {
    AmgLevel& L = h.levels.back();
    smoother_data(L, A);
    if (A.rows() <= kAmgCoarsest || static_cast<int>(h.levels.size()) == kMaxLevels) return false;
    int count = 0;
    const std::vector<int> agg = aggregate(strong_neighbours(A, g, theta), count);
    NearNull coarse_B;
    Grouping coarse;
    // Each double-precision matrix is freed as soon as the next one no longer needs it (the level
    // keeps single-precision runs): the setup's peak memory is the product's operands, not every
    // intermediate at once.
    CsrMatrix P;
    {
        const CsrMatrix Pt = tentative(B, g, agg, count, coarse_B, coarse);
        if (count == 0 || Pt.cols() > kStallRatio * A.rows()) return false;
        const double omega = 4.0 / 3.0 / L.lambda_max;
        CsrMatrix smoothing = product_of(A, Pt);  // becomes omega D^-1 A P_tent
        for (int i = 0; i < smoothing.outerSize(); ++i)
            for (CsrMatrix::InnerIterator it(smoothing, i); it; ++it) it.valueRef() *= omega * L.inverse_diagonal[i];
        P = Pt - smoothing;
    }
    CsrMatrix AP = product_of(A, P);
    if (owned) release(*owned);
    L.P = to_runs(P);
    CsrMatrix R = P.transpose();
    release(P);
    CsrMatrix RAP = sparse_product(R, AP);  // R (A P): the Galerkin product
    coarse_A.swap(RAP);
    release(AP);
    L.R = to_runs(R);
    release(R);
    h.levels.emplace_back();
    h.levels.back().A = to_runs(coarse_A);
    B = std::move(coarse_B), g = std::move(coarse);
    return true;
}

}  // namespace

void build_amg(const LinearSystem& Ablock, const std::vector<Eigen::Vector3d>& position, const Eigen::VectorXd& mask,
               AmgHierarchy& h) {
    h.levels.assign(1, AmgLevel{});
    h.ok = false, h.age = 0, h.first_iterations = h.last_iterations = 0;
    h.topology = Ablock.topology;
    const int rows = Ablock.rows();
    Grouping g;
    for (int k = 0; k <= rows; ++k) g.start.push_back(3 * k);
    NearNull B = rigid_modes(position, rows, mask);
    double theta = kTheta;
    CsrMatrix A;  // the operator of the level being set up, from the first coarse one on
    if (!coarsen(BlockRows{Ablock}, nullptr, h, B, g, theta, A)) {
        copy_to_scalar(Ablock, A, true);  // the finest level is the coarsest
    } else {
        for (CsrMatrix coarse_A;; A.swap(coarse_A)) {  // Eigen 3.4's sparse matrices have no move assignment
            theta *= 0.5;
            if (!coarsen(ScalarRows{A}, &A, h, B, g, theta, coarse_A)) break;
        }
    }
    h.coarsest.compute(Eigen::SparseMatrix<double>(A));  // the coarsest level is solved exactly
    h.ok = h.coarsest.info() == Eigen::Success;
    for (AmgLevel& L : h.levels) size_vectors(L, static_cast<int>(L.inverse_diagonal.size()));
}

bool amg_extend(AmgHierarchy& h, const LinearSystem& A) {
    if (h.levels.size() < 2) return false;
    AmgLevel& L = h.levels.front();
    const int n = 3 * A.rows();
    if (n < L.P.rows()) return false;
    L.P.row_start.resize(n + 1, L.P.row_start.back());  // the new rows: no runs
    L.P.row_count = n;
    L.R.column_count = n;
    L.inverse_diagonal.setOnes(n);  // refilled from the current A before every solve
    size_vectors(L, n);
    h.topology = A.topology;
    return true;
}

double amg_nonzeros(const AmgHierarchy& h) {
    double n = 0.0;
    for (const AmgLevel& L : h.levels) n += double(L.A.nonZeros()) + double(L.P.nonZeros()) + double(L.R.nonZeros());
    return n + double(h.coarsest.matrixL().nestedExpression().nonZeros());
}

}  // namespace xcut
