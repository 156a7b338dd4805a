#include "tools/bench/force_kernel_model.h"

#include "engine/world.h"
#include "systems/kernels/corotational_kernel.h"
#include "systems/kernels/polar_decomposition.h"

namespace xcut {

// FLOPS per tetrahedron (3D), as the code is written; add, sub, mul, div and sqrt count one each,
// negations and copies none. n = Newton iterations of the polar decomposition, r = nodes / elements.
//
// 1. update_rotations:                                                     105 + 143 n
//    edge matrix 9 (3 x 3 subs); F = Ds Dm^-1 45 (27 mul + 18 add); det F 14 (Eigen's 3 x 3:
//    3 x (2 mul, 1 sub, 1 mul) + 2 add); the singular test: |F|^2 17, |F| 18, two products 2.
//    Per Newton step 143: X^-1 42 (9 cofactors x 3, det 5, 1 div, 9 scalings); |X^-T| 18, |X| 18,
//    g = sqrt(ratio) 2; next = (g X + X^-T / g) / 2: 9 mul + 9 div + 9 add + 9 mul = 36;
//    |next - X| 9 + 18 = 27.
// 2. compute_forces, per element:                                          318
//    Lame parameters from the material 9 (lambda 6, mu 3), V x weight 1; corotational_forces 308:
//    edge matrix 9, F 45, H = R^T F - I 54 (45 + 9), stress 49 (eps = (H + H^T) / 2: 18,
//    trace 2, lambda tr I: 1 + 9, 2 mu eps: 1 + 9, sum 9), scatter 108 (scale R 9, (scale R) sigma
//    45, times Dm^-T 45, column sum 9), strain energy 43 (eps again 18, |eps|^2 17, 8 products
//    and sums).
// 3. gathers of the force and of diag(K): 3 adds per incidence entry, 4 entries per element: 2 x 12.
//    Energy sum 1. Gravity: 3 mul + 3 add per node: 6 r.
// 4. stiffness diagonal:                                                   173
//    Lame 9 + V 1; g_0 = -Dm^-T 1: 15; per node (4): R g 15, |g|^2 5, scalings and sums 17 = 37.
// Total: 621 + 143 n + 6 r (about 1340 at n = 5).
//
// BYTES per tetrahedron, read + written by each pass (STREAM's convention: a written array counts
// once, no write-allocate); node arrays reached through element indices count once per node per
// pass (the elements sharing a node are close in memory, so it stays in cache between them).
// Sizes: node ids 16, Dm^-1 72, R 72, material id 2, volume 8, weight 8, element buffer 4 x 24 = 96,
// incidence entries 4 x 4 = 16; per node: position 24, force 24, diag 24, mass 8, offsets 4 + 4.
// 1. rotations: ids, Dm^-1, write R; positions                             160 + 24 r
// 2. forces: ids, Dm^-1, R, material, volume, weight, write buffer and energy;
//    the energy vector's allocation zero-fills it (8); positions            290 + 24 r
// 3. gather: entries, buffer; offsets (mesh, virtual), write force            112 + 32 r
// 4. energy sum 8; gravity: force read + write, mass                          8 + 56 r
// 5. diagonal: Dm^-1, R, material, volume, weight, write buffer              258
// 6. gather of the diagonal                                                 112 + 32 r
// Total: 940 + 168 r (about 975 at this mesh's r = 0.21).
ForceKernelCounts force_system_counts(double n, double r) {
    ForceKernelCounts c;
    c.flops_per_element = 621.0 + 143.0 * n + 6.0 * r;
    c.bytes_per_element = 940.0 + 168.0 * r;
    return c;
}

// The CG's product K p per tetrahedron: Lame 9, V 1; H = R^T (edge matrix of p) Dm^-1: 9 + 45 + 45;
// stress 49; scatter 108; gather 12: 278 flops. Bytes: the element pass reads ids, Dm^-1, R,
// material, volume, weight and writes the buffer (274), p gathered once per node (24 r); the gather
// reads entries and buffer (112), offsets (8 r), writes the product (24 r): 386 + 56 r.
ForceKernelCounts stiffness_product_counts(double r) {
    ForceKernelCounts c;
    c.flops_per_element = 278.0;
    c.bytes_per_element = 386.0 + 56.0 * r;
    return c;
}

double mean_newton_iterations(const World& w) {
    const Elements& el = w.elements;
    if (el.dim != 3 || el.count() == 0) return 0.0;
    long total = 0;
    for (int e = 0; e < el.count(); ++e) {
        std::array<Vec3, 4> x;
        for (int a = 0; a < 4; ++a) x[a] = w.nodes.position[el.nodes[e][a]];
        int iterations = 0;
        extract_rotation(edge_matrix<3>(x) * el.dm_inv[e], el.rotation[e], &iterations);
        total += iterations;
    }
    return static_cast<double>(total) / el.count();
}

}  // namespace xcut
