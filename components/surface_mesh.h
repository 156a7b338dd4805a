#pragma once
// A triangle surface carried by the simulation mesh (paper §3.2, §3.4): the visual surface (and
// later, separately, the collision surface). Each vertex is bound barycentrically to one element,
// a mesh element while that is whole, afterwards the virtual element of the vertex's side of the cut
// (the alternative mesh, Fig. 5). A reverse index from mesh elements to their bound vertices lets
// a cut re-bind only the vertices of the elements it split.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <map>
#include <vector>

#include "components/nodes.h"

namespace xcut {

struct SurfaceMesh {
    std::vector<Vec3> position;              ///< current positions [m], from the bindings
    std::vector<int> element;                ///< binding: force element (mesh or virtual)
    std::vector<Eigen::Vector4d> bary;       ///< barycentric coordinates in that element's rest shape
    std::vector<std::array<int, 3>> triangles;  ///< outward-oriented
    std::vector<int> triangle_owner;         ///< mesh element whose face (or cut) holds the triangle
    std::vector<uint8_t> cut_face;           ///< 1: a triangle of the internal cut surface (§3.4)
    std::vector<std::vector<int>> bound_to;  ///< per mesh element: the vertices bound to it
    std::vector<std::vector<int>> triangles_of;  ///< per mesh element: the skin triangles it owns
    /// Cut vertices by (side, rest position quantized to 1e-11 m): a point made once per side, reused
    /// by every element and triangle that meets it (the paper's "existing or future points").
    std::map<std::array<int64_t, 4>, int> cut_point;
    int cuts_mapped = 0;                     ///< cut elements already re-bound (CutElements index)
    int last_rebound = 0;                    ///< vertices re-bound by the last mapping update

    int vertex_count() const { return static_cast<int>(position.size()); }
};

}  // namespace xcut
