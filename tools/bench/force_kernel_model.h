#pragma once
// Work and traffic of one ForceSystem step per tetrahedron, counted by reading the code
// (systems/force_system.cpp, systems/kernels/corotational_kernel.h, systems/kernels/polar_decomposition.h and the
// Eigen 3.4 expressions they evaluate); the derivation is in force_kernel_model.cpp. With the
// measured ForceSystem time these give the kernel's achieved GFLOP/s and GB/s for the roofline.
// Hardware counters are not available on the benchmark VM (`perf stat -e cycles` reports "not
// supported"), so the counts are derived, not measured.

namespace xcut {

struct World;

struct ForceKernelCounts {
    double flops_per_element = 0;  ///< add, sub, mul, div, sqrt: one flop each
    double bytes_per_element = 0;  ///< read + written, STREAM's convention (no write-allocate)
    double intensity() const { return flops_per_element / bytes_per_element; }  ///< [flop/byte]
};

/// Counts per tetrahedron for a mesh with `nodes_per_element` = nodes / tetrahedra, when the polar
/// decomposition takes `newton_iterations` Newton steps on average.
ForceKernelCounts force_system_counts(double newton_iterations, double nodes_per_element);

/// Counts per tetrahedron of the CG's matrix-free product K p (stiffness_product: the element
/// pass and the gather), which the SolverSystem runs once per CG iteration.
ForceKernelCounts stiffness_product_counts(double nodes_per_element);

/// Mean Newton steps of the polar decomposition over the world's tetrahedra at their current
/// positions (what the ForceSystem's next step will take).
double mean_newton_iterations(const World& world);

}  // namespace xcut
