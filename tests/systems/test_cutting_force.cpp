// The blade's cutting resistance (systems/cut/cutting_force.h): F = J_c w against the blade's advance,
// w the edge's length in the tissue, checked against the closed form of a straight edge through a box.
#include <gtest/gtest.h>

#include "systems/cut/cut_system.h"
#include "systems/cut/cutting_force.h"
#include "systems/cut/enrichment_system.h"
#include "engine/io/metrics_columns.h"
#include "engine/io/scene.h"
#include "engine/io/scene_checks.h"
#include "systems/pipeline.h"
#include "systems/tool_system.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

using testing::grid;
using testing::world_from_mesh;

constexpr double kToughness = 200.0;  // [J/m^2], porcine liver cut by a blade: 187-225 (docs/cutting-force.md)

Keyframe key(double t, const Vec3& p) {
    Keyframe k;
    k.time = t;
    k.position = p;
    return k;
}

/// Block 30 x 20 x 10 mm, 2 mm cells, interior nodes jittered (tets of every orientation), with a
/// vertical blade from z0 to z1 at x = 0.0151 moving in +y from y = 0.0031 at `speed` [m/s].
World block(double speed, double z0, double z1, double jitter = 0.25) {
    Material m;
    m.toughness = kToughness;
    World w = world_from_mesh(generate_box(grid({0.03, 0.02, 0.01}, {15, 10, 5}, jitter)), m);
    add_scalpel(w, "scalpel", {key(0.0, Vec3(0.0151, 0.0031, 0.0)), key(1.0, Vec3(0.0151, 0.0031 + speed, 0.0))},
                Vec3(0, 0, z0), Vec3(0, 0, z1));
    w.solver.dt = 0.01;
    return w;
}

/// The tools moved over the step ending at time t and the cutting forces there (no dynamics: the
/// body stays at rest).
void force_at(World& w, ElementBvh& bvh, double t) {
    w.time = t - w.solver.dt;
    advance_tools(w, w.time);
    advance_tools(w, t);
    compute_cutting_forces(w, bvh);
}

TEST(CuttingForce, IsToughnessTimesDepthAgainstTheAdvance) {
    for (const double z0 : {0.002, -0.004}) {  // fully inside; sticking out below the block
        World w = block(0.01, z0, 0.02);
        ElementBvh bvh;
        force_at(w, bvh, 0.2);
        const double depth = 0.01 - std::max(z0, 0.0);  // the edge's part in the block [m]
        EXPECT_NEAR(w.tools.blade_depth[0], depth, 1e-12 * depth);
        EXPECT_NEAR(w.tools.cutting_force[0].y(), -kToughness * depth, 1e-9) << "J_c w, against +y";
        EXPECT_NEAR(w.tools.cutting_force[0].x(), 0.0, 1e-12);
        EXPECT_NEAR(w.tools.cutting_force[0].z(), 0.0, 1e-12);
        EXPECT_EQ(w.tools.reaction_force[0], w.tools.cutting_force[0]) << "the tool's force carries it";
    }
}

TEST(CuttingForce, DoesNotDependOnSpeedAndFadesBelowTheFloor) {
    double force[3];
    const double speeds[3] = {0.005, 0.05, 0.25 * kCuttingSpeedFloor};
    for (int k = 0; k < 3; ++k) {
        World w = block(speeds[k], 0.002, 0.02);
        ElementBvh bvh;
            force_at(w, bvh, 0.1);
        force[k] = -w.tools.cutting_force[0].y();
    }
    EXPECT_NEAR(force[0], kToughness * 0.008, 1e-9);
    EXPECT_NEAR(force[1], force[0], 1e-12 * force[0]) << "rate-independent fracture work";
    EXPECT_NEAR(force[2], 0.25 * force[0], 1e-9) << "scaled down linearly below kCuttingSpeedFloor";
}

TEST(CuttingForce, StillOrOutsideTheTissueFeelsNothing) {
    World still = block(0.0, 0.002, 0.02);
    ElementBvh bvh;
    force_at(still, bvh, 0.1);
    EXPECT_GT(still.tools.blade_depth[0], 0.0);
    EXPECT_LT(still.tools.cutting_force[0].norm(), 1e-12) << "only the interpolation's rounding moves it";
    World above = block(0.01, 0.012, 0.03);  // the edge above the block
    ElementBvh bvh2;
    force_at(above, bvh2, 0.1);
    EXPECT_EQ(above.tools.blade_depth[0], 0.0);
    EXPECT_EQ(above.tools.cutting_force[0], Vec3::Zero());
}

TEST(CuttingForce, AStabFeelsOnlyTheFrictionOfTheLips) {
    World w = block(0.0, 0.002, 0.02);
    w.materials.list[0].blade_friction = 30.0;  // [N/m]
    w.tools.trajectory[0] = {key(0.0, Vec3(0.0151, 0.0031, 0.0)), key(1.0, Vec3(0.0151, 0.0031, -0.001))};
    ElementBvh bvh;
    force_at(w, bvh, 0.1);  // moving down along its own edge at 1 mm/s
    const double depth = w.tools.blade_depth[0];
    EXPECT_NEAR(depth, 0.01 - 0.0019, 1e-12);
    EXPECT_NEAR(w.tools.cutting_force[0].z(), 30.0 * depth, 1e-9) << "friction against the motion (-z)";
    EXPECT_NEAR(w.tools.cutting_force[0].y(), 0.0, 1e-12) << "an edge sliding along itself opens nothing";
}

// A stab cuts nothing today (an edge moving along itself sweeps no surface), and is not silent: the
// end of the run says how far the blade went that way.
TEST(CuttingForce, AStabIsReportedAtTheEndOfTheRun) {
    World w = block(0.0, 0.002, 0.02);
    w.tools.trajectory[0] = {key(0.0, Vec3(0.0151, 0.0031, 0.0)), key(1.0, Vec3(0.0151, 0.0031, -0.01))};
    ElementBvh bvh;
    for (int s = 1; s <= 100; ++s) force_at(w, bvh, 0.01 * s);
    ASSERT_EQ(w.cut_state.stab_travel.size(), 1u);
    EXPECT_NEAR(w.cut_state.stab_travel[0], 0.01, 1e-9) << "10 mm down its own edge, in the tissue throughout";
    bool said = false;
    for (const std::string& note : end_of_run_notes(w)) said = said || note.find("(a stab)") != std::string::npos;
    EXPECT_TRUE(said);
    World across = block(0.01, 0.002, 0.02);  // cutting across its edge: no stab
    for (int s = 1; s <= 100; ++s) force_at(across, bvh, 0.01 * s);
    EXPECT_EQ(across.cut_state.stab_travel[0], 0.0);
}

TEST(CuttingForce, LayersAddTheirToughnessTimesTheirDepth) {
    World w = block(0.01, 0.002, 0.02, 0.0);  // unjittered: the layers meet at z = 6 mm exactly
    Material fat = w.materials.list[0];
    fat.toughness = 4100.0;
    w.materials.list.push_back(fat);
    for (int e = 0; e < w.mesh_elements; ++e) {
        double z = 0.0;
        for (int a = 0; a < 4; ++a) z += 0.25 * w.nodes.rest[w.elements.nodes[e][a]].z();
        w.elements.material[e] = z < 0.006 ? 1 : 0;
    }
    ElementBvh bvh;
    force_at(w, bvh, 0.1);
    EXPECT_NEAR(-w.tools.cutting_force[0].y(), 4100.0 * 0.004 + kToughness * 0.004, 1e-9);
}

// An edge lying in the faces between elements (a blade on a grid plane) counts once.
TEST(CuttingForce, AnEdgeInTheFacesBetweenElementsCountsOnce) {
    Material m;
    m.toughness = kToughness;
    World w = world_from_mesh(generate_box(grid({0.03, 0.02, 0.01}, {15, 10, 5})), m);
    add_scalpel(w, "scalpel", {key(0.0, Vec3(0.014, 0.004, 0.0)), key(1.0, Vec3(0.014, 0.014, 0.0))}, Vec3(0, 0, 0.002),
                Vec3(0, 0, 0.02));
    w.solver.dt = 0.01;
    ElementBvh bvh;
    force_at(w, bvh, 0.1);
    EXPECT_NEAR(w.tools.blade_depth[0], 0.008, 1e-12);
}

// Through XFEM's split elements: each virtual element holds its side's material only, so a blade
// inside the elements it has split (the progressive front splits them at once) keeps its depth.
TEST(CuttingForce, SplitElementsKeepTheDepthOnce) {
    for (const bool progressive : {false, true}) {
        World w = block(0.01, 0.002, 0.02);
        w.cut_state.progressive = progressive;
        ElementBvh cut_bvh, bvh;
        for (int s = 1; s <= 60; ++s) {
            advance_tools(w, 0.01 * s);
            run_cut_system(w, cut_bvh);
            apply_cut_events(w);
            w.time = 0.01 * s;
        }
        ASSERT_GT(w.cuts.count(), 20) << (progressive ? "progressive" : "semi");
        compute_cutting_forces(w, bvh);
        EXPECT_NEAR(w.tools.blade_depth[0], 0.008, 1e-9) << (progressive ? "progressive" : "semi");
        EXPECT_NEAR(w.tools.cutting_force[0].y(), -kToughness * 0.008, 1e-6);
        // Drawn back 3 mm along its own wound (1.5 cells): no friction here, and the toughness only
        // where the edge is in elements the cut has not split: the row at its tip, which the tip's
        // own front crossed partly (a small part of the forward force, against the motion).
        w.tools.trajectory[0] = {key(0.6, w.tools.position[0]), key(0.9, w.tools.position[0] - Vec3(0, 0.003, 0))};
        for (int s = 61; s <= 90; ++s) {
            advance_tools(w, 0.01 * s);
            run_cut_system(w, cut_bvh);
            apply_cut_events(w);
            w.time = 0.01 * s;
        }
        compute_cutting_forces(w, bvh);
        EXPECT_NEAR(w.tools.blade_depth[0], 0.008, 1e-9);
        const Vec3 back = w.tools.cutting_force[0];
        EXPECT_GE(back.y(), 0.0) << "against the motion (-y)";
        EXPECT_LT(back.y(), 0.1 * kToughness * 0.008) << (progressive ? "progressive" : "semi");
    }
}

TEST(CuttingForce, TwoDimensionsUseTheThickness) {
    Material m;
    m.toughness = kToughness;
    m.thickness = 0.003;
    World w = world_from_mesh(generate_plate(grid({0.03, 0.02, 0.0}, {15, 10, 1}, 0.2)), m);
    add_scalpel(w, "scalpel", {key(0.0, Vec3(0.0151, 0.0031, 0.0)), key(1.0, Vec3(0.0151, 0.0131, 0.0))},
                Vec3(0, 0, 0), Vec3(0, 0.001, 0));
    w.solver.dt = 0.01;
    ElementBvh bvh;
    force_at(w, bvh, 0.1);
    EXPECT_NEAR(w.tools.blade_depth[0], 0.003, 1e-15);
    EXPECT_NEAR(w.tools.cutting_force[0].y(), -kToughness * 0.003, 1e-12);
}

// The default scene end to end: mid-incision its scalpel feels the skin's toughness (1700 J/m^2)
// times its edge's depth in the 2 mm skin, in the tool's force and the metrics' columns.
TEST(CuttingForce, TheDefaultScenesScalpelFeelsTheSkin) {
    const Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json",
                                   {"output.vtu=false", "output.metrics_csv=false"});
    auto sim = make_simulation(scene, false);
    World& w = sim->world;
    while (w.time < 0.7 - 1e-9) step_simulation(*sim);  // the blade cuts along y from 0.2 to 1.2 s
    const double depth = w.tools.blade_depth[0];
    EXPECT_GT(depth, 0.0019) << "the edge spans the 2 mm skin (sagging a little)";
    EXPECT_LE(depth, 0.0021);
    const Vec3 f = w.tools.reaction_force[0];
    EXPECT_NEAR(f.y(), -1700.0 * depth, 1e-6 * 1700.0 * depth) << "against its advance along +y";
    int split_total = 0;
    double column = 0.0;
    for (const MetricColumn& c : metric_columns(w, split_total))
        if (c.name == "scalpel_cut_fy_N") column = c.value;
    EXPECT_EQ(column, f.y());
}

}  // namespace
}  // namespace xcut
