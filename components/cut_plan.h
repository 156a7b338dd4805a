#pragma once
// Scripted cuts: a planar polygon (3D) or a segment (2D) applied at a given time, splitting every
// element it crosses completely. Lets XFEM be verified and scenes be cut without a tool.
#include <vector>

#include "components/nodes.h"

namespace xcut {

struct ScriptedCut {
    double time = 0.0;              ///< simulated time at which the cut is made [s]
    std::vector<Vec3> polygon;      ///< vertices, current configuration [m]; 2 points in 2D (a segment)
    /// The polygon is drawn on the body at rest ("frame": "rest"), as a surgeon marks the skin
    /// before cutting: it cuts the material it was drawn on wherever the tissue has moved since.
    bool at_rest = false;
    /// "front.radius" [m]: the crack front where the cut ends inside the tissue is enriched with
    /// the branch functions over the nodes within it (systems/cut/scripted_front_system.h); < 0: not.
    double front_radius = -1.0;
    bool applied = false;
    bool front_enriched = false;  ///< its front is in world.tips
};

struct CutPlan {
    std::vector<ScriptedCut> cuts;
    /// Elements already cut that a scripted cut crossed along another plane and did not cut again
    /// (where the world does not cut again, or the element holds kMaxElementLines): the end of the
    /// run says so.
    int recut_ignored = 0;
};

}  // namespace xcut
