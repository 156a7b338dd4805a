#include "systems/surface/surface_check.h"

#include <algorithm>
#include <cstdint>
#include <vector>

#include "systems/surface/surface_cut.h"

namespace xcut {

SurfaceDefects surface_defects(const SurfaceMesh& s, bool closed) {
    // Each directed edge a -> b as one key, a in the high half: equal keys are one edge's uses,
    // and the reversed keys sorted too give each edge's uses the other way by one merge.
    const auto key = [](int a, int b) { return static_cast<uint64_t>(static_cast<uint32_t>(a)) << 32 | static_cast<uint32_t>(b); };
    const auto flip = [](uint64_t k) { return k << 32 | k >> 32; };
    std::vector<uint64_t> directed;
    directed.reserve(3 * s.triangles.size());
    for (const auto& t : s.triangles)
        for (int k = 0; k < 3; ++k) directed.push_back(key(t[k], t[(k + 1) % 3]));
    std::sort(directed.begin(), directed.end());
    std::vector<uint64_t> reversed;  // a sheet (2D) counts one direction alone
    if (closed) {
        reversed.resize(directed.size());
        std::transform(directed.begin(), directed.end(), reversed.begin(), flip);
        std::sort(reversed.begin(), reversed.end());
    }
    SurfaceDefects d;
    size_t r = 0;  // the first reversed key not below the current one
    for (size_t i = 0; i < directed.size();) {
        size_t j = i;
        while (j < directed.size() && directed[j] == directed[i]) ++j;
        const int n = static_cast<int>(j - i);
        i = j;
        if (!closed) {
            d.pinched += n > 1;
            continue;
        }
        while (r < reversed.size() && reversed[r] < directed[j - 1]) ++r;
        int m = 0;  // its uses the other way: reversed keys equal to it
        while (r + m < reversed.size() && reversed[r + m] == directed[j - 1]) ++m;
        const uint64_t k = directed[j - 1];
        if (m == 0 || (k >> 32) < (k & 0xffffffffu)) {  // each undirected edge once
            d.open += n != m;
            d.pinched += n == m && n > 1;
        }
    }
    d.zero_area = zero_area_triangles(s);
    return d;
}

void note_defects(SurfaceMesh& s, bool closed, double time) {
    const SurfaceDefects d = surface_defects(s, closed);
    s.open_edges = d.open, s.pinched_edges = d.pinched, s.zero_area = d.zero_area;
    if (d.total() == 0) s.defects_since = -1.0;
    else if (s.defects_since < 0.0) s.defects_since = time;
}

}  // namespace xcut
