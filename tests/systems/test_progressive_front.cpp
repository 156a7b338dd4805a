// The progressive crack front (cutter.front = "progressive", docs/xfem.md): an element is split the
// step the blade enters it, the crack-front rule holds the enriched DOFs of the split edges the blade
// has not crossed, so the wound opens at the blade and never ahead of it; the surfaces stay closed.
#include <gtest/gtest.h>

#include <set>

#include "systems/cut/cut_system.h"
#include "systems/cut/enrichment_system.h"
#include "systems/surface/mapping_system.h"
#include "systems/surface/surface_cut.h"
#include "systems/tool_system.h"
#include "tests/surface_checks.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

using testing::grid;
using testing::world_from_mesh;

constexpr double kX = 0.031;      // incision plane x [m], in the middle of a 2 mm cell
constexpr double kStopY = 0.011;  // the blade stops here [m], in the middle of a cell
constexpr double kDt = 0.01;      // [s]

Keyframe key(double t, double x, double y) {
    Keyframe k;
    k.time = t;
    k.position = Vec3(x, y, 0.0);
    return k;
}

/// Slab 40 x 20 x 4 mm (2 mm cells), visual surface, a scalpel through its thickness tilted by
/// `tilt` [m of x across the thickness], from y = 3 mm to kStopY in 0.4 s (20 mm/s), then still.
World slab(bool progressive, double tilt = 0.0) {
    World w = world_from_mesh(generate_box(grid({0.04, 0.02, 0.004}, {20, 10, 2})));
    add_scalpel(w, "scalpel", {key(0.0, kX, 0.003), key(0.4, kX, kStopY)}, Vec3(-tilt, 0, -0.001),
                Vec3(tilt, 0, 0.005));
    w.cut_state.progressive = progressive;
    build_surface(w, w.visual, 0);
    return w;
}

/// One step of the cutter alone (the body at rest): tool, CutSystem, enrichment, surface.
void cut_step(World& w, ElementBvh& bvh, int n) {
    w.time = n * kDt;
    advance_tools(w, w.time);
    run_cut_system(w, bvh);
    apply_cut_events(w);
    rebind_cut_vertices(w);
}

/// Where the cut crosses mesh edge a-b in the rest configuration [m]; the edge must be split.
Vec3 crossing(const World& w, int a, int b) {
    const double t = crack_edge_param(w, a, b);
    EXPECT_GE(t, 0.0);
    return w.nodes.rest[a] + t * (w.nodes.rest[b] - w.nodes.rest[a]);
}

/// The blade's farthest y so far [m].
double blade_y(double t) { return 0.003 + (kStopY - 0.003) * std::min(t / 0.4, 1.0); }

TEST(ProgressiveFront, SplitsAnElementTheStepTheBladeEntersIt) {
    for (bool progressive : {false, true}) {
        SCOPED_TRACE(progressive ? "progressive" : "semi");
        World w = slab(progressive);
        ElementBvh bvh;
        int partly_crossed_uncut = 0;
        for (int n = 1; n <= 45; ++n) {
            cut_step(w, bvh, n);
            for (const auto& [e, c] : w.cut_state.blade[0].crossing)
                partly_crossed_uncut += w.cuts.cut_of_element[e] < 0;
        }
        if (progressive) {
            EXPECT_EQ(partly_crossed_uncut, 0) << "every element the blade entered is split that step";
            for (double d : w.cut_state.delay_sim) EXPECT_EQ(d, 0.0);
        } else {
            EXPECT_GT(partly_crossed_uncut, 0) << "the semi-progressive front waits for full crossings";
        }
        ASSERT_GT(w.cuts.count(), 0);
    }
}

// Every node that has a phantom (its enriched DOF free) has each of its split edges crossed where
// the blade has been: the crack never opens ahead of the blade. Every element is split the step it
// is entered, and the last ones hold its front: some uncrossed edge is left where the blade stopped.
TEST(ProgressiveFront, CrackOpensUpToTheBladeAndNotBeyond) {
    World w = slab(true);
    ElementBvh bvh;
    for (int n = 1; n <= 45; ++n) {
        cut_step(w, bvh, n);
        const double reach = blade_y(w.time) + 1e-9;
        for (int c = 0; c < w.cuts.count(); ++c) {
            const int e = w.cuts.element[c];
            for (const auto& ed : kTetEdges) {
                const int i = w.elements.nodes[e][ed[0]], j = w.elements.nodes[e][ed[1]];
                if (w.enriched.sign[i] == w.enriched.sign[j]) continue;
                const bool open = w.enriched.phantom[i] >= 0 || w.enriched.phantom[j] >= 0;
                if (open && edge_crossed(w, i, j)) {
                    EXPECT_LE(crossing(w, i, j).y(), reach) << "step " << n;
                }
                if (!edge_crossed(w, i, j)) {  // where the blade has not been: behind its start, or at most
                                               // one quad (a mean edge of travel) behind it
                    EXPECT_TRUE(w.enriched.front_fixed[i] || w.enriched.phantom[i] >= 0);
                    const double y = crossing(w, i, j).y();
                    EXPECT_TRUE(y <= 0.003 + 1e-9 || y >= blade_y(w.time) - w.cut_state.mean_edge - 1e-9) << y;
                }
            }
        }
    }
    int held = 0;
    for (int j = 0; j < w.mesh_nodes; ++j) held += w.enriched.front_fixed[j] && w.enriched.phantom[j] < 0;
    EXPECT_GT(held, 0) << "the front where the blade stopped stays closed";
}

// The wound opens the step the blade enters an element: its virtual elements use a phantom at once
// (the nodes behind it are free). On the semi-progressive front it opens only once the elements
// around its crossed edges are fully crossed. Measured as CutElements::open_delay_sim.
TEST(ProgressiveFront, WoundOpensTheStepTheBladeEnters) {
    double worst[2] = {0.0, 0.0};
    int opened[2] = {0, 0};
    for (int p = 0; p < 2; ++p) {
        World w = slab(p == 1);
        ElementBvh bvh;
        for (int n = 1; n <= 45; ++n) cut_step(w, bvh, n);
        for (double d : w.cuts.open_delay_sim) worst[p] = std::max(worst[p], d);
        opened[p] = static_cast<int>(w.cuts.open_delay_sim.size());
        EXPECT_GT(opened[p], w.cuts.count() / 2);
    }
    EXPECT_LE(worst[1], kDt * (1.0 + 1e-9)) << "progressive: within one step";
    EXPECT_GE(worst[0], 2.0 * kDt) << "semi-progressive: the wound lags the blade";
    EXPECT_GT(opened[1], opened[0]) << "the progressive wound reaches further";
}

// The visual surface is a closed, oriented 2-manifold without zero-area triangles at every step,
// for a straight and a tilted blade, as the tip elements open edge by edge.
TEST(ProgressiveFront, SurfaceStaysClosedAsTheBladeAdvances) {
    for (double tilt : {0.0, 0.0005}) {
        SCOPED_TRACE(tilt);
        World w = slab(true, tilt);
        ElementBvh bvh;
        for (int n = 1; n <= 45; ++n) {
            cut_step(w, bvh, n);
            update_surface_positions(w);
            SCOPED_TRACE(n);
            testing::check_closed_oriented(w.visual);
            testing::expect_bound_to_live_elements(w, w.visual);
            ASSERT_EQ(zero_area_triangles(w.visual), 0);
            if (::testing::Test::HasFailure()) return;
        }
        EXPECT_GT(w.cuts.crossed_log.size(), 0u) << "tip elements had edges crossed after their split";
    }
}

}  // namespace
}  // namespace xcut
