// `xcut compare` pieces: the repeated incisions (offsets, times, duration) and the quality measures.
#include <gtest/gtest.h>

#include <cmath>

#include "tools/studies/compare.h"
#include "tools/studies/mesh_quality.h"
#include "systems/pipeline.h"

namespace xcut {
namespace {

TEST(Compare, IncisionsAlternateSidewaysOneAfterAnother) {
    const Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/face_skin_2d.json");
    const Incisions inc = repeated_incisions(scene, 5, 0.003);
    ASSERT_EQ(inc.scene.tools.count(), 5);
    ASSERT_EQ(inc.end_time.size(), 5u);
    const auto& first = scene.tools.trajectory[0];
    const double slot = first.back().time - first.front().time;  // 1.2 s
    const double offsets[5] = {0.0, 0.003, -0.003, 0.006, -0.006};  // across the path (y) and edge (z): x
    for (int k = 0; k < 5; ++k) {
        const auto& keys = inc.scene.tools.trajectory[k];
        ASSERT_EQ(keys.size(), first.size());
        for (size_t i = 0; i < keys.size(); ++i) {
            EXPECT_NEAR(keys[i].time, first[i].time + k * slot, 1e-12);
            EXPECT_NEAR(std::abs(keys[i].position.x() - first[i].position.x()), std::abs(offsets[k]), 1e-12);
            EXPECT_NEAR(keys[i].position.y(), first[i].position.y(), 1e-12);
            EXPECT_NEAR(keys[i].position.z(), first[i].position.z(), 1e-12) << "a flat body: no lift";
        }
        EXPECT_NEAR(inc.end_time[k], first.back().time + k * slot + 2 * scene.solver.dt, 1e-12);
    }
    EXPECT_GE(inc.scene.steps * scene.solver.dt, inc.end_time.back());
}

// Snapping on the default scene's repeated incisions: by step 443 two snaps in one step turned a
// sliver piece over (rest volume -3.7e-15 m^3), its stiffness was negative, and the factor and CG
// failed, so `xcut compare scenes/skin_slab.json` stopped. Such a piece keeps |V| now.
TEST(Compare, SnappingSurvivesTheSkinSlabsIncisions) {
    const Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json");
    Scene s = repeated_incisions(scene, 20, 0.0).scene;
    s.cutter = "snap";
    auto sim = make_simulation(s, /*with_output=*/false);
    for (int i = 0; i < 460; ++i) ASSERT_NO_THROW(step_simulation(*sim)) << "step " << i;
    const World& w = sim->world;
    EXPECT_GT(w.snap.inverted_pieces, 0) << "the case this guards happened";
    for (int e = 0; e < w.elements.count(); ++e) {
        if (w.elements.weight[e] > 0.0) {
            ASSERT_GT(w.elements.rest_volume[e], 0.0) << "element " << e;
        }
    }
}

TEST(Compare, QualityOfRegularSimplices) {
    const double regular_dihedral = std::acos(1.0 / 3.0);  // 70.53 deg
    const Vec3 a(1, 1, 1), b(1, -1, -1), c(-1, 1, -1), d(-1, -1, 1);
    EXPECT_NEAR(min_dihedral_angle(a, b, c, d), regular_dihedral, 1e-12);
    // The corner tetrahedron: 90 deg at the axes, acos(1/sqrt 3) = 54.7 deg against the slanted face.
    EXPECT_NEAR(min_dihedral_angle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)), std::acos(1 / std::sqrt(3.0)), 1e-12);
    EXPECT_NEAR(min_triangle_angle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, std::sqrt(0.75), 0)), M_PI / 3, 1e-12);
    EXPECT_NEAR(min_triangle_angle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)), M_PI / 4, 1e-12);
}

}  // namespace
}  // namespace xcut
