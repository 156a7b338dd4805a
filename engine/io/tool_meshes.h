#pragma once
// Triangle meshes of the tools at their current poses, for pictures (engine/io/render.h): each
// contact shape (sphere, capsule, box, mesh) and each blade, the blade as a thin triangle from its
// edge backwards. Positions in world [m].
#include <array>
#include <vector>

#include "components/tools.h"

namespace xcut {

struct ToolTriangles {
    std::vector<Vec3> position;
    std::vector<std::array<int, 3>> triangles;
    std::vector<uint8_t> blade;  ///< per triangle: 1 on a blade, 0 on a contact shape
};

/// Every tool of `tools`; `size` [m] sets the blade's back (a fifth of the edge, at least `size`).
ToolTriangles tool_triangles(const ToolBodies& tools, double size);

}  // namespace xcut
