// Gmsh .msh reader: ASCII formats 2.2 and 4.1 (tetrahedra, or triangles for a 2D mesh); nodes are
// named in messages by their tags (engine/io/mesh_io.h).
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <unordered_map>
#include <vector>

#include "components/nodes.h"
#include "engine/error.h"
#include "engine/io/input_file.h"
#include "engine/io/mesh_io.h"
#include "engine/io/mesh_tokens.h"

namespace xcut {
namespace {

using mesh_io_detail::Tokens;

/// Maps file node tags to 0-based indices.
struct TagMap {
    std::unordered_map<long long, int> index;
    int at(Tokens& t, long long tag) const {
        const auto it = index.find(tag);
        if (it == index.end()) t.fail(fmt::format("element refers to node {}, which $Nodes does not define", tag), -1);
        return it->second;
    }
};

/// Cells of one Gmsh element type: 4 = tetrahedron (4 nodes), 2 = triangle (3 nodes).
struct GmshElements {
    std::vector<std::array<int, 4>> tets, tris;
};

void add_gmsh_element(int type, const std::vector<int>& nodes, GmshElements& out) {
    if (type == 4) out.tets.push_back({nodes[0], nodes[1], nodes[2], nodes[3]});
    if (type == 2) out.tris.push_back({nodes[0], nodes[1], nodes[2], -1});
}

/// Nodes per element for the Gmsh types we can skip over; -1 if unknown.
int gmsh_type_nodes(int type) {
    static const std::map<int, int> kNodes = {{1, 2}, {2, 3}, {3, 4}, {4, 4}, {5, 8}, {6, 6}, {7, 5}, {8, 3},
                                              {9, 6}, {10, 9}, {11, 10}, {15, 1}, {16, 8}, {17, 20}, {18, 15}};
    const auto it = kNodes.find(type);
    return it == kNodes.end() ? -1 : it->second;
}

void read_gmsh2(Tokens& t, MeshData& mesh, GmshElements& els) {
    TagMap tags;
    if (!t.seek("$Nodes")) t.fail("no $Nodes section");
    const long long n = t.count("node count", 4);
    for (long long i = 0; i < n; ++i) {
        const long long tag = t.integer("node tag");
        Vec3 p;
        for (int k = 0; k < 3; ++k) p[k] = t.real("coordinate");
        tags.index[tag] = static_cast<int>(mesh.points.size());
        mesh.points.push_back(p);
        mesh.point_id.push_back(tag);
    }
    t.expect("$EndNodes");
    if (!t.seek("$Elements")) t.fail("no $Elements section");
    const long long m = t.count("element count", 4);
    for (long long i = 0; i < m; ++i) {
        t.integer("element tag");
        const int type = static_cast<int>(t.integer("element type"));
        const int ntags = static_cast<int>(t.integer("tag count"));
        if (ntags < 0 || ntags > 64) t.fail(fmt::format("implausible tag count {}", ntags), -1);
        for (int k = 0; k < ntags; ++k) t.integer("element tag");
        const int nn = gmsh_type_nodes(type);
        if (nn < 0) t.fail(fmt::format("unknown element type {}", type), -1);
        std::vector<int> nodes(nn);
        for (int k = 0; k < nn; ++k) nodes[k] = tags.at(t, t.integer("node tag"));
        add_gmsh_element(type, nodes, els);
    }
    t.expect("$EndElements");
}

void read_gmsh4(Tokens& t, MeshData& mesh, GmshElements& els) {
    TagMap tags;
    if (!t.seek("$Nodes")) t.fail("no $Nodes section");
    const long long blocks = t.count("entity block count", 4);
    const long long total = t.count("node count", 4);
    t.integer("min tag");
    t.integer("max tag");
    for (long long b = 0; b < blocks; ++b) {
        t.integer("entity dim");
        t.integer("entity tag");
        const long long parametric = t.integer("parametric flag");
        if (parametric != 0) t.fail("parametric nodes are not supported", -1);
        const long long n = t.count("nodes in block", 4);
        std::vector<long long> block_tags(n);
        for (long long i = 0; i < n; ++i) block_tags[i] = t.integer("node tag");
        for (long long i = 0; i < n; ++i) {
            Vec3 p;
            for (int k = 0; k < 3; ++k) p[k] = t.real("coordinate");
            tags.index[block_tags[i]] = static_cast<int>(mesh.points.size());
            mesh.points.push_back(p);
            mesh.point_id.push_back(block_tags[i]);
        }
    }
    if (static_cast<long long>(mesh.points.size()) != total)
        t.fail(fmt::format("$Nodes announces {} nodes but its blocks hold {}", total, mesh.points.size()));
    t.expect("$EndNodes");
    if (!t.seek("$Elements")) t.fail("no $Elements section");
    const long long blocks_e = t.count("entity block count", 4);
    t.count("element count", 2);
    t.integer("min tag");
    t.integer("max tag");
    for (long long b = 0; b < blocks_e; ++b) {
        t.integer("entity dim");
        t.integer("entity tag");
        const int type = static_cast<int>(t.integer("element type"));
        const int nn = gmsh_type_nodes(type);
        if (nn < 0) t.fail(fmt::format("unknown element type {}", type), -1);
        const long long n = t.count("elements in block", nn + 1);
        std::vector<int> nodes(nn);
        for (long long i = 0; i < n; ++i) {
            t.integer("element tag");
            for (int k = 0; k < nn; ++k) nodes[k] = tags.at(t, t.integer("node tag"));
            add_gmsh_element(type, nodes, els);
        }
    }
    t.expect("$EndElements");
}

MeshData finish_gmsh(const std::string& path, MeshData mesh, GmshElements& els) {
    if (!els.tets.empty()) {
        mesh.dim = 3;
        mesh.cells = std::move(els.tets);
    } else if (!els.tris.empty()) {
        mesh.dim = 2;
        mesh.cells = std::move(els.tris);
    } else {
        throw InputError(path, "$Elements", "no tetrahedra (type 4) or triangles (type 2)");
    }
    // Only the nodes the kept cells use: a surface mesh's extra nodes would be massless.
    std::vector<int> remap(mesh.points.size(), -1);
    std::vector<Vec3> used;
    std::vector<long long> used_id;
    for (auto& c : mesh.cells)
        for (int a = 0; a < mesh.nodes_per_cell(); ++a) {
            int& r = remap[c[a]];
            if (r < 0) r = static_cast<int>(used.size()), used.push_back(mesh.points[c[a]]), used_id.push_back(mesh.point_id[c[a]]);
            c[a] = r;
        }
    mesh.points = std::move(used);
    mesh.point_id = std::move(used_id);
    return mesh;
}

/// Reads .node or .ele rows: count, then `per_row` values per row after the index.

}  // namespace

MeshData read_gmsh(const std::string& path) {
    const std::string text = read_input_file(path, "file", "mesh");
    Tokens t(path, text, false);
    if (!t.seek("$MeshFormat")) t.fail("not a Gmsh file: no $MeshFormat");
    const double version = t.real("format version");
    const long long binary = t.integer("file type");
    t.integer("data size");
    if (binary != 0) t.fail("binary Gmsh files are not supported: save as ASCII", -2);
    t.expect("$EndMeshFormat");
    MeshData mesh;
    mesh.source = path;
    GmshElements els;
    if (version >= 2.0 && version < 3.0) {
        read_gmsh2(t, mesh, els);
    } else if (version >= 4.0 && version < 5.0) {
        read_gmsh4(t, mesh, els);
    } else {
        throw InputError(path, "$MeshFormat", fmt::format("version {} is not supported (2.2 or 4.1)", version));
    }
    return finish_gmsh(path, std::move(mesh), els);
}

}  // namespace xcut
