// Pieces of tissue (systems/cut/pieces_system.h): a cut through a body frees the part it closes
// off, counted with its exact rest volume (the cut's volume fractions are exact), for both cutters
// and through the whole pipeline.
#include <gtest/gtest.h>

#include "systems/cut/pieces_system.h"
#include "systems/pipeline.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

using testing::cut_now;
using testing::grid;
using testing::square_on_plane;

constexpr double kBarVolume = 0.1 * 0.01 * 0.01;  // 100 x 10 x 10 mm [m^3]

/// The 100 x 10 x 10 mm bar (100 x 10 mm strip of thickness 10 mm), clamped at x = 0.
World bar(int dim) {
    Material m;
    m.young = 1e5, m.poisson = 0.3, m.density = 1000.0, m.thickness = 0.01;
    const MeshData mesh = dim == 3 ? generate_box(grid({0.1, 0.01, 0.01}, {10, 2, 2}))
                                   : generate_plate(grid({0.1, 0.01, 0}, {10, 2, 1}));
    World w;
    w.materials.list = {m};
    w.constraints.boxes.push_back({Vec3(-1, -1, -1), Vec3(1e-9, 1, 1), 7});
    build_bodies(w, mesh);
    prepare_enrichment(w);
    return w;
}

std::vector<Vec3> across(int dim, double x) {
    if (dim == 2) return {Vec3(x, -1, 0), Vec3(x, 1, 0)};
    return square_on_plane(Vec3(x, 0.005, 0.005), Vec3(1, 0, 0), 1.0);
}

class PiecesOfABar : public ::testing::TestWithParam<int> {};

TEST_P(PiecesOfABar, ACutThroughFreesTheEndWithItsExactVolume) {
    const int dim = GetParam();
    World w = bar(dim);
    EXPECT_TRUE(count_pieces(w));
    EXPECT_EQ(w.pieces.count, 1);
    EXPECT_EQ(w.pieces.initial, 1);
    EXPECT_FALSE(count_pieces(w)) << "nothing changed: not counted again";
    const int layer = dim == 3 ? 2 * 2 * 6 : 2 * 2;  // the elements of one layer of cells
    ASSERT_EQ(cut_now(w, across(dim, 0.035)), layer);
    ASSERT_TRUE(count_pieces(w));
    ASSERT_EQ(w.pieces.count, 2);
    ASSERT_EQ(w.pieces.volume.size(), 2u);
    EXPECT_NEAR(w.pieces.volume[0], 0.35 * kBarVolume, 1e-12 * kBarVolume);  // the clamped one first
    EXPECT_NEAR(w.pieces.volume[1], 0.65 * kBarVolume, 1e-12 * kBarVolume);
    EXPECT_EQ(w.pieces.anchored, (std::vector<uint8_t>{1, 0}));
    ASSERT_EQ(w.pieces.log.size(), 1u);
    EXPECT_NEAR(w.pieces.log[0].volume, 0.65 * kBarVolume, 1e-12 * kBarVolume);
    EXPECT_FALSE(w.pieces.log[0].anchored);

    // A second cut through the free part: three pieces; the smaller part is the one it freed. It
    // splits its own layer only (the sides the first cut fixed are not this plane's: before, the
    // layer at 40-50 mm, whose nodes the two planes put on different sides, was split too).
    ASSERT_EQ(cut_now(w, across(dim, 0.075)), layer);
    ASSERT_TRUE(count_pieces(w));
    ASSERT_EQ(w.pieces.count, 3);
    ASSERT_EQ(w.pieces.log.size(), 2u);
    EXPECT_NEAR(w.pieces.log[1].volume, 0.25 * kBarVolume, 1e-12 * kBarVolume);
    double sum = 0.0;
    for (double v : w.pieces.volume) sum += v;
    EXPECT_NEAR(sum, kBarVolume, 1e-12 * kBarVolume);
    EXPECT_NE(pieces_report(w).find("cuts freed 2"), std::string::npos) << pieces_report(w);
}

TEST_P(PiecesOfABar, ACutPartWayThroughFreesNothing) {
    const int dim = GetParam();
    World w = bar(dim);
    count_pieces(w);
    // Through the upper half of the bar only: the crack-front rule keeps both sides joined.
    const std::vector<Vec3> half = dim == 2 ? std::vector<Vec3>{Vec3(0.055, 0.0051, 0), Vec3(0.055, 1, 0)}
                                            : std::vector<Vec3>{Vec3(0.055, -1, 0.0051), Vec3(0.055, 1, 0.0051),
                                                                Vec3(0.055, 1, 1), Vec3(0.055, -1, 1)};
    ASSERT_GT(cut_now(w, half), 0);
    ASSERT_TRUE(count_pieces(w));
    EXPECT_EQ(w.pieces.count, 1);
    EXPECT_TRUE(w.pieces.log.empty());
    EXPECT_EQ(pieces_report(w), "");
}

INSTANTIATE_TEST_SUITE_P(Dims, PiecesOfABar, ::testing::Values(3, 2));

/// The bar as a scene: clamped at x = 0, gravity -z, cut through at 35 mm (t = 0.02 s) and 75 mm
/// (t = 0.05 s) by scripted polygons, with the given cutter.
std::unique_ptr<Simulation> cut_bar_scene(const std::string& cutter, double gravity) {
    const std::string text = R"({
      "mesh": {"generator": "box", "origin": [0, 0, 0], "size": [0.1, 0.01, 0.01], "element_size": 0.01},
      "material": {"young": 1e5, "poisson": 0.3, "density": 1000},
      "gravity": [0, 0, )" + std::to_string(gravity) + R"(],
      "constraints": {"fixed_boxes": [{"min": [-1, -1, -1], "max": [1e-6, 1, 1]}]},
      "cutter": {"type": ")" + cutter + R"("},
      "cuts": [
        {"time": 0.02, "polygon": [[0.035, -1, -1], [0.035, 1, -1], [0.035, 1, 1], [0.035, -1, 1]]},
        {"time": 0.05, "polygon": [[0.075, -1, -1], [0.075, 1, -1], [0.075, 1, 1], [0.075, -1, 1]]}],
      "solver": {"dt": 0.005},
      "steps": 30
    })";
    return make_simulation(load_scene_text(text, "cut bar", "."), /*with_output=*/false);
}

class PiecesInAScene : public ::testing::TestWithParam<std::string> {};

TEST_P(PiecesInAScene, TwoCutsThroughABarFreeTwoPiecesThatFall) {
    auto sim = cut_bar_scene(GetParam(), -9.81);
    sim->scheduler.set_access_check(true);
    std::vector<int> count;
    for (int i = 0; i < 30; ++i) {
        step_simulation(*sim);
        count.push_back(sim->world.pieces.count);
    }
    const World& w = sim->world;
    EXPECT_EQ(count[2], 1);   // before the first cut
    EXPECT_EQ(count[6], 2);   // t = 0.035 s: after the first cut
    EXPECT_EQ(count.back(), 3);
    ASSERT_EQ(w.pieces.log.size(), 2u);
    // The planes cut the sagging (then falling) bar where it is now: volumes near the rest ones.
    EXPECT_NEAR(w.pieces.log[0].volume, 0.65 * kBarVolume, 1e-2 * kBarVolume);
    EXPECT_NEAR(w.pieces.log[1].volume, 0.25 * kBarVolume, 1e-2 * kBarVolume);
    EXPECT_FALSE(w.pieces.log[0].anchored);
    // The freed end falls (the step is stable and the piece is simulated, not dropped): the nodes
    // that started at the bar's far end have dropped by more than the clamped bar's sag would let
    // them, and stay within a free fall from the first cut (implicit Euler: 1/2 g h^2 n (n + 1))
    // plus the piece's turn (its 25 mm length).
    double lowest = 0.0;
    for (int i = 0; i < w.nodes.count(); ++i)
        if (w.nodes.rest[i].x() > 0.0999) lowest = std::min(lowest, w.nodes.position[i].z() - w.nodes.rest[i].z());
    EXPECT_LT(lowest, -0.25 * 9.81 * 0.1 * 0.1) << "fell over the last 0.1 s";
    EXPECT_GT(lowest, -0.5 * 9.81 * 0.005 * 0.005 * 30 * 31 - 0.025) << "no faster than free fall from the start";
}

TEST_P(PiecesInAScene, AFreedPieceWithoutGravityStaysBounded) {
    auto sim = cut_bar_scene(GetParam(), 0.0);
    for (int i = 0; i < 30; ++i) step_simulation(*sim);
    const World& w = sim->world;
    EXPECT_EQ(w.pieces.count, 3);
    // Both cutters cut mid-cell (no node within the snapping threshold) of the bar at rest: exact.
    ASSERT_EQ(w.pieces.log.size(), 2u);
    EXPECT_NEAR(w.pieces.log[0].volume, 0.65 * kBarVolume, 1e-12 * kBarVolume);
    EXPECT_NEAR(w.pieces.log[1].volume, 0.25 * kBarVolume, 1e-12 * kBarVolume);
    for (int i = 0; i < w.nodes.count(); ++i)
        ASSERT_LT((w.nodes.position[i] - w.nodes.rest[i]).norm(), 1e-6) << "node " << i << " drifted";
}

INSTANTIATE_TEST_SUITE_P(Cutters, PiecesInAScene, ::testing::Values("xfem", "snap"));

}  // namespace
}  // namespace xcut
