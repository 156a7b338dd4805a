#include "systems/kernels/tet10_side_rule.h"

#include <Eigen/LU>
#include <cmath>
#include <vector>

#include "components/cut_elements.h"
#include "systems/kernels/branch_enrichment.h"

namespace xcut {
namespace {

using Bary = Eigen::Vector4d;

Bary corner(int a) { return Bary::Unit(a); }

/// The point where the cut crosses the edge from local node a to local node b.
Bary crossing(const std::array<double, 6>& t, int a, int b) {
    for (int k = 0; k < 6; ++k) {
        if (kTetEdges[k][0] == a && kTetEdges[k][1] == b) return corner(a) + t[k] * (corner(b) - corner(a));
        if (kTetEdges[k][0] == b && kTetEdges[k][1] == a) return corner(b) + t[k] * (corner(a) - corner(b));
    }
    return corner(a);
}

/// The prism between triangles (a0, a1, a2) and (b0, b1, b2), a_i over b_i, as three tetrahedra.
void prism(const Bary& a0, const Bary& a1, const Bary& a2, const Bary& b0, const Bary& b1, const Bary& b2,
           std::array<std::array<Bary, 4>, 3>& pieces) {
    pieces[0] = {a0, a1, a2, b0};
    pieces[1] = {a1, a2, b0, b1};
    pieces[2] = {a2, b0, b1, b2};
}

/// |det| of the piece's barycentric vertices: its volume over the parent's.
double piece_fraction(const std::array<Bary, 4>& piece) {
    Eigen::Matrix4d M;
    for (int v = 0; v < 4; ++v) M.row(v) = piece[v].transpose();
    return std::abs(M.determinant());
}

/// The point where the cut crosses the triangle's edge from corner a to corner b (t: kTriEdges order,
/// from each edge's first corner).
Bary tri_crossing(const std::array<double, 3>& t, int a, int b) {
    for (int k = 0; k < 3; ++k) {
        if (kTriEdges[k][0] == a && kTriEdges[k][1] == b) return corner(a) + t[k] * (corner(b) - corner(a));
        if (kTriEdges[k][0] == b && kTriEdges[k][1] == a) return corner(b) + t[k] * (corner(a) - corner(b));
    }
    return corner(a);
}

/// |det| of a triangle piece's barycentric vertices (their first three coordinates): its area over
/// the parent's.
double tri_piece_fraction(const std::array<Bary, 3>& piece) {
    Eigen::Matrix3d M;
    for (int v = 0; v < 3; ++v) M.row(v) = piece[v].head<3>().transpose();
    return std::abs(M.determinant());
}

/// HRZ: the consistent mass's diagonal scaled so that it sums to the side's fraction of the parent.
std::array<double, 10> hrz_scaled(const std::array<double, 10>& diagonal, double fraction) {
    double sum = 0.0;
    for (double d : diagonal) sum += d;
    std::array<double, 10> out{};
    if (sum > 0.0)
        for (int i = 0; i < 10; ++i) out[i] = diagonal[i] * fraction / sum;
    return out;
}

/// HRZ masses of a side made of the first n simplices of `pieces` (V vertices each: triangles or
/// tetrahedra, in the parent's barycentric coordinates): int N_i^2 over each by the collapsed map of
/// the unit square (cube) with 4-point Gauss-Legendre in each direction, x = u, y = v (1 - u)
/// [, z = w (1 - u)(1 - v)], Jacobian (1 - u) times 2 [(1 - u)^2 (1 - v) times 6], the diagonal then
/// scaled to the side's fraction (hrz_scaled).
template <size_t V, size_t P>
std::array<double, 10> side_masses(const std::array<std::array<Bary, V>, P>& pieces, int n) {
    std::vector<double> node, weight;  // 4-point Gauss-Legendre on [0, 1]
    gauss_legendre_unit(4, node, weight);
    std::array<double, 10> diagonal{};
    double total = 0.0;
    for (int p = 0; p < n; ++p) {
        const std::array<Bary, V>& S = pieces[p];
        double fraction = 0.0;
        if constexpr (V == 3) fraction = tri_piece_fraction(S);
        else fraction = piece_fraction(S);
        total += fraction;
        for (int a = 0; a < 4; ++a)
            for (int b = 0; b < 4; ++b)
                for (int c = 0; c < (V == 3 ? 1 : 4); ++c) {
                    const double u = node[a], v = node[b], w = V == 3 ? 0.0 : node[c];
                    const double y = v * (1.0 - u), z = w * (1.0 - u) * (1.0 - v);
                    Bary L = S[0] + u * (S[1] - S[0]) + y * (S[2] - S[0]);
                    double d = 0.0;
                    if constexpr (V == 4) {
                        L += z * (S[3] - S[0]);
                        d = 6.0 * fraction * weight[a] * weight[b] * weight[c] * (1.0 - u) * (1.0 - u) * (1.0 - v);
                    } else {
                        d = 2.0 * fraction * weight[a] * weight[b] * (1.0 - u);
                    }
                    const std::array<double, 10> N = tet10_shapes(L);
                    for (int i = 0; i < 10; ++i) diagonal[i] += d * N[i] * N[i];
                }
    }
    return hrz_scaled(diagonal, total);
}


}  // namespace

int tri_side_pieces(const std::array<int8_t, 3>& H, const std::array<double, 3>& t, int side,
                    std::array<std::array<Eigen::Vector4d, 3>, 2>& pieces) {
    int in[3], out[3], n_in = 0, n_out = 0;
    for (int a = 0; a < 3; ++a) (H[a] == side ? in[n_in++] : out[n_out++]) = a;
    if (n_in == 0) return 0;
    if (n_out == 0) {
        pieces[0] = {corner(0), corner(1), corner(2)};
        return 1;
    }
    if (n_in == 1) {
        pieces[0] = {corner(in[0]), tri_crossing(t, in[0], out[0]), tri_crossing(t, in[0], out[1])};
        return 1;
    }
    // Two corners A, B and the crossings toward the third, C: the quad (A, B, p_BC, p_AC).
    const int A = in[0], B = in[1], C = out[0];
    pieces[0] = {corner(A), corner(B), tri_crossing(t, B, C)};
    pieces[1] = {corner(A), tri_crossing(t, B, C), tri_crossing(t, A, C)};
    return 2;
}

TetSideRule tri_side_rule(const std::array<int8_t, 3>& H, const std::array<double, 3>& t, int side) {
    std::array<std::array<Bary, 3>, 2> pieces;
    const int n = tri_side_pieces(H, t, side, pieces);
    const TetSideRule& whole = tri6_rule();
    TetSideRule rule;
    for (int p = 0; p < n; ++p) {
        const double fraction = tri_piece_fraction(pieces[p]);
        for (int q = 0; q < whole.count; ++q) {
            Bary L = Bary::Zero();
            for (int v = 0; v < 3; ++v) L += whole.L[q][v] * pieces[p][v];
            rule.L[rule.count] = L;
            rule.weight[rule.count] = whole.weight[q] * fraction;
            ++rule.count;
        }
    }
    return rule;
}

std::array<double, 10> tri6_side_masses(const std::array<int8_t, 3>& H, const std::array<double, 3>& t, int side) {
    std::array<std::array<Bary, 3>, 2> pieces;
    const int n = tri_side_pieces(H, t, side, pieces);
    return side_masses(pieces, n);
}

int tet_side_pieces(const std::array<int8_t, 4>& H, const std::array<double, 6>& t, int side,
                    std::array<std::array<Bary, 4>, 3>& pieces) {
    int in[4], out[4], n_in = 0, n_out = 0;
    for (int a = 0; a < 4; ++a) (H[a] == side ? in[n_in++] : out[n_out++]) = a;
    if (n_in == 0) return 0;
    if (n_out == 0) {
        pieces[0] = {corner(0), corner(1), corner(2), corner(3)};
        return 1;
    }
    if (n_in == 1) {
        const int k = in[0];
        pieces[0] = {corner(k), crossing(t, k, out[0]), crossing(t, k, out[1]), crossing(t, k, out[2])};
        return 1;
    }
    if (n_out == 1) {  // the three nodes' triangle over the crossings toward the one across
        const int k = out[0];
        prism(corner(in[0]), corner(in[1]), corner(in[2]), crossing(t, in[0], k), crossing(t, in[1], k),
              crossing(t, in[2], k), pieces);
        return 3;
    }
    // Two and two: (A, p_AC, p_AD) over (B, p_BC, p_BD), as tet_side_volume splits it.
    const int A = in[0], B = in[1], C = out[0], D = out[1];
    prism(corner(A), crossing(t, A, C), crossing(t, A, D), corner(B), crossing(t, B, C), crossing(t, B, D), pieces);
    return 3;
}

TetSideRule tet_side_rule(const std::array<int8_t, 4>& H, const std::array<double, 6>& t, int side) {
    std::array<std::array<Bary, 4>, 3> pieces;
    const int n = tet_side_pieces(H, t, side, pieces);
    TetSideRule rule;
    for (int p = 0; p < n; ++p) {
        const double fraction = piece_fraction(pieces[p]);
        for (int q = 0; q < 4; ++q) {
            Bary L = Bary::Zero();
            for (int v = 0; v < 4; ++v) L += tet10_point_coordinate(q, v) * pieces[p][v];
            rule.L[rule.count] = L;
            rule.weight[rule.count] = 0.25 * fraction;
            ++rule.count;
        }
    }
    return rule;
}

Tet10SideGradients tet10_side_gradients(const Mat3& dm_inv, const TetSideRule& rule, bool planar) {
    const std::array<Vec3, 4> g = planar ? tri3_gradients(dm_inv) : tet4_gradients(dm_inv);
    Tet10SideGradients out;
    out.count = rule.count;
    out.planar = planar;
    for (int q = 0; q < rule.count; ++q) {
        tet10_gradients_at(g, rule.L[q], out.grad[q]);
        out.weight[q] = rule.weight[q];
    }
    return out;
}

const TetSideRule& tri6_rule() {
    static const TetSideRule rule = [] {
        TetSideRule r;
        r.count = 3;
        for (int q = 0; q < 3; ++q) {
            r.L[q] = Eigen::Vector4d(1.0 / 6.0, 1.0 / 6.0, 1.0 / 6.0, 0.0);
            r.L[q][q] = 2.0 / 3.0;
            r.weight[q] = 1.0 / 3.0;
        }
        return r;
    }();
    return rule;
}

std::array<double, 10> tet10_side_masses(const std::array<int8_t, 4>& H, const std::array<double, 6>& t, int side) {
    std::array<std::array<Bary, 4>, 3> pieces;
    const int n = tet_side_pieces(H, t, side, pieces);
    return side_masses(pieces, n);
}

}  // namespace xcut
