#pragma once
// The Cauchy stress of an element for output, as the corotational model has it: F = Ds Dm^-1 from
// the current positions; R from the polar decomposition of F (by SVD, reflection-free); the small
// strain in the rotated frame eps = sym(R^T F) - I; sigma = R (lambda tr(eps) I + 2 mu eps) R^T
// (Mueller & Gross 2004, "Interactive virtual materials"; 2D: plane stress, sigma_zz = 0). Units: Pa.
// For a virtual element its own nodes (real or phantom) give its side's stress.
#include "engine/world.h"

namespace xcut {

Mat3 cell_cauchy_stress(const World& world, int element);
/// sqrt(3/2 s:s), s the deviator of sigma [Pa].
double von_mises(const Mat3& sigma);

}  // namespace xcut
