#pragma once
// Where a cut meets an element's edge, for both cutters (the blade's, systems/cut/cut_system.h, and
// the scripted one's): the edge is the chord between its corners, or a quadratic element's curve
// through its mid-edge node (systems/kernels/intersection.h); its parameter is the rest edge's.
#include "engine/world.h"

namespace xcut {

/// The point at parameter t of local edge k of element e [m], its nodes at `x` (current positions
/// unless given: the rest ones for a cut drawn on the body at rest).
Vec3 edge_point(const World& w, int e, int k, double t, const std::vector<Vec3>* x = nullptr);
/// The parameter where local edge k of element e (nodes at `x`, as edge_point) meets the plane
/// through o with normal n; 0.5 for a chord in the plane's direction.
double plane_edge_param(const World& w, int e, int k, const Vec3& o, const Vec3& n, const std::vector<Vec3>* x = nullptr);

}  // namespace xcut
