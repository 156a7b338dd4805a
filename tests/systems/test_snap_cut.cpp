// The snapping-and-subdivision baseline (systems/cut/snap_cut_system.h): DOF growth counted by hand,
// a conforming, non-inverted mesh with closed surfaces after an incision, snaps bounded by the
// threshold, and the same split decisions as the XFEM cutter on the same trajectory.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "engine/parallel.h"
#include "systems/pipeline.h"
#include "tests/surface_checks.h"
#include "systems/cut/cut_system.h"
#include "systems/surface/mapping_system.h"
#include "systems/cut/snap_cut_system.h"
#include "systems/tool_system.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

using testing::grid;
using testing::world_from_mesh;

World snap_world(const MeshData& mesh, double threshold = 0.1) {
    World w = world_from_mesh(mesh);
    w.snap.enabled = true;
    w.snap.threshold = threshold;
    prepare_snap_cut(w);
    return w;
}

double total_mass(const World& w) {
    double m = 0.0;
    for (double x : w.nodes.mass) m += x;
    return m;
}

double live_volume(const World& w) {
    double v = 0.0;
    for (int e : live_elements(w)) v += w.elements.rest_volume[e];
    return v;
}

// 2D: a 40 x 20 mm plate of 4 x 2 cells (10 mm), cut through along x = 15 mm, the middle of the
// second column. Each of its 2 cells is crossed on 3 edges: 3 horizontal edges (y = 0, 10, 20 mm)
// and 2 diagonals, all at their middle (no snap): 5 points, each duplicated once the cut is
// through -> 15 + 10 = 25 nodes. Its 4 triangles become 3 each: 12 + 12 = 24 triangles.
// XFEM on the same cut enriches the 6 nodes of the cut column: 15 + 6 = 21.
TEST(SnapCut, ThroughCutOfAPlateAddsTheNodesCountedByHand) {
    const MeshData plate = generate_plate(grid({0.04, 0.02, 0}, {4, 2, 1}));
    const std::vector<Vec3> segment = {Vec3(0.015, -0.005, 0), Vec3(0.015, 0.025, 0)};
    World snap = snap_world(plate);
    const double mass = total_mass(snap);
    queue_polygon_cut(snap, segment);
    EXPECT_EQ(apply_snap_events(snap), 4);
    EXPECT_EQ(snap.nodes.count(), 25);
    EXPECT_EQ(snap.snap.points, 5);
    EXPECT_EQ(snap.snap.copies, 5);
    EXPECT_EQ(snap.snap.snaps, 0);
    EXPECT_EQ(live_elements(snap).size(), 24u);
    EXPECT_NEAR(total_mass(snap), mass, 1e-15 * mass);

    World xfem = world_from_mesh(plate);
    EXPECT_EQ(testing::cut_now(xfem, segment), 4);
    EXPECT_EQ(xfem.nodes.count(), 21);
}

// 3D: one 10 mm cube of 6 tetrahedra (all sharing the diagonal (0,0,0)-(1,1,1)), cut through by
// the plane x = 5 mm. Crossed edges (x differs at the ends): 4 cube edges along x, the diagonals
// of the 4 faces y = 0, y = 1, z = 0, z = 1, and the body diagonal: 9 points, each duplicated ->
// 8 + 18 = 26 nodes. Tetrahedra whose path steps in x first or last have one node alone (3 crossed
// edges, 1 + 3 pieces), the 2 that step in x second are two-and-two (4 crossed edges, 3 + 3):
// 4 x 4 + 2 x 6 = 28 pieces. XFEM enriches the 8 nodes: 16.
TEST(SnapCut, ThroughCutOfACubeAddsTheNodesCountedByHand) {
    const MeshData cube = generate_box(grid({0.01, 0.01, 0.01}, {1, 1, 1}));
    const auto square = testing::square_on_plane(Vec3(0.005, 0.005, 0.005), Vec3::UnitX(), 0.02);
    World snap = snap_world(cube);
    const double mass = total_mass(snap);
    queue_polygon_cut(snap, square);
    EXPECT_EQ(apply_snap_events(snap), 6);
    EXPECT_EQ(snap.nodes.count(), 26);
    EXPECT_EQ(snap.snap.points, 9);
    EXPECT_EQ(snap.snap.copies, 9);
    EXPECT_EQ(live_elements(snap).size(), 28u);
    for (int e : live_elements(snap)) EXPECT_GT(snap.elements.rest_volume[e], 0.0) << "element " << e;
    EXPECT_NEAR(live_volume(snap), 1e-6, 1e-18);
    EXPECT_NEAR(total_mass(snap), mass, 1e-15 * mass);

    World xfem = world_from_mesh(cube);
    EXPECT_EQ(testing::cut_now(xfem, square), 6);
    EXPECT_EQ(xfem.nodes.count(), 16);
}

/// Slab 40 x 20 x 4 mm, 2 mm cells (2 layers), a vertical scalpel edge through its thickness drawn
/// along y at x = `x` from y = 2 mm to 14 mm (a partial incision: the slab is 20 mm deep in y).
World slab_with_scalpel(bool snap, double x, double jitter = 0.0, double threshold = 0.1) {
    const MeshData mesh = generate_box(grid({0.04, 0.02, 0.004}, {20, 10, 2}, jitter, 7));
    World w = snap ? snap_world(mesh, threshold) : world_from_mesh(mesh);
    Keyframe a, b;
    a.position = Vec3(x, 0.002, 0.0);
    b.position = Vec3(x, 0.014, 0.0);
    b.time = 1.0;
    add_scalpel(w, "scalpel", {a, b}, Vec3(0, 0, -0.001), Vec3(0, 0, 0.005));
    return w;
}

/// Steps the cutter alone (the body at rest) to t = 1.1 s; returns the split elements per step.
std::vector<std::vector<int>> run_cutter(World& w) {
    ElementBvh bvh;
    prepare_cut_search(w, bvh);
    std::vector<std::vector<int>> steps;
    for (int i = 0; i <= 55; ++i) {
        w.time = 0.02 * i;
        advance_tools(w, w.time);
        run_cut_system(w, bvh);
        std::vector<int> split;
        for (const CutEvent& ev : w.pending_cuts) split.push_back(ev.element);
        steps.push_back(split);
        if (w.snap.enabled) {
            apply_snap_events(w);
        } else {
            apply_cut_events(w);
        }
    }
    return steps;
}

using Face = std::array<int, 3>;
Face sorted_face(int a, int b, int c) {
    Face f{a, b, c};
    std::sort(f.begin(), f.end());
    return f;
}
constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

/// Conformity of the live tetrahedra: no live edge between two mesh nodes carries a point (no
/// hanging node); every face belongs to one or two live elements; a face of one element lies on
/// the body's boundary (its roots on one boundary face of the mesh) or on a cut (all its roots on
/// the cut surface).
void expect_conforming(const World& w) {
    std::map<Face, int> count;
    std::set<Face> mesh_boundary;
    {
        std::map<Face, int> mesh_faces;
        for (int e = 0; e < w.mesh_elements; ++e)
            for (const auto& f : kFaces) ++mesh_faces[sorted_face(w.elements.nodes[e][f[0]], w.elements.nodes[e][f[1]], w.elements.nodes[e][f[2]])];
        for (const auto& [f, n] : mesh_faces)
            if (n == 1) mesh_boundary.insert(f);
    }
    auto mesh_nodes_of = [&](int root) -> std::vector<int> {
        if (root < w.mesh_nodes) return {root};
        const auto ab = w.snap.extra_edge[root - w.mesh_nodes];
        return {ab[0], ab[1]};
    };
    for (int e : live_elements(w)) {
        const auto& n = w.elements.nodes[e];
        for (int i = 0; i < 4; ++i)
            for (int j = i + 1; j < 4; ++j) {
                const int a = snap_root(w, n[i]), b = snap_root(w, n[j]);
                if (a < w.mesh_nodes && b < w.mesh_nodes) {
                    const uint64_t key = (uint64_t(std::min(a, b)) << 32) | uint32_t(std::max(a, b));
                    EXPECT_FALSE(w.snap.edge_point.count(key)) << "element " << e << " has a hanging node on " << a << "-" << b;
                }
            }
        for (const auto& f : kFaces) ++count[sorted_face(n[f[0]], n[f[1]], n[f[2]])];
    }
    for (const auto& [f, k] : count) {
        EXPECT_LE(k, 2) << "face shared by " << k << " elements";
        if (k != 1) continue;
        bool cut = true;
        std::set<int> under;
        for (int v : f) {
            const int r = snap_root(w, v);
            cut = cut && snap_surface_root(w, r);
            for (int m : mesh_nodes_of(r)) under.insert(m);
        }
        bool boundary = false;
        for (const Face& b : mesh_boundary)
            if (std::includes(b.begin(), b.end(), under.begin(), under.end())) boundary = true;
        EXPECT_TRUE(cut || boundary) << "an open face inside the body: " << f[0] << " " << f[1] << " " << f[2];
    }
}

TEST(SnapCut, IncisionLeavesAConformingMeshWithPositiveVolumesAndClosedSurface) {
    World w = slab_with_scalpel(true, 0.0312);  // crossings 0.6 of a cell from a node: subdivision
    build_surface(w, w.visual, 0);
    w.snap.visual_subdivisions = 0;
    const double mass = total_mass(w), volume = live_volume(w);
    run_cutter(w);
    EXPECT_GT(w.snap.elements_split, 20);
    EXPECT_GT(w.snap.copies, 0) << "the lips separate";
    for (int e : live_elements(w)) EXPECT_GT(w.elements.rest_volume[e], 0.0) << "element " << e;
    EXPECT_NEAR(live_volume(w), volume, 1e-12 * volume);
    EXPECT_NEAR(total_mass(w), mass, 1e-12 * mass);
    expect_conforming(w);
    testing::check_closed_oriented(w.visual);
    testing::expect_bound_to_live_elements(w, w.visual);
    EXPECT_NEAR(testing::enclosed_volume(w.visual), volume, 1e-9 * volume) << "the surface encloses the body";
    int cut_faces = 0;
    for (uint8_t c : w.visual.cut_face) cut_faces += c;
    EXPECT_GT(cut_faces, 0) << "the wound's walls are on the surface";
    // And it steps: gravity, a few implicit Euler steps, finite and bounded.
    w.gravity = Vec3(0, 0, -9.81);
    w.solver.dt = 0.01;
    for (int i = 0; i < 5; ++i) testing::step_world(w);
    for (const Vec3& x : w.nodes.position) ASSERT_TRUE(x.allFinite());
}

TEST(SnapCut, SnappingMovesANodeByAtMostTheThreshold) {
    for (double threshold : {0.1, 0.25, 0.45}) {
        SCOPED_TRACE(threshold);
        World w = slab_with_scalpel(true, 0.03015, 0.25, threshold);  // irregular inside, near nodes outside
        const std::vector<Vec3> rest = w.nodes.rest;
        std::vector<double> longest(w.mesh_nodes, 0.0);
        for (int e = 0; e < w.mesh_elements; ++e)
            for (const auto& ed : kTetEdges) {
                const int a = w.elements.nodes[e][ed[0]], b = w.elements.nodes[e][ed[1]];
                const double l = (rest[a] - rest[b]).norm();
                longest[a] = std::max(longest[a], l), longest[b] = std::max(longest[b], l);
            }
        run_cutter(w);
        EXPECT_GT(w.snap.snaps, 0) << "some crossings were near nodes";
        for (double f : w.snap.snap_fraction) EXPECT_LE(f, threshold);
        for (int i = 0; i < w.mesh_nodes; ++i)
            EXPECT_LE((w.nodes.rest[i] - rest[i]).norm(), threshold * longest[i] * (1 + 1e-12)) << "node " << i;
        for (int e : live_elements(w)) EXPECT_GT(w.elements.rest_volume[e], 0.0) << "element " << e;
        expect_conforming(w);
    }
}

TEST(SnapCut, BothCuttersSplitTheSameElements) {
    for (double x : {0.0312, 0.0302}) {  // 0.0302: crossings 0.1 of a cell from the nodes, so nodes snap
        SCOPED_TRACE(x);
        World xfem = slab_with_scalpel(false, x), snap = slab_with_scalpel(true, x, 0.0, 0.15);
        const auto a = run_cutter(xfem), b = run_cutter(snap);
        EXPECT_EQ(a, b);
        EXPECT_EQ(xfem.cuts.count(), snap.snap.elements_split);
        if (x == 0.0302) {
            EXPECT_GT(snap.snap.snaps, 0);
        }
    }
}

/// The 2D face scene with the snapping cutter for 60 steps (the incision begins at 0.2 s).
uint64_t run_snap_face(int threads) {
    set_thread_count(threads);
    Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/face_skin_2d.json", {"cutter.type=\"snap\""});
    auto sim = make_simulation(scene, /*with_output=*/false);
    for (int i = 0; i < 60; ++i) step_simulation(*sim);
    EXPECT_GT(sim->world.snap.elements_split, 0);
    set_thread_count(2);
    uint64_t h = 1469598103934665603ull;
    for (const auto* v : {&sim->world.nodes.position, &sim->world.nodes.velocity}) {
        const auto* p = reinterpret_cast<const unsigned char*>(v->data());
        for (size_t i = 0; i < v->size() * sizeof(Vec3); ++i) h = (h ^ p[i]) * 1099511628211ull;
    }
    return h;
}

TEST(SnapCut, RunsAreBitIdenticalForAnyThreadCount) { EXPECT_EQ(run_snap_face(1), run_snap_face(2)); }

}  // namespace
}  // namespace xcut
