// A surface's defects (systems/surface/surface_check.h) on surfaces made by hand: a closed
// tetrahedron, one with a face taken off, two sharing an edge, a triangle without area, and a 2D
// sheet with two triangles overlapping.
#include <gtest/gtest.h>

#include "systems/surface/surface_check.h"

namespace xcut {
namespace {

/// The outward surface of the tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1) shifted by `at`, as
/// four more vertices and triangles of s.
void add_tetrahedron(SurfaceMesh& s, const Vec3& at) {
    const int v = s.vertex_count();
    for (const Vec3& p : {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}) s.position.push_back(at + p);
    for (const std::array<int, 3>& t : {std::array<int, 3>{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}})
        s.triangles.push_back({v + t[0], v + t[1], v + t[2]});
}

TEST(SurfaceCheck, AClosedTetrahedronHasNoDefectAndOneFaceOffLeavesItsThreeEdgesOpen) {
    SurfaceMesh s;
    add_tetrahedron(s, Vec3::Zero());
    SurfaceDefects d = surface_defects(s, true);
    EXPECT_EQ(d.total(), 0);
    s.triangles.pop_back();
    d = surface_defects(s, true);
    EXPECT_EQ(d.open, 3);
    EXPECT_EQ(d.pinched, 0);
    EXPECT_EQ(d.zero_area, 0);
    // As a 2D sheet the same triangles are open by design: no defect.
    EXPECT_EQ(surface_defects(s, false).total(), 0);
}

TEST(SurfaceCheck, TwoClosedTetrahedraSharingAnEdgePinchIt) {
    SurfaceMesh s;
    add_tetrahedron(s, Vec3::Zero());
    add_tetrahedron(s, Vec3(0.0, -1.0, 0.0));
    // The second's vertices 6 (0, 0, 0) and 7 (0, -1, 1) taken as the first's 0 and 3: its edge
    // 6 - 7 becomes the first's edge 0 - 3, which then has four triangles, two each way.
    for (auto& t : s.triangles)
        for (int& v : t) v = v == 6 ? 0 : v == 7 ? 3 : v;
    const SurfaceDefects d = surface_defects(s, true);
    EXPECT_EQ(d.open, 0);
    EXPECT_EQ(d.pinched, 1);
}

TEST(SurfaceCheck, ATriangleWithoutAreaIsCounted) {
    SurfaceMesh s;
    add_tetrahedron(s, Vec3::Zero());
    s.position.push_back(Vec3(0.5, 0.0, 0.0));  // on the edge 0 -> 1
    s.triangles.push_back({0, 1, 4});
    s.triangles.push_back({0, 4, 1});  // and back, so no edge is open
    const SurfaceDefects d = surface_defects(s, true);
    EXPECT_EQ(d.zero_area, 2);
    EXPECT_EQ(d.open, 0);
}

TEST(SurfaceCheck, ASheetWithTwoTrianglesOverlappingAlongAnEdgeIsPinched) {
    SurfaceMesh s;
    s.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(0.5, 0.5, 0)};
    s.triangles = {{0, 1, 2}, {0, 2, 3}};  // a square: open at its border, no defect
    EXPECT_EQ(surface_defects(s, false).total(), 0);
    s.triangles.push_back({0, 1, 4});  // over the first, the same way along 0 -> 1
    EXPECT_EQ(surface_defects(s, false).pinched, 1);
}

TEST(SurfaceCheck, NoteDefectsKeepsWhenTheyWereFirstSeenAndForgetsThemOnceClosed) {
    SurfaceMesh s;
    add_tetrahedron(s, Vec3::Zero());
    const auto face = s.triangles.back();
    s.triangles.pop_back();
    note_defects(s, true, 0.5);
    note_defects(s, true, 0.7);
    EXPECT_EQ(s.open_edges, 3);
    EXPECT_DOUBLE_EQ(s.defects_since, 0.5);
    s.triangles.push_back(face);
    note_defects(s, true, 0.9);
    EXPECT_EQ(s.open_edges, 0);
    EXPECT_DOUBLE_EQ(s.defects_since, -1.0);
}

}  // namespace
}  // namespace xcut
