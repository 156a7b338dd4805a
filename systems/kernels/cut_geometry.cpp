#include "systems/kernels/cut_geometry.h"

namespace xcut {
namespace {

/// Local edge index joining local nodes a and b.
int tet_edge(int a, int b) {
    for (int k = 0; k < 6; ++k)
        if ((kTetEdges[k][0] == a && kTetEdges[k][1] == b) || (kTetEdges[k][0] == b && kTetEdges[k][1] == a)) return k;
    return -1;
}

int tri_edge(int a, int b) {
    for (int k = 0; k < 3; ++k)
        if ((kTriEdges[k][0] == a && kTriEdges[k][1] == b) || (kTriEdges[k][0] == b && kTriEdges[k][1] == a)) return k;
    return -1;
}

/// Point where the cut crosses the edge from local node a to local node b.
Vec3 crossing(const std::array<Vec3, 4>& X, const std::array<double, 6>& t, int dim, int a, int b) {
    const int k = dim == 3 ? tet_edge(a, b) : tri_edge(a, b);
    return edge_point(X, dim, k, t[k]);
}

}  // namespace

double tet_side_volume(const std::array<Vec3, 4>& X, const std::array<int8_t, 4>& H, const std::array<double, 6>& t,
                       int side) {
    int in[4], out[4], n_in = 0, n_out = 0;
    for (int a = 0; a < 4; ++a) (H[a] == side ? in[n_in++] : out[n_out++]) = a;
    const double total = std::abs(tet_signed_volume(X[0], X[1], X[2], X[3]));
    if (n_in == 0) return 0.0;
    if (n_out == 0) return total;
    if (n_in == 1 || n_out == 1) {
        const bool alone_in = n_in == 1;
        const int k = alone_in ? in[0] : out[0];
        const int* others = alone_in ? out : in;
        const double corner = std::abs(tet_signed_volume(X[k], crossing(X, t, 3, k, others[0]),
                                                         crossing(X, t, 3, k, others[1]),
                                                         crossing(X, t, 3, k, others[2])));
        return alone_in ? corner : total - corner;
    }
    // Two and two: wedge a0 a1 a2 / b0 b1 b2 with a = (A, p_AC, p_AD), b = (B, p_BC, p_BD).
    const int A = in[0], B = in[1], C = out[0], D = out[1];
    const Vec3 a0 = X[A], a1 = crossing(X, t, 3, A, C), a2 = crossing(X, t, 3, A, D);
    const Vec3 b0 = X[B], b1 = crossing(X, t, 3, B, C), b2 = crossing(X, t, 3, B, D);
    const double v = tet_signed_volume(a0, a1, a2, b0) + tet_signed_volume(a1, a2, b0, b1) +
                     tet_signed_volume(a2, b0, b1, b2);
    return std::abs(v);
}

double tri_side_area(const std::array<Vec3, 4>& X, const std::array<int8_t, 4>& H, const std::array<double, 6>& t,
                     int side) {
    int in[3], out[3], n_in = 0, n_out = 0;
    for (int a = 0; a < 3; ++a) (H[a] == side ? in[n_in++] : out[n_out++]) = a;
    auto area = [](const Vec3& p, const Vec3& q, const Vec3& r) {
        return 0.5 * std::abs((q - p).head<2>().x() * (r - p).head<2>().y() - (q - p).head<2>().y() * (r - p).head<2>().x());
    };
    const double total = area(X[0], X[1], X[2]);
    if (n_in == 0) return 0.0;
    if (n_out == 0) return total;
    const bool alone_in = n_in == 1;
    const int k = alone_in ? in[0] : out[0];
    const int* others = alone_in ? out : in;
    const double corner = area(X[k], crossing(X, t, 2, k, others[0]), crossing(X, t, 2, k, others[1]));
    return alone_in ? corner : total - corner;
}

}  // namespace xcut
