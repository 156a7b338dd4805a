// The XFEM element (paper §3.1, eq. 1-6, App. A) against an independent evaluation of the paper's
// formulas: the engine stores phantom vertices (Fig. 4); here the forces and the stiffness action
// are recomputed in the enriched DOFs (u_j, a_j) with an explicitly assembled 12x12 element
// stiffness K = V B^T C B, and compared to 1e-12.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "systems/kernels/cut_geometry.h"
#include "systems/cut/enrichment_system.h"
#include "systems/force_system.h"
#include "systems/cut/scripted_cut_system.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

using Mat12 = Eigen::Matrix<double, 12, 12>;
using Vec12 = Eigen::Matrix<double, 12, 1>;

/// Linear-tetrahedron stiffness V B^T C B (Voigt: xx, yy, zz, xy, yz, zx with engineering shears).
Mat12 element_stiffness(const Mat3& dm_inv, double V, double lambda, double mu) {
    std::array<Vec3, 4> g;
    for (int j = 1; j < 4; ++j) g[j] = dm_inv.row(j - 1).transpose();
    g[0] = -(g[1] + g[2] + g[3]);
    Eigen::Matrix<double, 6, 12> B = Eigen::Matrix<double, 6, 12>::Zero();
    for (int j = 0; j < 4; ++j) {
        B(0, 3 * j) = g[j].x();
        B(1, 3 * j + 1) = g[j].y();
        B(2, 3 * j + 2) = g[j].z();
        B(3, 3 * j) = g[j].y(), B(3, 3 * j + 1) = g[j].x();
        B(4, 3 * j + 1) = g[j].z(), B(4, 3 * j + 2) = g[j].y();
        B(5, 3 * j) = g[j].z(), B(5, 3 * j + 2) = g[j].x();
    }
    Eigen::Matrix<double, 6, 6> C = Eigen::Matrix<double, 6, 6>::Zero();
    C.topLeftCorner<3, 3>().setConstant(lambda);
    C.topLeftCorner<3, 3>().diagonal().array() += 2 * mu;
    C.bottomRightCorner<3, 3>().diagonal().setConstant(mu);
    return V * B.transpose() * C * B;
}

Eigen::Matrix<double, 12, 12> block_rotation(const Mat3& R) {
    Mat12 out = Mat12::Zero();
    for (int j = 0; j < 4; ++j) out.block<3, 3>(3 * j, 3 * j) = R;
    return out;
}

struct CutTet {
    World world;
    int cut = 0;
};

/// One tetrahedron cut by the plane n.x = d, deformed randomly on both sides.
CutTet make_cut_tet(const Vec3& normal, double offset, uint64_t seed) {
    MeshData mesh;
    mesh.dim = 3;
    mesh.points = {Vec3(0, 0, 0), Vec3(0.01, 0.001, 0), Vec3(0.002, 0.011, 0), Vec3(0.001, 0.002, 0.012)};
    mesh.cells = {{0, 1, 2, 3}};
    CutTet t{testing::world_from_mesh(mesh)};
    World& w = t.world;
    const Vec3 n = normal.normalized();
    // A large square polygon on the plane, so the tet is crossed completely.
    const Vec3 u = n.unitOrthogonal(), v = n.cross(u), c = n * offset;
    queue_polygon_cut(w, {c - u - v, c + u - v, c + u + v, c - u + v});
    EXPECT_EQ(apply_cut_events(w), 1);
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, 4e-4);
    const Mat3 Q = Eigen::AngleAxisd(0.6, Vec3(1, -1, 2).normalized()).matrix();
    for (int i = 0; i < w.nodes.count(); ++i)
        w.nodes.position[i] = Q * w.nodes.rest[i] + Vec3(noise(rng), noise(rng), noise(rng));
    update_rotations(w);
    compute_forces(w);
    return t;
}

/// Generalized forces in (u, a) from the engine's real/phantom node forces: f_u = f_x + f_y and
/// f_a = +f_y (H = -1, y = x + a) or -f_y (H = +1, y = x - a).
void engine_forces_in_enriched_dofs(const World& w, const Eigen::VectorXd& f, Vec12& fu, Vec12& fa) {
    for (int j = 0; j < 4; ++j) {
        const int p = w.enriched.phantom[j];
        const Vec3 fy = p >= 0 ? Vec3(f.segment<3>(3 * p)) : Vec3::Zero();
        fu.segment<3>(3 * j) = f.segment<3>(3 * j) + fy;
        fa.segment<3>(3 * j) = w.enriched.sign[j] < 0 ? fy : Vec3(-fy);
    }
}

void check_against_paper(const Vec3& normal, double offset, uint64_t seed) {
    CutTet t = make_cut_tet(normal, offset, seed);
    const World& w = t.world;
    ASSERT_EQ(w.enriched.count(), 4) << "every node of a lone cut tet is enriched";
    const Elements& el = w.elements;
    const Material& m = w.materials.list[0];
    const Mat12 K = element_stiffness(el.dm_inv[0], el.rest_volume[0], m.lambda(), m.mu());
    const double fa_frac = w.cuts.fraction_above[0];
    const Mat3 Ra = el.rotation[w.virtual_elements.element[w.cuts.virtual_element[0][0]]];
    const Mat3 Rb = el.rotation[w.virtual_elements.element[w.cuts.virtual_element[0][1]]];

    // Each side's rotation is the polar rotation of its own virtual element (checked by SVD).
    for (int s = 0; s < 2; ++s) {
        const auto& verts = el.nodes[w.virtual_elements.element[w.cuts.virtual_element[0][s]]];
        Mat3 Ds;
        for (int k = 0; k < 3; ++k) Ds.col(k) = w.nodes.position[verts[k + 1]] - w.nodes.position[verts[0]];
        Eigen::JacobiSVD<Mat3> svd(Ds * el.dm_inv[0], Eigen::ComputeFullU | Eigen::ComputeFullV);
        const Mat3 R = svd.matrixU() * svd.matrixV().transpose();
        EXPECT_LT((R - (s == 0 ? Ra : Rb)).norm(), 1e-10);
    }

    // u_j, a_j and the side positions p_aj, p_bj of eq. 4 / 6.
    Vec12 p0, pa, pb;
    std::array<int8_t, 4> H;
    for (int j = 0; j < 4; ++j) {
        H[j] = w.enriched.sign[j];
        const Vec3 x = w.nodes.position[j], a = enriched_displacement(w, j);
        p0.segment<3>(3 * j) = w.nodes.rest[j];
        pa.segment<3>(3 * j) = H[j] > 0 ? x : Vec3(x + a);
        pb.segment<3>(3 * j) = H[j] > 0 ? Vec3(x - a) : x;
    }
    const Vec12 fa_side = -fa_frac * block_rotation(Ra) * K * (block_rotation(Ra).transpose() * pa - p0);
    const Vec12 fb_side = -(1 - fa_frac) * block_rotation(Rb) * K * (block_rotation(Rb).transpose() * pb - p0);
    // Eq. 2 (standard DOFs) and eq. 5 (enriched DOFs, shifted Heaviside). Sign: the paper writes
    // the internal force R K (R^T p - p0); the force acting on the node is its negative.
    Vec12 ref_u = fa_side + fb_side, ref_a;
    for (int j = 0; j < 4; ++j)
        ref_a.segment<3>(3 * j) = H[j] > 0 ? Vec3(-fb_side.segment<3>(3 * j)) : Vec3(fa_side.segment<3>(3 * j));

    Vec12 fu, fa;
    engine_forces_in_enriched_dofs(w, w.forces.force, fu, fa);
    const double scale = std::max(ref_u.norm(), ref_a.norm());
    EXPECT_LT((fu - ref_u).norm(), 1e-12 * scale) << "eq. 2";
    EXPECT_LT((fa - ref_a).norm(), 1e-12 * scale) << "eq. 5";

    // Stiffness action on a random (du, da): -d f / d(u, a) with rotations frozen.
    std::mt19937_64 rng(seed + 1);
    std::normal_distribution<double> nz;
    Vec12 du, da;
    for (int i = 0; i < 12; ++i) du[i] = nz(rng), da[i] = nz(rng);
    Vec12 dpa, dpb;
    for (int j = 0; j < 4; ++j) {
        dpa.segment<3>(3 * j) = du.segment<3>(3 * j) + (H[j] > 0 ? Vec3::Zero() : Vec3(da.segment<3>(3 * j)));
        dpb.segment<3>(3 * j) = du.segment<3>(3 * j) - (H[j] > 0 ? Vec3(da.segment<3>(3 * j)) : Vec3::Zero());
    }
    const Vec12 ka = fa_frac * block_rotation(Ra) * K * block_rotation(Ra).transpose() * dpa;
    const Vec12 kb = (1 - fa_frac) * block_rotation(Rb) * K * block_rotation(Rb).transpose() * dpb;
    Vec12 ref_ku = ka + kb, ref_ka;
    for (int j = 0; j < 4; ++j)
        ref_ka.segment<3>(3 * j) = H[j] > 0 ? Vec3(-kb.segment<3>(3 * j)) : Vec3(ka.segment<3>(3 * j));
    // The same perturbation in the engine's variables: x_j += du_j, y_j += du_j -/+ da_j.
    Eigen::VectorXd dxy(3 * w.nodes.count());
    for (int j = 0; j < 4; ++j) {
        dxy.segment<3>(3 * j) = du.segment<3>(3 * j);
        dxy.segment<3>(3 * w.enriched.phantom[j]) =
            du.segment<3>(3 * j) + (H[j] > 0 ? Vec3(-da.segment<3>(3 * j)) : Vec3(da.segment<3>(3 * j)));
    }
    Eigen::VectorXd kxy;
    World& wm = t.world;
    elastic_stiffness_product(wm, dxy, kxy);
    Vec12 ku, kaa;
    engine_forces_in_enriched_dofs(w, kxy, ku, kaa);
    const double kscale = std::max(ref_ku.norm(), ref_ka.norm());
    EXPECT_LT((ku - ref_ku).norm(), 1e-12 * kscale);
    EXPECT_LT((kaa - ref_ka).norm(), 1e-12 * kscale);
}

TEST(XfemElement, OneNodeAloneMatchesPaperEquations) { check_against_paper(Vec3(0, 0, 1), 0.004, 1); }
TEST(XfemElement, TwoAndTwoMatchesPaperEquations) { check_against_paper(Vec3(1, 1, 0.2), 0.006, 2); }
TEST(XfemElement, ObliqueCutMatchesPaperEquations) { check_against_paper(Vec3(0.3, -1, 0.5), -0.003, 3); }

TEST(XfemElement, VolumeFractionsAreExact) {
    // Unit corner tet cut by x + y = 1/2: the side x + y > 1/2 has volume 1/12 of the tet's 1/6
    // (integral of (1 - s) s over s in [1/2, 1]), so V_a/V = 1/2 exactly.
    std::array<Vec3, 4> X = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    std::array<int8_t, 4> H = {-1, 1, 1, -1};
    std::array<double, 6> t{};
    t[0] = 0.5, t[1] = 0.5, t[4] = 0.5, t[5] = 0.5;  // edges 01, 02, 13, 23 at their midpoints
    EXPECT_NEAR(tet_side_volume(X, H, t, 1), 1.0 / 12.0, 1e-15);
    EXPECT_NEAR(tet_side_volume(X, H, t, -1), 1.0 / 12.0, 1e-15);
    // Corner cut z = 0.3 : the corner tet above has volume (0.7)^3 / 6.
    std::array<int8_t, 4> H2 = {-1, -1, -1, 1};
    std::array<double, 6> t2{};
    t2[2] = 0.3, t2[4] = 0.3, t2[5] = 0.3;
    EXPECT_NEAR(tet_side_volume(X, H2, t2, 1), 0.343 / 6.0, 1e-15);
    EXPECT_NEAR(tet_side_volume(X, H2, t2, -1), (1.0 - 0.343) / 6.0, 1e-15);
}

}  // namespace
}  // namespace xcut
