// Several cuts per element, 2D (systems/cut/recut.h; docs/xfem.md, Several cuts per element). The
// fragments' geometry against closed forms, and what crossing cuts make of a plate against the
// geometry of the lines alone: which elements are divided, the pieces, and their exact areas.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include <fmt/format.h>

#include "engine/fragment_geometry.h"
#include "engine/io/clipped_cells.h"
#include "engine/io/scene_checks.h"
#include "engine/parallel.h"
#include "systems/cut/pieces_system.h"
#include "systems/cut/recut.h"
#include "systems/kernels/disjoint_sets.h"
#include "systems/surface/mapping_system.h"
#include "systems/surface/surface_cut.h"
#include "systems/pipeline.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

using testing::cut_now;
using testing::grid;

constexpr uint32_t kBoth = (1u << kBoundBit) | (1u << (kBoundBit + 1));  // bounded by lines 0 and 1

TEST(FragmentGeometry, TwoLinesCrossingInATriangleGiveFourFragmentsOfTheirExactAreas) {
    const std::array<Vec3, 3> tri{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    const std::array<CutLine, 2> lines{CutLine{Vec3(0.3, 0, 0), Vec3(1, 0, 0)}, CutLine{Vec3(0, 0.2, 0), Vec3(0, 1, 0)}};
    // x >= 0.3, y >= 0.2 under x + y <= 1: a right triangle of legs 0.5; the others by integration.
    const double exact[4] = {0.06, 0.12, 0.195, 0.125};  // masks 00, 01 (x side), 10 (y side), 11
    double sum = 0.0;
    for (uint32_t side = 0; side < 4; ++side) {
        const double a = polygon_area(fragment_polygon(tri, lines.data(), 2, side | kBoth));
        EXPECT_NEAR(a, exact[side], 1e-15) << "mask " << side;
        sum += a;
    }
    EXPECT_NEAR(sum, 0.5, 1e-15);
    // Bounded by line 0 only: the half x >= 0.3 whole.
    EXPECT_NEAR(polygon_area(fragment_polygon(tri, lines.data(), 2, 1u | bound_by(0))), 0.245, 1e-15);
    // The hypotenuse (1 - s, s) in the fragment x >= 0.3, y >= 0.2: s in [0.2, 0.7].
    const auto part = segment_part(tri[1], tri[2], lines.data(), 2, 3u | kBoth);
    EXPECT_NEAR(part[0], 0.2, 1e-15);
    EXPECT_NEAR(part[1], 0.7, 1e-15);
    const auto none = segment_part(tri[0], tri[1], lines.data(), 2, 2u | kBoth);  // y >= 0.2: not the base
    EXPECT_LE(none[1], none[0]);
}

constexpr double kSide = 0.04, kThickness = 0.002;  // a 40 x 40 mm sheet, 2 mm thick [m]

/// The sheet in 8 x 8 cells of two triangles, held nowhere (no surface: elements are cut again).
World sheet() {
    Material m;
    m.young = 1e5, m.poisson = 0.3, m.density = 1000.0, m.thickness = kThickness;
    World w;
    w.materials.list = {m};
    build_bodies(w, generate_plate(grid({kSide, kSide, 0}, {8, 8, 1})));
    prepare_enrichment(w);
    return w;
}

std::vector<Vec3> segment(double x0, double y0, double x1, double y1) { return {Vec3(x0, y0, 0), Vec3(x1, y1, 0)}; }

/// The pieces' areas [m^2], smallest first.
std::vector<double> piece_areas(World& w) {
    count_pieces(w);
    std::vector<double> a;
    for (double v : w.pieces.volume) a.push_back(v / kThickness);
    std::sort(a.begin(), a.end());
    return a;
}

/// Whether every mesh element the line y = y0 crosses inside x in (x0, x1) has a cut along it: its
/// own first cut, or one of its lines, horizontal.
bool every_crossed_element_cut_along(const World& w, double y0, double x0, double x1) {
    for (int e = 0; e < w.mesh_elements; ++e) {
        double left = 1e9, right = -1e9;  // where the line crosses the element's edges
        for (int k = 0; k < 3; ++k) {
            const Vec3& A = w.nodes.rest[w.elements.nodes[e][kTriEdges[k][0]]];
            const Vec3& B = w.nodes.rest[w.elements.nodes[e][kTriEdges[k][1]]];
            if ((A.y() - y0) * (B.y() - y0) >= 0.0) continue;
            const double x = A.x() + (y0 - A.y()) / (B.y() - A.y()) * (B.x() - A.x());
            left = std::min(left, x), right = std::max(right, x);
        }
        if (!(std::min(right, x1) - std::max(left, x0) > 1e-9)) continue;
        const int c = w.cuts.cut_of_element[e];
        if (c < 0) return false;
        bool along = std::abs(w.cuts.points[c][0].y() - y0) < 1e-12 && std::abs(w.cuts.points[c][1].y() - y0) < 1e-12;
        for (const CutLine& l : w.cuts.lines[c])
            along = along || (std::abs(std::abs(l.normal.y()) - 1.0) < 1e-12 && std::abs(l.origin.y() - y0) < 1e-12);
        if (!along) return false;
    }
    return true;
}

TEST(Recut, AnXAcrossASheetDividesEveryElementEitherLineCrossesIntoFourPiecesOfTheirExactAreas) {
    World w = sheet();
    ASSERT_TRUE(recut_allowed(w));
    const double x = 0.0175, y = 0.0215;  // inside a cell's column and row
    EXPECT_EQ(cut_now(w, segment(x, -1, x, 1)), 16);
    EXPECT_EQ(cut_now(w, segment(-1, y, 1, y)), 16) << "14 whole elements and the 2 the first line cut";
    EXPECT_TRUE(every_crossed_element_cut_along(w, y, 0.0, kSide));
    const std::vector<double> areas = piece_areas(w);
    ASSERT_EQ(areas.size(), 4u);
    const std::vector<double> exact{x * (kSide - y), x * y, (kSide - x) * (kSide - y), (kSide - x) * y};
    std::vector<double> sorted = exact;
    std::sort(sorted.begin(), sorted.end());
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(areas[k], sorted[k], 1e-12 * kSide * kSide) << k;
    // The two elements cut twice: three or four fragments each, their areas the element's.
    int fragments = 0;
    for (int c = 0; c < w.cuts.count(); ++c) {
        if (w.cuts.lines[c].size() < 2) continue;
        double sum = 0.0;
        for (int v : w.cuts.fragments[c]) sum += w.elements.weight[w.virtual_elements.element[v]];
        EXPECT_NEAR(sum, 1.0, 1e-12);
        fragments += static_cast<int>(w.cuts.fragments[c].size());
    }
    EXPECT_EQ(fragments, 7) << "the triangle holding the crossing: 4, its cell's other: 3";
}

TEST(Recut, TheVolumeOutputWritesEachFragmentAsItsPolygon) {
    World w = sheet();
    const double x = 0.0175, y = 0.0215;
    cut_now(w, segment(x, -1, x, 1));
    cut_now(w, segment(-1, y, 1, y));
    const ClippedCells out = clipped_cells(w);
    std::map<int, double> of;  // rest area per force element
    double total = 0.0;
    for (size_t k = 0; k < out.cells.size(); ++k) {
        const auto& c = out.cells[k];
        const Vec3 a = out.rest[c[1]] - out.rest[c[0]], b = out.rest[c[2]] - out.rest[c[0]];
        const double area = 0.5 * (a.x() * b.y() - a.y() * b.x());
        EXPECT_GT(area, 0.0) << "cell " << k;
        of[out.element[k]] += area, total += area;
    }
    EXPECT_NEAR(total, kSide * kSide, 1e-12 * kSide * kSide) << "the cells tile the sheet";
    for (int c = 0; c < w.cuts.count(); ++c)
        for (int v : w.cuts.fragments[c]) {  // each fragment's cells: its weight's share of its element
            const int fe = w.virtual_elements.element[v];
            EXPECT_NEAR(of[fe], w.elements.weight[fe] * 0.005 * 0.005 / 2.0, 1e-12 * kSide * kSide);
        }
}

TEST(Recut, AClosedLoopFreesThePieceItEnclosesWithItsArea) {
    World w = sheet();
    const double x0 = 0.0115, x1 = 0.0285, y0 = 0.0135, y1 = 0.0265, over = 0.002;  // corners overshot 2 mm
    cut_now(w, segment(x0 - over, y0, x1 + over, y0));
    cut_now(w, segment(x1, y0 - over, x1, y1 + over));
    cut_now(w, segment(x1 + over, y1, x0 - over, y1));
    cut_now(w, segment(x0, y1 + over, x0, y0 - over));
    const std::vector<double> areas = piece_areas(w);
    ASSERT_EQ(areas.size(), 2u) << "the loop frees its piece";
    EXPECT_NEAR(areas[0], (x1 - x0) * (y1 - y0), 1e-12 * kSide * kSide);
    EXPECT_NEAR(areas[0] + areas[1], kSide * kSide, 1e-12 * kSide * kSide);
}

TEST(Recut, ACrossCutFromAWoundFreesAThirdPiece) {
    World w = sheet();
    const double x = 0.0175, y = 0.0215;
    cut_now(w, segment(x, -1, x, 1));
    ASSERT_EQ(piece_areas(w).size(), 2u);
    cut_now(w, segment(x, y, 1, y));  // from the wound to the sheet's edge: a T
    EXPECT_TRUE(every_crossed_element_cut_along(w, y, x, kSide));
    const std::vector<double> areas = piece_areas(w);
    ASSERT_EQ(areas.size(), 3u);
    EXPECT_NEAR(areas[0], (kSide - x) * (kSide - y), 1e-12 * kSide * kSide);
    EXPECT_NEAR(areas[1], (kSide - x) * y, 1e-12 * kSide * kSide);
    EXPECT_NEAR(areas[2], x * kSide, 1e-12 * kSide * kSide);
}

TEST(Recut, ALineAlongAnEarlierCutOrThroughNoFragmentDividesNothing) {
    World w = sheet();
    const double x = 0.0175;
    cut_now(w, segment(x, -1, x, 1));
    const int fragments = w.virtual_elements.count();
    EXPECT_EQ(cut_now(w, segment(x, -1, x, 1)), 0) << "the same line again";
    EXPECT_EQ(w.virtual_elements.count(), fragments);
}

// A scripted cut through an element that holds its last line, or in a world that does not cut again
// (3D), is counted and named at the end of the run, not dropped; the same cut again is not counted.
TEST(Recut, AScriptedCutAnElementCannotTakeIsCountedAndNamed) {
    World w = sheet();
    const Vec3 p(0.0175, 0.0215, 0.0);
    for (int k = 0; k < kMaxElementLines; ++k) {  // four lines through p, 36 degrees apart
        const double a = k * M_PI / 5.0;
        cut_now(w, {p - Vec3(std::cos(a), std::sin(a), 0), p + Vec3(std::cos(a), std::sin(a), 0)});
    }
    EXPECT_EQ(w.cut_plan.recut_ignored, 0) << "each element took its lines";
    const double a = 4.0 * M_PI / 5.0;
    cut_now(w, {p - Vec3(std::cos(a), std::sin(a), 0), p + Vec3(std::cos(a), std::sin(a), 0)});
    EXPECT_GE(w.cut_plan.recut_ignored, 1) << "the triangle holding p has its four lines";
    std::string notes;
    for (const std::string& n : end_of_run_notes(w)) notes += n + "\n";
    EXPECT_NE(notes.find("the scripted cuts crossed"), std::string::npos) << notes;

    World box = testing::world_from_mesh(generate_box(grid({0.02, 0.02, 0.02}, {3, 3, 3})));
    prepare_enrichment(box);
    ASSERT_FALSE(recut_allowed(box));
    cut_now(box, testing::square_on_plane(Vec3(0.0105, 0.0105, 0.0105), Vec3(1, 0, 0), 0.05));
    cut_now(box, testing::square_on_plane(Vec3(0.0105, 0.0105, 0.0105), Vec3(1, 0, 0), 0.05));
    EXPECT_EQ(box.cut_plan.recut_ignored, 0) << "the same plane again";
    cut_now(box, testing::square_on_plane(Vec3(0.0105, 0.0105, 0.0105), Vec3(0, 1, 0), 0.05));
    EXPECT_GT(box.cut_plan.recut_ignored, 0) << "the elements the first plane split";
}

/// The sheet's surface as the stress suite checks it: every directed edge used once, no triangle
/// without area; and its parts (triangles joined by a vertex) with their rest areas, smallest first.
std::vector<double> sheet_parts(const World& w, const SurfaceMesh& s) {
    std::map<std::pair<int, int>, int> used;
    for (const auto& t : s.triangles)
        for (int k = 0; k < 3; ++k) ++used[{t[k], t[(k + 1) % 3]}];
    for (const auto& [edge, n] : used) EXPECT_EQ(n, 1) << "edge " << edge.first << "-" << edge.second;
    EXPECT_EQ(zero_area_triangles(s), 0);
    DisjointSets parts(s.vertex_count());
    for (const auto& t : s.triangles) parts.join(t[0], t[1]), parts.join(t[1], t[2]);
    std::map<int, double> area;
    const auto rest = [&](int v) {
        Vec3 X = Vec3::Zero();
        for (int a = 0; a < 3; ++a) X += s.bary[v][a] * w.nodes.rest[w.elements.nodes[s.element[v]][a]];
        return X;
    };
    for (const auto& t : s.triangles) {
        const Vec3 a = rest(t[1]) - rest(t[0]), b = rest(t[2]) - rest(t[0]);
        EXPECT_GT(a.x() * b.y() - a.y() * b.x(), 0.0) << "a triangle turned over";
        area[parts.find(t[0])] += 0.5 * (a.x() * b.y() - a.y() * b.x());
    }
    std::vector<double> out;
    for (const auto& [root, value] : area) out.push_back(value);
    std::sort(out.begin(), out.end());
    return out;
}

/// A first cut's crossing on a skin subdivision point (x = 17.5 mm: mid-cell) moves by 1e-6 of its
/// edge (surface_edge_param), so a part's area is the exact one within 1e-6 of an edge times the
/// sheet's side, twice [m^2].
constexpr double kNudge = 2e-6 * 0.005 * kSide;

/// The sheet with its visual surface subdivided once, cut by the segments in turn, the surface
/// mapped after each.
World cut_sheet_with_surface(const std::vector<std::vector<Vec3>>& cuts) {
    World w = sheet();
    build_surface(w, w.visual, 1);
    for (const auto& c : cuts) {
        cut_now(w, c);
        map_cuts(w, w.visual);
    }
    update_surface_positions(w, w.visual);
    return w;
}

TEST(Recut, TheSheetOfAnXIsFourPartsOfTheQuadrantsAreas) {
    const double x = 0.0175, y = 0.0215;
    World w = cut_sheet_with_surface({segment(x, -1, x, 1), segment(-1, y, 1, y)});
    const std::vector<double> parts = sheet_parts(w, w.visual);
    std::vector<double> exact{x * (kSide - y), x * y, (kSide - x) * (kSide - y), (kSide - x) * y};
    std::sort(exact.begin(), exact.end());
    ASSERT_EQ(parts.size(), 4u);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(parts[k], exact[k], kNudge) << k;
}

TEST(Recut, TheSheetOfALoopFreesItsSquareAndOfATItsThirdPart) {
    const double x0 = 0.0115, x1 = 0.0285, y0 = 0.0135, y1 = 0.0265, over = 0.002;
    World loop = cut_sheet_with_surface({segment(x0 - over, y0, x1 + over, y0), segment(x1, y0 - over, x1, y1 + over),
                                         segment(x1 + over, y1, x0 - over, y1), segment(x0, y1 + over, x0, y0 - over)});
    const std::vector<double> inside = sheet_parts(loop, loop.visual);
    ASSERT_EQ(inside.size(), 2u);
    EXPECT_NEAR(inside[0], (x1 - x0) * (y1 - y0), kNudge);
    const double x = 0.0175, y = 0.0215;
    World t = cut_sheet_with_surface({segment(x, -1, x, 1), segment(x, y, 1, y)});
    const std::vector<double> three = sheet_parts(t, t.visual);
    ASSERT_EQ(three.size(), 3u);
    EXPECT_NEAR(three[0], (kSide - x) * (kSide - y), kNudge);
    // A stem that stops inside the sheet: its lips meet where it ends (one part more for none).
    World stop = cut_sheet_with_surface({segment(x, -1, x, 1), segment(x, y, 0.031, y)});
    EXPECT_EQ(sheet_parts(stop, stop.visual).size(), 2u);
}

}  // namespace
}  // namespace xcut

namespace xcut {
namespace {

/// The sheet as a scene without a surface, cut by two scalpels in turn: the first along x = 17.5 mm
/// over the sheet's height, the second along y = 21.5 mm over its width (both from outside it to
/// beyond it).
std::unique_ptr<Simulation> crossed_by_two_scalpels(const std::string& element_size = "0.005",
                                                    const std::string& second_start = "-0.002") {
    const std::string text = R"({
      "mesh": {"generator": "plate", "origin": [0, 0, 0], "size": [0.04, 0.04, 0], "element_size": )" + element_size + R"(},
      "material": {"young": 1e4, "poisson": 0.3, "density": 1000, "thickness": 0.002},
      "tools": [
        {"name": "first", "blade": {"tip": [0, 0, 0], "heel": [0, 0, 0.001]},
         "trajectory": [{"time": 0, "position": [0.0175, -0.002, 0]}, {"time": 0.2, "position": [0.0175, 0.042, 0]}]},
        {"name": "second", "blade": {"tip": [0, 0, 0], "heel": [0, 0, 0.001]},
         "trajectory": [{"time": 0, "position": [)" + second_start + R"(, 0.0215, 0]}, {"time": 0.2, "position": [)" + second_start + R"(, 0.0215, 0]},
                        {"time": 0.4, "position": [0.042, 0.0215, 0]}]}],
      "solver": {"dt": 0.01},
      "steps": 45
    })";
    return make_simulation(load_scene_text(text, "crossed sheet", "."), /*with_output=*/false);
}

TEST(Recut, TwoScalpelsCrossingDivideEveryElementTheSecondCrossesIntoFourPieces) {
    auto sim = crossed_by_two_scalpels();
    while (sim->world.step < 45) step_simulation(*sim);
    World& w = sim->world;
    EXPECT_TRUE(every_crossed_element_cut_along(w, 0.0215, 0.0, kSide));
    int twice = 0;
    for (int c = 0; c < w.cuts.count(); ++c) twice += w.cuts.lines[c].size() >= 2;
    EXPECT_EQ(twice, 2) << "the crossing cell's two triangles";
    count_pieces(w);
    ASSERT_EQ(w.pieces.count, 4);
    double sum = 0.0;
    for (double v : w.pieces.volume) sum += v;
    EXPECT_NEAR(sum, kSide * kSide * kThickness, 1e-12 * kSide * kSide * kThickness);
    const int ignored = w.cut_state.recut_ignored.size() < 2 ? 0 : w.cut_state.recut_ignored[1];
    EXPECT_EQ(ignored, 0) << "no element the second crossed kept the first's cut alone";
}

TEST(Recut, AScalpelsStemBegunAtTheWoundReachesItAndFreesAThirdPiece) {
    auto sim = crossed_by_two_scalpels("0.005", "0.0175");  // the second starts on the first's line
    while (sim->world.step < 45) step_simulation(*sim);
    World& w = sim->world;
    EXPECT_TRUE(every_crossed_element_cut_along(w, 0.0215, 0.0175, kSide));
    count_pieces(w);
    EXPECT_EQ(w.pieces.count, 3);
}

/// Random scalpels on the sheet with its visual surface (subdivided once): 2 to 4, each a straight
/// stroke between two random points of a square 10 mm larger than the sheet, one after the other.
std::string random_scalpels_scene(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> at(-0.005, kSide + 0.005);
    std::uniform_int_distribution<int> count(2, 4);
    std::string tools;
    const int n = count(rng);
    for (int b = 0; b < n; ++b) {
        const double t0 = 0.01 + 0.1 * b, x0 = at(rng), y0 = at(rng), x1 = at(rng), y1 = at(rng);
        tools += fmt::format(R"({}{{"name": "s{}", "blade": {{"tip": [0, 0, 0], "heel": [0, 0, 0.001]}},
          "trajectory": [{{"time": 0, "position": [{}, {}, 0]}}, {{"time": {}, "position": [{}, {}, 0]}},
                         {{"time": {}, "position": [{}, {}, 0]}}]}})",
                             b ? ", " : "", b, x0, y0, t0, x0, y0, t0 + 0.1, x1, y1);
    }
    return R"({
      "mesh": {"generator": "plate", "origin": [0, 0, 0], "size": [0.04, 0.04, 0], "element_size": 0.005},
      "visual": {"subdivisions": 1},
      "material": {"young": 1e4, "poisson": 0.3, "density": 1000, "thickness": 0.002},
      "constraints": {"fixed_boxes": [{"min": [-1e-6, -1, -1], "max": [1e-6, 1, 1], "displacement": [-0.0005, 0, 0]},
                                      {"min": [0.039999, -1, -1], "max": [0.040001, 1, 1], "displacement": [0.0005, 0, 0]}]},
      "tools": [)" + tools + R"(],
      "solver": {"dt": 0.01},
      "steps": 50
    })";
}

/// The sheet (5 mm cells), cut along x = 17.5 mm, then along y = 21.5 mm from outside its left
/// border by a second scalpel that stops at `stop_x` (t = 0.3-0.45 s) and, if `resume`, goes on past
/// the right border.
std::unique_ptr<Simulation> stopping_second(const std::string& stop_x, bool resume) {
    const std::string text = R"({
      "mesh": {"generator": "plate", "size": [0.04, 0.04, 0], "element_size": 0.005},
      "material": {"young": 1e5, "poisson": 0.3, "density": 1000, "thickness": 0.002},
      "tools": [{"name": "first", "blade": {"tip": [0, 0, 0], "heel": [0, 0, 0.001]},
                 "trajectory": [{"time": 0, "position": [0.0175, -0.002, 0]}, {"time": 0.2, "position": [0.0175, 0.042, 0]}]},
                {"name": "second", "blade": {"tip": [0, 0, 0], "heel": [0, 0, 0.001]},
                 "trajectory": [{"time": 0, "position": [-0.002, 0.0215, 0]}, {"time": 0.2, "position": [-0.002, 0.0215, 0]},
                                {"time": 0.3, "position": [)" + stop_x + R"(, 0.0215, 0]}, {"time": 0.45, "position": [)" +
                             stop_x + R"(, 0.0215, 0]})" + (resume ? R"(, {"time": 0.6, "position": [0.042, 0.0215, 0]})" : "") + R"(]}],
      "solver": {"dt": 0.01},
      "allow": ["dt"],
      "steps": 70
    })";
    return make_simulation(load_scene_text(text, "stopping scalpel", "."), /*with_output=*/false);
}

// A blade that stops past a wound inside the element it crossed it in divides the fragment it
// crossed (end_stems: without it the T keeps a bridge there, 2 pieces); one that pauses there, before
// or past the wound line, and goes on loses nothing (the chord's line is the stem's: 4 pieces, as
// without the pause).
TEST(Recut, AScalpelThatStopsOrPausesPastAWoundInsideAnElementDividesWhatItCrossed) {
    auto stopped = stopping_second("0.0185", false);
    while (stopped->world.step < 70) step_simulation(*stopped);
    count_pieces(stopped->world);
    EXPECT_EQ(stopped->world.pieces.count, 3) << "the T's stem reaches the wound";
    for (const char* at : {"0.0165", "0.0185"}) {
        SCOPED_TRACE(at);
        auto sim = stopping_second(at, true);
        while (sim->world.step < 70) step_simulation(*sim);
        EXPECT_TRUE(every_crossed_element_cut_along(sim->world, 0.0215, 0.0, kSide));
        count_pieces(sim->world);
        EXPECT_EQ(sim->world.pieces.count, 4);
    }
}

// Random crossings, T's and re-cuts of re-cut elements (100 runs, seed 31; 12 under the sanitizer,
// where the 100 took two minutes): at every step no
// triangle without area and no number NaN; at the end the sheet is sound (every directed edge once,
// none turned over), the pieces' areas are the sheet's, and the sheet's parts are the material's
// pieces, each of its area.
TEST(Recut, RandomScalpelsKeepTheSheetSoundAndThePiecesWhole) {
    std::mt19937_64 rng(31);
    int again = 0;
    const int runs = testing::kInstrumented ? 12 : 100;
    for (int n = 0; n < runs; ++n) {
        SCOPED_TRACE(n);
        auto sim = make_simulation(load_scene_text(random_scalpels_scene(rng), "random scalpels", "."), false);
        World& w = sim->world;
        for (int step = 0; step < 50; ++step) {
            step_simulation(*sim);
            ASSERT_EQ(zero_area_triangles(w.visual), 0) << "step " << step;
            for (const Vec3& x : w.nodes.position) ASSERT_TRUE(x.allFinite()) << "step " << step;
        }
        const std::vector<double> parts = sheet_parts(w, w.visual);
        count_pieces(w);
        double sum = 0.0;
        for (double v : w.pieces.volume) sum += v;
        EXPECT_NEAR(sum, kSide * kSide * kThickness, 1e-12 * kSide * kSide * kThickness);
        std::vector<double> pieces;  // slivers too: the sheet shows them
        for (double v : w.pieces.volume) pieces.push_back(v / kThickness);
        std::sort(pieces.begin(), pieces.end());
        ASSERT_EQ(parts.size(), pieces.size());
        for (size_t k = 0; k < parts.size(); ++k) EXPECT_NEAR(parts[k], pieces[k], 4.0 * kNudge) << k;
        for (int c = 0; c < w.cuts.count(); ++c) again += w.cuts.lines[c].size() >= 2;
    }
    EXPECT_GT(again, runs / 5) << "the runs cut elements again";
}

/// The crossed sheet at 1 mm cells (3,200 triangles: past the parallel loops' serial cut-off).
uint64_t crossed_fine(int threads) {
    set_thread_count(threads);
    auto sim = crossed_by_two_scalpels("0.001");
    while (sim->world.step < 45) step_simulation(*sim);
    int twice = 0;
    for (int c = 0; c < sim->world.cuts.count(); ++c) twice += sim->world.cuts.lines[c].size() >= 2;
    EXPECT_GT(twice, 0) << "elements were cut again";
    set_thread_count(2);
    return testing::state_hash(sim->world);
}

TEST(Recut, CrossingScalpelsAreBitIdenticalOnOneAndTwoThreads) { EXPECT_EQ(crossed_fine(1), crossed_fine(2)); }

}  // namespace
}  // namespace xcut
