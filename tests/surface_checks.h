#pragma once
// Checks on bound surfaces shared by the tests: closed oriented 2-manifolds, components, volume.
#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <numeric>
#include <set>

#include "engine/world.h"

namespace xcut::testing {

/// Every directed edge once and its reverse once: a closed, consistently oriented 2-manifold.
/// Returns the Euler characteristic V - E + F.
inline int check_closed_oriented(const SurfaceMesh& s) {
    std::map<std::pair<int, int>, int> directed;
    for (const auto& t : s.triangles)
        for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
    for (const auto& [e, n] : directed) {
        EXPECT_EQ(n, 1) << "directed edge " << e.first << "-" << e.second;
        EXPECT_EQ(directed.count({e.second, e.first}), 1u) << "edge " << e.first << "-" << e.second << " is open";
    }
    return s.vertex_count() - static_cast<int>(directed.size() / 2) + static_cast<int>(s.triangles.size());
}

inline double enclosed_volume(const SurfaceMesh& s) {
    double v = 0.0;
    for (const auto& t : s.triangles) v += s.position[t[0]].dot(s.position[t[1]].cross(s.position[t[2]])) / 6.0;
    return v;
}

/// Connected components of the surface (by shared vertices); returns component per triangle.
inline std::vector<int> components_of(const SurfaceMesh& s, int& count) {
    std::vector<int> parent(s.vertex_count());
    std::iota(parent.begin(), parent.end(), 0);
    std::function<int(int)> find = [&](int v) { return parent[v] == v ? v : parent[v] = find(parent[v]); };
    for (const auto& t : s.triangles) parent[find(t[1])] = find(t[0]), parent[find(t[2])] = find(t[0]);
    std::map<int, int> id;
    std::vector<int> comp;
    for (const auto& t : s.triangles) comp.push_back(id.emplace(find(t[0]), static_cast<int>(id.size())).first->second);
    count = static_cast<int>(id.size());
    return comp;
}

/// The Euler characteristic V - E + F over the vertices the triangles use, with the closed,
/// oriented checks of check_closed_oriented.
inline int euler_characteristic(const SurfaceMesh& s) {
    std::set<int> used;
    for (const auto& t : s.triangles) used.insert(t.begin(), t.end());
    return check_closed_oriented(s) - (s.vertex_count() - static_cast<int>(used.size()));
}

/// The triangles of component k only.
inline SurfaceMesh component(const SurfaceMesh& s, const std::vector<int>& comp, int k) {
    SurfaceMesh part = s;
    part.triangles.clear();
    for (size_t t = 0; t < s.triangles.size(); ++t)
        if (comp[t] == k) part.triangles.push_back(s.triangles[t]);
    return part;
}

/// No two vertices on one side of the cut at one place, within 1e-12 m.
inline void expect_no_duplicate_points(const SurfaceMesh& s) {
    std::map<std::array<long long, 4>, int> seen;
    for (int v = 0; v < s.vertex_count(); ++v) {
        const int side = s.side[v];
        const Vec3& x = s.position[v];
        const std::array<long long, 4> key = {side, std::llround(x.x() * 1e12), std::llround(x.y() * 1e12),
                                              std::llround(x.z() * 1e12)};
        EXPECT_TRUE(seen.emplace(key, v).second) << "vertex " << v << " duplicates " << seen[key];
    }
}

/// Every vertex bound to a live element (a whole mesh element or a virtual one: weight > 0), with
/// barycentric coordinates in [-1e-12, 1 + 1e-12] summing to 1.
inline void expect_bound_to_live_elements(const World& w, const SurfaceMesh& s) {
    for (int v = 0; v < s.vertex_count(); ++v) {
        ASSERT_GE(s.element[v], 0) << "vertex " << v;
        EXPECT_GT(w.elements.weight[s.element[v]], 0.0) << "vertex " << v << " is bound to a live element";
        EXPECT_GE(s.bary[v].minCoeff(), -1e-12) << "vertex " << v;
        EXPECT_LE(s.bary[v].maxCoeff(), 1.0 + 1e-12) << "vertex " << v;
        EXPECT_NEAR(s.bary[v].sum(), 1.0, 1e-12) << "vertex " << v;
    }
}

}  // namespace xcut::testing
