#include "systems/kernels/quadratic_elastic.h"

#include "engine/parallel.h"

namespace xcut {
namespace {

Tet10Vectors gather(const std::array<int, 10>& ids, const Vec3* v) {
    Tet10Vectors out;
    for (int a = 0; a < 10; ++a) out[a] = v[ids[a]];
    return out;
}

double volume_of(const QuadraticView& v, int t) {
    const int e = v.quadratic.element[t];
    return v.elements.rest_volume[e] * v.elements.weight[e];
}

const Material& material_of(const QuadraticView& v, int t) {
    return v.materials.list[v.elements.material[v.quadratic.element[t]]];
}

}  // namespace

LameParameters quadratic_lame(const Material& m) { return {m.lambda(), m.mu()}; }

double quadratic_forces(const QuadraticView& v, const Vec3* x, std::vector<Tet10Vectors>& buffer) {
    const int n = v.quadratic.count();
    buffer.resize(n);
    std::vector<double> energy(n);
    parallel_for(n, [&](int t) {
        const int e = v.quadratic.element[t];
        energy[t] = tet10_forces(gather(v.quadratic.nodes[t], x), tet10_gradients(v.elements.dm_inv[e]),
                                 v.elements.rotation[e], volume_of(v, t), quadratic_lame(material_of(v, t)), buffer[t]);
    });
    return deterministic_sum(n, [&](int t) { return energy[t]; });
}

void quadratic_product_element(const QuadraticView& v, const Vec3* p, int t, std::vector<Tet10Vectors>& buffer) {
    const int e = v.quadratic.element[t];
    tet10_stiffness_product(gather(v.quadratic.nodes[t], p), tet10_gradients(v.elements.dm_inv[e]), v.elements.rotation[e],
                            volume_of(v, t), quadratic_lame(material_of(v, t)), buffer[t]);
}

void quadratic_products(const QuadraticView& v, const Vec3* p, std::vector<Tet10Vectors>& buffer) {
    buffer.resize(v.quadratic.count());
    parallel_for(v.quadratic.count(), [&](int t) { quadratic_product_element(v, p, t, buffer); });
}

void quadratic_diagonals(const QuadraticView& v, std::vector<Tet10Vectors>& buffer) {
    buffer.resize(v.quadratic.count());
    parallel_for(v.quadratic.count(), [&](int t) {
        const int e = v.quadratic.element[t];
        tet10_stiffness_diagonal(tet10_gradients(v.elements.dm_inv[e]), v.elements.rotation[e], volume_of(v, t),
                                 quadratic_lame(material_of(v, t)), buffer[t]);
    });
}

Vec3 quadratic_gathered(const QuadraticElements& q, const std::vector<Tet10Vectors>& buffer, int i) {
    Vec3 s = Vec3::Zero();
    if (i + 1 >= static_cast<int>(q.incidence.offset.size())) return s;
    for (int k = q.incidence.offset[i]; k < q.incidence.offset[i + 1]; ++k)
        s += buffer[q.incidence.entry[k] >> 4][q.incidence.entry[k] & 15];
    return s;
}

void quadratic_block_terms(const QuadraticView& v, double stiff_scale, std::vector<QuadraticBlocks>& terms) {
    terms.resize(v.quadratic.count());
    parallel_for(v.quadratic.count(), [&](int t) {
        const int e = v.quadratic.element[t];
        const Tet10Gradients G = tet10_gradients(v.elements.dm_inv[e]);
        const LameParameters lame = quadratic_lame(material_of(v, t));
        const double w = 0.25 * stiff_scale * volume_of(v, t);
        QuadraticBlocks& b = terms[t];
        b.lambda_w = w * lame.lambda, b.mu_w = w * lame.mu;
        for (int q = 0; q < 4; ++q)
            for (int j = 0; j < 10; ++j) b.r[q][j] = v.elements.rotation[e] * G.grad[q][j];
    }, 512);
}

void add_quadratic_row(const QuadraticElements& q, const std::vector<QuadraticBlocks>& terms, int i, LinearSystem& A) {
    if (i + 1 >= static_cast<int>(q.incidence.offset.size())) return;
    for (int k = q.incidence.offset[i]; k < q.incidence.offset[i + 1]; ++k) {
        const QuadraticBlocks& b = terms[q.incidence.entry[k] >> 4];
        const int a = q.incidence.entry[k] & 15;
        const std::array<int, 10>& slot = A.quadratic_slot[k];
        for (int p = 0; p < 4; ++p) {
            const Vec3 lambda_ra = b.lambda_w * b.r[p][a], mu_ra = b.mu_w * b.r[p][a];
            for (int c = 0; c < 10; ++c) add_corotational_stiffness_block(lambda_ra, mu_ra, b.r[p][c], 3, A.value.data() + 9 * slot[c]);
        }
    }
}

}  // namespace xcut
