#pragma once
// Union-find with path halving (Tarjan & van Leeuwen 1984). The smaller root wins a union, so the
// classes and their representatives do not depend on the order of the unions: the same bits on any
// thread count. Used for the pieces a cut frees, the snapping cutter's surface copies and XFEM's node
// copies.
#include <algorithm>
#include <numeric>
#include <vector>

namespace xcut {

struct DisjointSets {
    std::vector<int> parent;
    explicit DisjointSets(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    /// The class's representative: its smallest member.
    int find(int i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    }
    void join(int a, int b) {
        a = find(a), b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
};

}  // namespace xcut
