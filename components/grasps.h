#pragma once
// Graspers: a tool whose jaws close on the tissue's skin at a set time, hold it and let it go
// (docs/tools.md, Graspers). What the jaws hold is the skin's vertices within their radius when
// they close: each is pulled toward the point of the tool frame where it was held by a spring of
// the grasp's stiffness, spread to the DOF nodes of the element it is bound to with its
// barycentric weights (the XFEM shape functions, eq. 4, 6: a vertex on a freed piece pulls that
// piece). One entry per tool; a tool without "grasp" has radius 0.
#include <vector>

#include "components/nodes.h"

namespace xcut {

struct Grasps {
    // Settings, from the scene ("tools[i].grasp").
    std::vector<double> radius;     ///< jaws' reach around their centre [m]; 0: the tool does not grasp
    std::vector<Vec3> centre;       ///< the jaws' centre in the tool frame [m]
    std::vector<double> close;      ///< simulated time the jaws close [s]
    std::vector<double> open;       ///< simulated time they open again [s] (infinity: never)
    std::vector<double> stiffness;  ///< per held vertex [N/m]

    // State.
    enum State : uint8_t { kWaiting, kHolding, kReleased };
    std::vector<uint8_t> state;
    std::vector<uint8_t> surface;                ///< the skin held: 0 the collision surface, 1 the visual one
    std::vector<std::vector<int>> vertex;        ///< held vertices of that surface
    std::vector<std::vector<Vec3>> anchor;       ///< where each is held, tool frame [m]
    std::vector<int> held_at_close;              ///< how many vertices the jaws closed on (0: nothing)
    std::vector<Vec3> force;                     ///< the tissue's pull on the jaws over the last step [N]
    std::vector<double> peak_force;              ///< its largest magnitude over the run [N]
    /// The work the jaws put into the tissue over the last step, bounded above: |pull . held point's
    /// travel| summed over the held vertices, with the pull the step applies [J] (the watchdog's
    /// energy budget).
    double step_work = 0.0;

    int count() const { return static_cast<int>(radius.size()); }
    bool any() const {
        for (double r : radius)
            if (r > 0.0) return true;
        return false;
    }
};

}  // namespace xcut
