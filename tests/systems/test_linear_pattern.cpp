// The assembled system's block pattern after a split (systems/solver/linear_assembly.cpp): the rows
// a split changes are gathered again and the others carried over with their blocks shifted; the
// result must be the pattern gathered whole, block for block and slot for slot.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "engine/io/scene.h"
#include "systems/pipeline.h"
#include "systems/solver/linear_assembly.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

/// Steps the default skin with `overrides` and, at every step whose pattern was made again since
/// the last, rebuilds it whole in a copy and compares; returns how many rebuilds were compared.
int compare_rebuilds(const std::vector<std::string>& overrides, int steps) {
    Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json", overrides);
    scene.visual_subdivisions = scene.collision_subdivisions = -1;
    auto sim = make_simulation(scene, false);
    World& w = sim->world;
    uint64_t seen = w.linear.topology;
    int compared = 0, carried = w.linear.pattern.carried;
    for (int s = 0; s < steps; ++s) {
        step_simulation(*sim);
        if (w.linear.topology == seen) continue;
        seen = w.linear.topology;
        EXPECT_EQ(w.linear.pattern.carried, ++carried) << "the split's pattern was gathered whole";
        ++compared;
        SCOPED_TRACE("step " + std::to_string(w.step));
        const LinearSystem made = w.linear;
        w.linear.topology = 0;  // no pattern to carry over: gathered whole
        EXPECT_TRUE(ensure_linear_pattern(w));
        const LinearSystem& whole = w.linear;
        EXPECT_EQ(made.row_offset, whole.row_offset);
        EXPECT_EQ(made.column, whole.column);
        EXPECT_EQ(made.diagonal, whole.diagonal);
        EXPECT_EQ(made.mesh_slot, whole.mesh_slot);
        EXPECT_EQ(made.virtual_slot, whole.virtual_slot);
        w.linear = made;
        if (::testing::Test::HasFailure()) break;
    }
    return compared;
}

// The default incision: each split adds phantoms and virtual elements beside the earlier ones.
TEST(LinearPattern, RowsCarriedOverAtASplitEqualTheWholePattern) {
    EXPECT_GE(compare_rebuilds({}, 130), 10);
}

// An X incision cut again where it crosses the first wound (cutter.recut): virtual elements whose
// nodes change, not only new ones.
TEST(LinearPattern, RowsCarriedOverAtARecutEqualTheWholePattern) {
    EXPECT_GE(compare_rebuilds({testing::kCrossingScalpel, "cutter.recut=true"}, 210), 20);
}

}  // namespace
}  // namespace xcut
