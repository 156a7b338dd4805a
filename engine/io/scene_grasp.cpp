#include "engine/io/scene_grasp.h"

#include <fmt/format.h>

#include <limits>

namespace xcut {

void read_tool_grasp(const JsonFields& t, Grasps& g) {
    const JsonFields grasp = t.object("grasp");
    grasp.allow_only({"radius", "centre", "close", "open", "stiffness"});
    const bool on = t.has("grasp");
    // Reach: 10 um to 10 cm [m]; stiffness 1e-3 to 1e6 N/m per held vertex.
    g.radius.push_back(on ? grasp.required_number("radius", 1e-5, 0.1) : 0.0);
    g.centre.push_back(grasp.vec3("centre", Vec3::Zero()));
    g.close.push_back(on ? grasp.required_number("close", 0.0, 1e6) : 0.0);
    const double never = std::numeric_limits<double>::infinity();
    g.open.push_back(grasp.has("open") ? grasp.required_number("open", 0.0, 1e6) : never);
    if (!(g.open.back() > g.close.back()))
        grasp.fail("open", fmt::format("{:g} s is not after \"close\" ({:g} s): the jaws open after they close",
                                       g.open.back(), g.close.back()));
    g.stiffness.push_back(grasp.number("stiffness", 10.0, 1e-3, 1e6));
    g.state.push_back(Grasps::kWaiting);
    g.surface.push_back(0);
    g.vertex.emplace_back();
    g.anchor.emplace_back();
    g.held_at_close.push_back(0);
    g.force.push_back(Vec3::Zero());
    g.peak_force.push_back(0.0);
}

}  // namespace xcut
