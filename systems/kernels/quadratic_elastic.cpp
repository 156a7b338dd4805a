#include "systems/kernels/quadratic_elastic.h"

#include "engine/parallel.h"
#include "systems/kernels/polar_decomposition.h"

namespace xcut {
namespace {

Tet10Vectors gather(const std::array<int, 10>& ids, const Vec3* v) {
    Tet10Vectors out;
    for (int a = 0; a < 10; ++a) out[a] = v[ids[a]];
    return out;
}

/// Element t's side rule, -1 for the whole element.
int side_of(const QuadraticView& v, int t) {
    return t < static_cast<int>(v.quadratic.side_rule.size()) ? v.quadratic.side_rule[t] : -1;
}

/// The volume the rule's weights scale [m^3]: the whole element's times its weight, or a side's
/// parent volume (its rule's weights are the side's fractions).
double volume_of(const QuadraticView& v, int t) {
    const int e = v.quadratic.element[t];
    return side_of(v, t) >= 0 ? v.elements.rest_volume[e] : v.elements.rest_volume[e] * v.elements.weight[e];
}

/// Element t's gradients at its rule's points when the rule is not Keast's 4: one side of a cut
/// element, or a 6-node triangle (whole: tri6_rule).
Tet10SideGradients rule_gradients(const QuadraticView& v, int t) {
    const int e = v.quadratic.element[t], s = side_of(v, t);
    const bool planar = v.quadratic.planar;
    return tet10_side_gradients(v.elements.dm_inv[e], s >= 0 ? v.quadratic.side_rules[s] : tri6_rule(), planar);
}

/// Whether element t integrates by rule_gradients (else Keast's 4 points).
bool by_rule(const QuadraticView& v, int t) { return v.quadratic.planar || side_of(v, t) >= 0; }

/// Calls f with element t's gradients: Keast's 4 points, or its rule's.
template <class F>
auto with_gradients(const QuadraticView& v, int t, F f) {
    if (!by_rule(v, t)) return f(tet10_gradients(v.elements.dm_inv[v.quadratic.element[t]]));
    return f(rule_gradients(v, t));
}

const Material& material_of(const QuadraticView& v, int t) {
    return v.materials.list[v.elements.material[v.quadratic.element[t]]];
}

LameParameters lame_of(const QuadraticView& v, int t) { return quadratic_lame(material_of(v, t), v.quadratic.planar); }

/// Element t's forces at positions x with rotation R into f; returns its strain energy [J].
double element_forces(const QuadraticView& v, const Vec3* x, int t, const Mat3& R, Tet10Vectors& f) {
    return with_gradients(v, t, [&](const auto& G) {
        return tet10_forces(gather(v.quadratic.nodes[t], x), G, R, volume_of(v, t), lame_of(v, t), f);
    });
}

}  // namespace

LameParameters quadratic_lame(const Material& m, bool planar) {
    const double lambda = planar ? m.lambda_plane_stress() : m.lambda();
    if (m.mean_dilatation) return {0.0, m.mu(), lambda};
    return {lambda, m.mu()};
}

double quadratic_forces(const QuadraticView& v, const Vec3* x, std::vector<Tet10Vectors>& buffer) {
    const int n = v.quadratic.count();
    buffer.resize(n);
    std::vector<double> energy(n);
    parallel_for(n, [&](int t) { energy[t] = element_forces(v, x, t, v.elements.rotation[v.quadratic.element[t]], buffer[t]); });
    return deterministic_sum(n, [&](int t) { return energy[t]; });
}

Mat3 quadratic_rotation(const QuadraticView& v, const Vec3* x, int t, const Mat3& warm) {
    Mat3 F = Mat3::Zero();
    if (side_of(v, t) >= 0) {  // the mean over the side's rule
        const Tet10SideGradients G = rule_gradients(v, t);
        const Tet10Vectors xs = gather(v.quadratic.nodes[t], x);
        double W = 0.0;
        for (int q = 0; q < G.count; ++q) F += G.weight[q] * tet10_deformation_gradient(xs, G, q), W += G.weight[q];
        if (!(W > 0.0)) return warm;  // a side without volume has no material to turn with
        F /= W;
    } else {  // the corner element's (a triangle's third column stays 0)
        const int e = v.quadratic.element[t];
        const auto& n = v.elements.nodes[e];
        for (int k = 0; k < (v.quadratic.planar ? 2 : 3); ++k) F.col(k) = x[n[k + 1]] - x[n[0]];
        F = F * v.elements.dm_inv[e];
    }
    if (!v.quadratic.planar) return extract_rotation(F, warm);
    Mat3 R = Mat3::Identity();
    R.topLeftCorner<2, 2>() = extract_rotation(Eigen::Matrix2d(F.topLeftCorner<2, 2>()));
    return R;
}

double quadratic_element_energy(const QuadraticView& v, const Vec3* x, int t, const Mat3& R) {
    Tet10Vectors unused;
    return element_forces(v, x, t, R, unused);
}

void quadratic_product_element(const QuadraticView& v, const Vec3* p, int t, std::vector<Tet10Vectors>& buffer) {
    const int e = v.quadratic.element[t];
    with_gradients(v, t, [&](const auto& G) {
        tet10_stiffness_product(gather(v.quadratic.nodes[t], p), G, v.elements.rotation[e], volume_of(v, t),
                                lame_of(v, t), buffer[t]);
    });
}

void quadratic_products(const QuadraticView& v, const Vec3* p, std::vector<Tet10Vectors>& buffer) {
    buffer.resize(v.quadratic.count());
    parallel_for(v.quadratic.count(), [&](int t) { quadratic_product_element(v, p, t, buffer); });
}

void quadratic_diagonals(const QuadraticView& v, std::vector<Tet10Vectors>& buffer) {
    buffer.resize(v.quadratic.count());
    parallel_for(v.quadratic.count(), [&](int t) {
        const int e = v.quadratic.element[t];
        with_gradients(v, t, [&](const auto& G) {
            tet10_stiffness_diagonal(G, v.elements.rotation[e], volume_of(v, t), lame_of(v, t), buffer[t]);
        });
    });
}

Vec3 quadratic_gathered(const QuadraticElements& q, const std::vector<Tet10Vectors>& buffer, int i) {
    Vec3 s = Vec3::Zero();
    if (i + 1 >= static_cast<int>(q.incidence.offset.size())) return s;
    for (int k = q.incidence.offset[i]; k < q.incidence.offset[i + 1]; ++k)
        s += buffer[q.incidence.entry[k] >> 4][q.incidence.entry[k] & 15];
    return s;
}

namespace {

/// A constant-pressure element's rbar (tet10_mean_gradients) and its block scale lambda_mean V / W
/// (`volume`: V times the stiffness scale); 0 for any other element.
template <size_t P>
double mean_pressure_terms(const Tet10PointGradients<P>& G, const Mat3& R, const LameParameters& lame, double volume,
                           std::array<Vec3, 10>& rbar) {
    if (lame.lambda_mean == 0.0) return 0.0;
    return lame.lambda_mean * volume / tet10_mean_gradients(G, R, rbar);
}

}  // namespace

void quadratic_block_terms(const QuadraticView& v, double stiff_scale, QuadraticTerms& terms) {
    const int n = v.quadratic.count();
    terms.whole.resize(n);
    terms.side_of.assign(n, -1);
    int sides = 0;
    for (int t = 0; t < n; ++t)
        if (by_rule(v, t)) terms.side_of[t] = sides++;
    terms.side.resize(sides);
    parallel_for(n, [&](int t) {
        const int e = v.quadratic.element[t];
        const LameParameters lame = lame_of(v, t);
        const Mat3& R = v.elements.rotation[e];
        if (terms.side_of[t] >= 0) {
            const Tet10SideGradients G = rule_gradients(v, t);
            QuadraticSideBlocks& b = terms.side[terms.side_of[t]];
            b.count = G.count;
            for (int q = 0; q < G.count; ++q) {
                const double w = G.weight[q] * stiff_scale * volume_of(v, t);
                b.lambda_w[q] = w * lame.lambda, b.mu_w[q] = w * lame.mu;
                for (int j = 0; j < 10; ++j) b.r[q][j] = R * G.grad[q][j];
            }
            b.lambda_mean_w = mean_pressure_terms(G, R, lame, stiff_scale * volume_of(v, t), b.rbar);
            return;
        }
        const Tet10Gradients G = tet10_gradients(v.elements.dm_inv[e]);
        const double w = 0.25 * stiff_scale * volume_of(v, t);
        QuadraticBlocks& b = terms.whole[t];
        b.lambda_w = w * lame.lambda, b.mu_w = w * lame.mu;
        for (int q = 0; q < 4; ++q)
            for (int j = 0; j < 10; ++j) b.r[q][j] = R * G.grad[q][j];
        b.lambda_mean_w = mean_pressure_terms(G, R, lame, stiff_scale * volume_of(v, t), b.rbar);
    }, 512);
}

namespace {

/// Adds local row a of one element's blocks at one point: (lambda_w r_a) r_c^T + mu_w ... per column c.
void add_point_row(const std::array<Vec3, 10>& r, double lambda_w, double mu_w, int a, const std::array<int, 10>& slot,
                   LinearSystem& A) {
    const Vec3 lambda_ra = lambda_w * r[a], mu_ra = mu_w * r[a];
    for (int c = 0; c < 10; ++c) add_corotational_stiffness_block(lambda_ra, mu_ra, r[c], 3, A.value.data() + 9 * slot[c]);
}

}  // namespace

void add_quadratic_row(const QuadraticElements& q, const QuadraticTerms& terms, int i, LinearSystem& A) {
    if (i + 1 >= static_cast<int>(q.incidence.offset.size())) return;
    for (int k = q.incidence.offset[i]; k < q.incidence.offset[i + 1]; ++k) {
        const int t = q.incidence.entry[k] >> 4, a = q.incidence.entry[k] & 15;
        const std::array<int, 10>& slot = A.quadratic_slot[k];
        if (terms.side_of[t] >= 0) {
            const QuadraticSideBlocks& b = terms.side[terms.side_of[t]];
            for (int p = 0; p < b.count; ++p) add_point_row(b.r[p], b.lambda_w[p], b.mu_w[p], a, slot, A);
            if (b.lambda_mean_w != 0.0) add_point_row(b.rbar, b.lambda_mean_w, 0.0, a, slot, A);
            continue;
        }
        const QuadraticBlocks& b = terms.whole[t];
        for (int p = 0; p < 4; ++p) add_point_row(b.r[p], b.lambda_w, b.mu_w, a, slot, A);
        if (b.lambda_mean_w != 0.0) add_point_row(b.rbar, b.lambda_mean_w, 0.0, a, slot, A);
    }
}

}  // namespace xcut
