// An elliptical excision in 3D (docs/xfem.md, Several cuts per element): a lens drawn as chords of
// two arcs, each chord a scripted cut that overshoots its neighbours, frees the lens of the exact
// volume of the chords' polygon; scenes/excision.json does so on the sagging, stretched skin and a
// grasper lifts the piece out.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "engine/io/scene.h"
#include "systems/cut/pieces_system.h"
#include "systems/cut/scripted_cut_system.h"
#include "systems/pipeline.h"
#include "tests/surface_checks.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace excision_3d {
namespace {

using testing::cut_now;
using testing::grid;

// The lens of scenes/excision.json: tips 24 mm apart round (30.3, 20.7) mm, arcs of radius 20 mm,
// each drawn in `chords` chords; every chord overshoots its ends by 3.6 mm (more than a cell's
// diagonal: an element a cut ends inside is not cut by it).
constexpr double kR = 0.020, kHalf = 0.012, kPast = 0.0036, kThick = 0.002;
const Vec3 kCentre(0.0303, 0.0207, 0.0);

/// The vertical rectangles of the lens's chords, upper arc first, through z in [-10, 10] mm.
std::vector<std::vector<Vec3>> lens_chords(int chords) {
    const double d = std::sqrt(kR * kR - kHalf * kHalf), phi0 = std::asin(kHalf / kR);
    std::vector<std::vector<Vec3>> out;
    for (int sign : {1, -1}) {
        const Vec3 centre = kCentre - sign * d * Vec3::UnitY();
        for (int k = 0; k < chords; ++k) {
            const double p0 = -phi0 + 2.0 * phi0 * k / chords, p1 = -phi0 + 2.0 * phi0 * (k + 1) / chords;
            Vec3 a = centre + kR * Vec3(std::sin(p0), sign * std::cos(p0), 0.0);
            Vec3 b = centre + kR * Vec3(std::sin(p1), sign * std::cos(p1), 0.0);
            const Vec3 u = (b - a).normalized();
            a -= kPast * u, b += kPast * u;
            out.push_back({Vec3(a.x(), a.y(), -0.01), Vec3(b.x(), b.y(), -0.01), Vec3(b.x(), b.y(), 0.01), Vec3(a.x(), a.y(), 0.01)});
        }
    }
    return out;
}

/// The volume the chords enclose through the skin's thickness: per arc, its chords' triangles from
/// the arc's centre less the triangle from the centre to the tips.
double chord_lens_volume(int chords) {
    const double d = std::sqrt(kR * kR - kHalf * kHalf), theta = 2.0 * std::asin(kHalf / kR) / chords;
    return 2.0 * (0.5 * chords * kR * kR * std::sin(theta) - kHalf * d) * kThick;
}

/// The default skin patch (60 x 40 x 2 mm, 2 mm cells) at rest, cutting elements again.
World skin_patch() {
    World w = testing::world_from_mesh(generate_box(grid({0.06, 0.04, kThick}, {30, 20, 1})));
    w.cut_state.recut = 1;
    prepare_enrichment(w);
    return w;
}

/// The smaller piece's volume once the pieces are counted; 0 unless there are two.
double freed_volume(World& w) {
    count_pieces(w);
    return w.pieces.volume.size() == 2 ? std::min(w.pieces.volume[0], w.pieces.volume[1]) : 0.0;
}

// At rest, 3 or 4 chords per arc (25 and 18 degrees between neighbours). Before the rules of
// 2026-12-02 neither freed its lens: past a joint a chord's nodes kept the sides the previous chord
// gave (one incision within 30 degrees), so elements it crossed were split by the other's sides
// (4 chords) or not at all where its polygon faced the other way (3 chords).
TEST(Excision3d, ALensDrawnInChordsFreesThePolygonItEncloses) {
    for (int chords : {3, 4}) {
        World w = skin_patch();
        for (const auto& chord : lens_chords(chords)) EXPECT_GT(cut_now(w, chord), 0);
        EXPECT_NEAR(freed_volume(w), chord_lens_volume(chords), 1e-9 * chord_lens_volume(chords)) << chords << " chords";
    }
}

// The eight chords cut at one time (one batch of events): an element two of them cross is cut by
// the first and then again by the second, as a step later (the second's event was dropped before,
// and the lens stayed joined).
TEST(Excision3d, ChordsCutAtOneTimeFreeTheSameLens) {
    World w = skin_patch();
    for (const auto& chord : lens_chords(4)) queue_polygon_cut(w, chord);
    EXPECT_GT(apply_cut_events(w), 0);
    EXPECT_TRUE(w.pending_cuts.empty());
    EXPECT_NEAR(freed_volume(w), chord_lens_volume(4), 1e-9 * chord_lens_volume(4));
}

/// scenes/excision.json run to `until` [s], its chords drawn in `frame`.
std::unique_ptr<Simulation> run_excision(const std::string& frame, double until) {
    std::ifstream in(std::string(XCUT_SOURCE_DIR) + "/scenes/excision.json");
    nlohmann::json j;
    in >> j;
    for (auto& cut : j["cuts"]) cut["frame"] = frame;
    auto sim = make_simulation(load_scene_text(j.dump(), "excision", "."), /*with_output=*/false);
    while (sim->world.time < until - 1e-9) step_simulation(*sim);
    return sim;
}

// The scene: the chords are cut one by one (0.2-0.9 s) while the grasper holds the lesion, the
// skin sags under gravity and the wound opens under the skin's tension; drawn on the skin at rest
// they cut the material they were drawn on and free the lens of its exact volume, whose surface is
// then a closed part of its own that the grasper lifts 15 mm (1.0-2.5 s).
TEST(Excision3d, TheSceneFreesTheLensAndTheGrasperLiftsItOut) {
    auto sim = run_excision("rest", 2.6);
    const World& w = sim->world;
    ASSERT_EQ(w.pieces.log.size(), 1u) << "one piece freed";
    EXPECT_NEAR(w.pieces.log[0].volume, chord_lens_volume(4), 1e-9 * chord_lens_volume(4));
    const SurfaceMesh& s = w.visual;
    testing::check_closed_oriented(s);
    EXPECT_EQ(zero_area_triangles(s), 0);
    int count = 0;
    const std::vector<int> comp = testing::components_of(s, count);
    ASSERT_EQ(count, 2);
    std::array<double, 2> z{0.0, 0.0}, area{0.0, 0.0};
    for (size_t t = 0; t < s.triangles.size(); ++t) {  // each part's mean height, weighted by area
        const auto& tri = s.triangles[t];
        const double a = (s.position[tri[1]] - s.position[tri[0]]).cross(s.position[tri[2]] - s.position[tri[0]]).norm();
        z[comp[t]] += a * (s.position[tri[0]].z() + s.position[tri[1]].z() + s.position[tri[2]].z()) / 3.0;
        area[comp[t]] += a;
    }
    const int lens = area[0] < area[1] ? 0 : 1;
    EXPECT_GT(z[lens] / area[lens], z[1 - lens] / area[1 - lens] + 0.01) << "the lens is lifted above the skin";
}

}  // namespace
}  // namespace excision_3d
}  // namespace xcut
