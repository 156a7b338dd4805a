// The shipped scenes that read mesh files made by the real programs (scenes/meshes/, remade by
// tools/make_scene_meshes.sh): each loads, is cut where its description says, and renders the wound.
#include <gtest/gtest.h>

#include <set>

#include "engine/io/render.h"
#include "engine/io/scene.h"
#include "systems/pipeline.h"

namespace xcut {
namespace {

/// Steps `scene` (coarser dt, looser tolerance: the test is about the cut, not accuracy) to t = 1.3 s.
std::unique_ptr<Simulation> run_to_the_cut(Scene scene) {
    scene.solver.dt = 0.026;
    scene.solver.cg_tolerance = 1e-4;
    auto sim = make_simulation(scene, false);
    for (int i = 0; i < 50; ++i) step_simulation(*sim);
    return sim;
}

// The incision crosses skin and fat into the muscle: split elements in all three regions, each
// with its own material.
TEST(ShippedMeshScenes, LayeredIncisionCutsThroughEveryLayer) {
    const Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/layered_incision.json");
    auto sim = run_to_the_cut(scene);
    const World& w = sim->world;
    ASSERT_EQ(w.materials.list.size(), 3u);
    std::set<std::string> layers;
    for (int c = 0; c < w.cuts.count(); ++c) layers.insert(w.materials.list[w.elements.material[w.cuts.element[c]]].name);
    EXPECT_EQ(layers, (std::set<std::string>{"skin", "fat", "muscle"}));
    const Image img = render_surface(w.visual, scene.camera);
    int wound = 0;
    for (size_t p = 0; p < img.triangle.size(); ++p) wound += img.triangle[p] >= 0 && w.visual.cut_face.size() > 0 &&
                                                              w.visual.cut_face[img.triangle[p]];
    EXPECT_GT(wound, 50) << "the render shows the wound's cut faces";
}

// The organ is a surface in mm, tetrahedralized on load; the blade cuts into its lobe.
TEST(ShippedMeshScenes, OrganFromSurfaceLoadsInMetresAndIsCut) {
    const Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/organ_from_surface.json");
    auto sim = run_to_the_cut(scene);
    const World& w = sim->world;
    double x_max = -1.0;
    for (int i = 0; i < w.mesh_nodes; ++i) x_max = std::max(x_max, w.nodes.rest[i].x());
    EXPECT_NEAR(x_max, 0.115, 0.003) << "the 195 mm organ, scaled from mm to m";
    EXPECT_GT(w.cuts.count(), 10);
    for (int c = 0; c < w.cuts.count(); ++c)
        for (int a = 0; a < 4; ++a) EXPECT_GT(w.nodes.rest[w.elements.nodes[w.cuts.element[c]][a]].x(), 0.07) << "in the lobe";
}

}  // namespace
}  // namespace xcut
