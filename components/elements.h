#pragma once
// Elements of the simulation mesh: tetrahedra (3D) or triangles in the xy plane (2D, plane stress).
// Hot per-step data (rotation, shape gradients) are kept apart from bookkeeping; about 200 bytes per
// tetrahedron in all (see docs/architecture.md for the budget).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "components/nodes.h"

namespace xcut {

struct Elements {
    int dim = 3;                                  ///< 3: tetrahedra, 2: triangles (plane stress)
    std::vector<std::array<int, 4>> nodes;        ///< node indices; triangles: [3] = -1
    std::vector<double> rest_volume;              ///< V [m^3]; triangles: area x thickness
    std::vector<Mat3> dm_inv;                     ///< inverse rest edge matrix Dm^-1 (2D: upper 2x2) [1/m]
    std::vector<Mat3> rotation;                   ///< R from the polar decomposition of F, frozen in a step
    std::vector<uint16_t> material;               ///< index into Materials
    std::vector<int> region;                      ///< the mesh region (Gmsh physical group...) it comes from; 0: none
    std::vector<int> body;                        ///< the scene body it belongs to (World::body_names)
    /// Share of the element's volume this element carries [-]: 1 for a mesh element, V_s/V for a
    /// virtual element (one side of a cut element), 0 for a mesh element that has been cut (its two
    /// virtual elements carry it from then on). Scales stiffness and mass alike.
    std::vector<double> weight;

    int count() const { return static_cast<int>(nodes.size()); }
    int nodes_per_element() const { return dim == 3 ? 4 : 3; }
};

/// Node -> element incidence (CSR), so forces are gathered per node in a fixed order: deterministic
/// for any thread count, with no floating-point atomics.
struct Incidence {
    std::vector<int> offset;   ///< size nodes+1
    std::vector<int> entry;    ///< element * 4 + local vertex index
};

}  // namespace xcut
