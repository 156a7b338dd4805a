// TetGen .node/.ele reader (0- or 1-based, attributes and markers skipped); nodes and elements are
// named in messages by the file's own indices (engine/io/mesh_io.h).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <array>
#include <cstdint>
#include <map>
#include <unordered_map>
#include <vector>

#include "components/nodes.h"
#include "engine/error.h"
#include "engine/io/input_file.h"
#include "engine/io/mesh_io.h"
#include "engine/io/byte_cursor.h"

namespace xcut {
namespace {

using mesh_io_detail::ByteCursor;

/// Reads .node or .ele rows: count, then `per_row` values per row after the index.
void check_tetgen_index(const ByteCursor& t, long long idx, long long expected) {
    if (idx != expected) t.fail(fmt::format("row index {} where {} was expected", idx, expected));
}

}  // namespace

MeshData read_tetgen(const std::string& node_path, const std::string& ele_path) {
    MeshData mesh;
    mesh.source = ele_path;
    mesh.points_source = node_path;
    const std::string node_text = read_input_file(node_path, "file", "mesh");
    ByteCursor tn(node_path, node_text, true);
    const long long n = tn.count("node count", 8);
    const long long dim = tn.integer("dimension");
    if (dim != 3) tn.fail(fmt::format("dimension {} (TetGen meshes are 3D)", dim));
    const long long attrs = tn.integer("attribute count");
    const long long marker = tn.integer("boundary marker flag");
    if (attrs < 0 || attrs > 64 || marker < 0 || marker > 1) tn.fail("implausible attribute count or marker flag");
    long long base = 0;
    for (long long i = 0; i < n; ++i) {
        const long long idx = tn.integer("node index");
        if (i == 0) base = idx;
        if (base != 0 && base != 1) tn.fail("node indices must start at 0 or 1");
        check_tetgen_index(tn, idx, base + i);
        Vec3 p;
        for (int k = 0; k < 3; ++k) p[k] = tn.real("coordinate");
        for (long long a = 0; a < attrs + marker; ++a) tn.real("attribute");
        mesh.points.push_back(p);
        mesh.point_id.push_back(idx);
    }
    const std::string ele_text = read_input_file(ele_path, "file", "mesh");
    ByteCursor te(ele_path, ele_text, true);
    const long long m = te.count("element count", 10);
    const long long corners = te.integer("nodes per tetrahedron");
    if (corners != 4) te.fail(fmt::format("{}-node tetrahedra are not supported: linear (4-node) only", corners));
    const long long region = te.integer("region attribute count");
    if (region < 0 || region > 64) te.fail("implausible attribute count");
    // Region attributes (TetGen's -A switch): each kept as cell data; the first, when integral, as regions.
    mesh.cell_data.resize(region);
    for (long long a = 0; a < region; ++a) mesh.cell_data[a].name = a == 0 ? "tetgen:region" : fmt::format("tetgen:attribute{}", a + 1);
    for (long long e = 0; e < m; ++e) {
        const long long idx = te.integer("element index");
        if (e == 0 && idx != 0 && idx != 1) te.fail("element indices must start at 0 or 1");
        mesh.cell_id.push_back(idx);
        std::array<int, 4> c;
        for (int a = 0; a < 4; ++a) {
            const long long v = te.integer("node index") - base;
            if (v < 0 || v >= n)
                te.fail(fmt::format("node {} is out of range ({} nodes, first index {})", v + base, n, base));
            c[a] = static_cast<int>(v);
        }
        for (long long a = 0; a < region; ++a) mesh.cell_data[a].values.push_back(te.real("attribute"));
        mesh.cells.push_back(c);
    }
    if (region > 0) {
        std::vector<int> r;
        for (double v : mesh.cell_data[0].values)
            if (v == std::floor(v) && std::abs(v) <= 1e9) r.push_back(static_cast<int>(v));
        if (r.size() == mesh.cells.size()) mesh.cell_region = std::move(r);
    }
    return mesh;
}

}  // namespace xcut
