// The Embree renderer: a known silhouette, and the incision visible in the default scene.
#include <gtest/gtest.h>

#include <cstdio>

#include "engine/io/render.h"
#include "systems/pipeline.h"
#include "systems/surface/mapping_system.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

TEST(Render, BoxSilhouetteMatchesProjection) {
    // A 40 x 20 x 10 mm box seen straight down from 0.2 m above its top face's centre: the hit
    // pixels are the top face's perspective image, a rectangle computed here by the pinhole model.
    World w = testing::world_from_mesh(generate_box(testing::grid({0.04, 0.02, 0.01}, {4, 2, 1})));
    build_visual_surface(w, 0);
    Camera c;
    c.position = Vec3(0.02, 0.01, 0.21);
    c.target = Vec3(0.02, 0.01, 0.0);
    c.up = Vec3::UnitY();
    c.fov_deg = 20.0;
    c.width = 400, c.height = 300;
    const Image img = render_surface(w.visual, c);
    const double half_h = std::tan(10.0 * M_PI / 180.0), half_w = half_h * 400.0 / 300.0;
    const double depth = 0.2;  // to the top face
    int mismatched = 0, hits = 0;
    for (int row = 0; row < c.height; ++row)
        for (int col = 0; col < c.width; ++col) {
            const double sx = (2.0 * (col + 0.5) / c.width - 1.0) * half_w * depth;
            const double sy = (1.0 - 2.0 * (row + 0.5) / c.height) * half_h * depth;
            const bool inside = std::abs(sx) < 0.02 && std::abs(sy) < 0.01;
            const bool hit = img.triangle[row * c.width + col] >= 0;
            hits += hit;
            mismatched += inside != hit;
        }
    EXPECT_GT(hits, 10000);
    EXPECT_LT(mismatched, 0.01 * hits) << "only pixels along the silhouette's edge may differ";
}

TEST(Render, DefaultSceneShowsTheIncision) {
    auto render_after = [](bool with_scalpel) {
        Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json");
        scene.solver.dt = 0.03;
        scene.solver.cg_tolerance = 1e-4;
        if (!with_scalpel) scene.tools = ToolBodies{};
        auto sim = make_simulation(scene, false);
        for (int i = 0; i < 45; ++i) step_simulation(*sim);
        Camera c;
        c.position = Vec3(0.031, 0.02, 0.05);
        c.target = Vec3(0.031, 0.02, 0.0);
        c.fov_deg = 30.0;
        c.width = 200, c.height = 200;
        return render_surface(sim->world.visual, c);
    };
    const Image cut = render_after(true), whole = render_after(false);
    // Looking straight down on the incision line: with the cut, background or the wound's faces
    // show where the whole skin was.
    int opened = 0;
    for (size_t p = 0; p < cut.triangle.size(); ++p)
        opened += whole.triangle[p] >= 0 && (cut.triangle[p] < 0 ||
                                             std::abs(int(cut.rgb[3 * p + 1]) - int(whole.rgb[3 * p + 1])) > 60);
    std::printf("  pixels opened by the incision: %d of %zu\n", opened, cut.triangle.size());
    EXPECT_GT(opened, 50) << "pixels where the incision opens";
}

}  // namespace
}  // namespace xcut
