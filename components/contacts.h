#pragma once
// Tool-tissue contacts of the current step (paper §3.5): one per collision-surface vertex inside a
// tool's shape. A contact acts on the element the vertex is bound to (a virtual element once its
// side is cut, so a contact on one lip of a wound pushes that lip only) and is spread to that
// element's DOF nodes with the vertex's barycentric weights, the XFEM shape functions (eq. 4, 6).
#include <Eigen/Core>
#include <vector>

#include "components/nodes.h"

namespace xcut {

struct Contacts {
    std::vector<int> tool;                 ///< tool index
    std::vector<int> vertex;               ///< collision-surface vertex
    std::vector<int> element;              ///< force element the vertex is bound to
    std::vector<Eigen::Vector4d> bary;     ///< its barycentric weights there
    std::vector<Vec3> normal;              ///< unit, out of the tool: the push on the tissue
    std::vector<double> depth;             ///< penetration [m], > 0
    std::vector<double> stiffness;         ///< penalty k [N/m]: force k * depth along the normal
    std::vector<Vec3> force;               ///< force on the tissue at the vertex [N]

    int count() const { return static_cast<int>(tool.size()); }
    void clear() {
        tool.clear(), vertex.clear(), element.clear(), bary.clear(), normal.clear(), depth.clear();
        stiffness.clear(), force.clear();
    }
};

}  // namespace xcut
