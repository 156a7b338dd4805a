#include "engine/io/mesh_io.h"

#include <tetgen.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <sstream>
#include <unordered_map>

#include "components/nodes.h"
#include "engine/error.h"
#include "engine/io/input_file.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

std::string read_file(const std::string& path) { return read_input_file(path, "file", "mesh"); }

/// Whitespace-separated tokens with their line numbers; '#' comments skipped when asked.
class Tokens {
public:
    Tokens(const std::string& path, const std::string& text, bool hash_comments) : path_(path) {
        int line = 1;
        size_t i = 0;
        while (i < text.size()) {
            const char ch = text[i];
            if (ch == '\n') {
                ++line, ++i;
            } else if (std::isspace(static_cast<unsigned char>(ch))) {
                ++i;
            } else if (hash_comments && ch == '#') {
                while (i < text.size() && text[i] != '\n') ++i;
            } else {
                const size_t start = i;
                while (i < text.size() && !std::isspace(static_cast<unsigned char>(text[i]))) ++i;
                tokens_.push_back({text.substr(start, i - start), line});
            }
        }
    }
    bool done() const { return at_ >= tokens_.size(); }
    size_t remaining() const { return tokens_.size() - at_; }
    int line() const { return at_ < tokens_.size() ? tokens_[at_].line : (tokens_.empty() ? 1 : tokens_.back().line); }
    const std::string& peek(const char* what) const {
        if (done()) fail(fmt::format("unexpected end of file, expected {}", what));
        return tokens_[at_].text;
    }
    std::string word(const char* what) {
        const std::string& s = peek(what);
        ++at_;
        return s;
    }
    long long integer(const char* what) {
        const std::string s = word(what);
        char* end = nullptr;
        errno = 0;
        const long long v = std::strtoll(s.c_str(), &end, 10);
        if (end == s.c_str() || *end != '\0' || errno != 0)
            fail(fmt::format("\"{}\" is not an integer ({})", s, what), -1);
        return v;
    }
    double real(const char* what) {
        const std::string s = word(what);
        char* end = nullptr;
        const double v = std::strtod(s.c_str(), &end);
        if (end == s.c_str() || *end != '\0') fail(fmt::format("\"{}\" is not a number ({})", s, what), -1);
        return v;
    }
    /// A count read from the file, bounded by what the rest of the file could hold.
    long long count(const char* what, int tokens_each) {
        const long long n = integer(what);
        if (n < 0 || n > static_cast<long long>(remaining() / std::max(1, tokens_each) + 1))
            fail(fmt::format("{} {} does not fit in the rest of the file", what, n), -1);
        return n;
    }
    [[noreturn]] void fail(const std::string& message, int back = 0) const {
        const size_t k = std::min(tokens_.size() ? tokens_.size() - 1 : 0, static_cast<size_t>(std::max<long long>(0, static_cast<long long>(at_) + back)));
        throw InputError(path_, fmt::format("line {}", tokens_.empty() ? 1 : tokens_[k].line), message);
    }
    void expect(const std::string& word_expected) {
        const std::string w = word(word_expected.c_str());
        if (w != word_expected) fail(fmt::format("expected {}, found \"{}\"", word_expected, w), -1);
    }
    /// Skips to the token after `marker`; false if none.
    bool seek(const std::string& marker) {
        while (!done())
            if (tokens_[at_++].text == marker) return true;
        return false;
    }
    void rewind() { at_ = 0; }

private:
    struct Token {
        std::string text;
        int line;
    };
    std::string path_;
    std::vector<Token> tokens_;
    size_t at_ = 0;
};

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
void check_tetgen_index(Tokens& t, long long idx, long long expected) {
    if (idx != expected) t.fail(fmt::format("row index {} where {} was expected", idx, expected), -1);
}

/// Sorted-pair key of an undirected edge.
uint64_t edge_key(int a, int b) {
    return (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint32_t>(std::max(a, b));
}

struct Surface {
    std::vector<Vec3> points;
    std::vector<std::array<int, 3>> triangles;
};

Surface read_obj(const std::string& path) {
    const std::string text = read_file(path);
    Surface s;
    std::stringstream in(text);
    std::string line;
    int line_no = 0;
    while (std::getline(in, line)) {
        ++line_no;
        std::stringstream ls(line);
        std::string head;
        if (!(ls >> head) || head[0] == '#') continue;
        const std::string where = fmt::format("line {}", line_no);
        if (head == "v") {
            Vec3 p;
            for (int k = 0; k < 3; ++k) {
                std::string tok;
                if (!(ls >> tok)) throw InputError(path, where, "a vertex needs 3 coordinates");
                char* end = nullptr;
                p[k] = std::strtod(tok.c_str(), &end);
                if (end == tok.c_str() || *end != '\0') throw InputError(path, where, fmt::format("\"{}\" is not a number", tok));
            }
            s.points.push_back(p);
        } else if (head == "f") {
            std::vector<int> face;
            std::string tok;
            while (ls >> tok) {
                const std::string idx = tok.substr(0, tok.find('/'));
                char* end = nullptr;
                const long v = std::strtol(idx.c_str(), &end, 10);
                if (end == idx.c_str() || *end != '\0' || v == 0)
                    throw InputError(path, where, fmt::format("\"{}\" is not a vertex index", tok));
                const long n = static_cast<long>(s.points.size());
                const long i = v > 0 ? v - 1 : n + v;
                if (i < 0 || i >= n)
                    throw InputError(path, where, fmt::format("vertex index {} is out of range ({} vertices so far)", v, n));
                face.push_back(static_cast<int>(i));
            }
            if (face.size() < 3) throw InputError(path, where, "a face needs at least 3 vertices");
            for (size_t k = 1; k + 1 < face.size(); ++k) s.triangles.push_back({face[0], face[k], face[k + 1]});
        }
    }
    return s;
}

/// Adds a triangle's corners, merging exactly coincident points (STL repeats them per facet).
void add_stl_triangle(Surface& s, std::map<std::array<double, 3>, int>& ids, const std::array<Vec3, 3>& tri) {
    std::array<int, 3> t;
    for (int k = 0; k < 3; ++k) {
        const std::array<double, 3> key{tri[k].x(), tri[k].y(), tri[k].z()};
        auto [it, fresh] = ids.emplace(key, static_cast<int>(s.points.size()));
        if (fresh) s.points.push_back(tri[k]);
        t[k] = it->second;
    }
    s.triangles.push_back(t);
}

Surface read_stl(const std::string& path) {
    const std::string data = read_file(path);
    Surface s;
    std::map<std::array<double, 3>, int> ids;
    const bool ascii = data.compare(0, 5, "solid") == 0 && data.find("facet") != std::string::npos;
    if (ascii) {
        Tokens t(path, data, false);
        while (t.seek("vertex")) {
            std::array<Vec3, 3> tri;
            for (int c = 0; c < 3; ++c) {
                if (c > 0) t.expect("vertex");
                for (int k = 0; k < 3; ++k) tri[c][k] = t.real("vertex coordinate");
            }
            add_stl_triangle(s, ids, tri);
        }
        return s;
    }
    if (data.size() < 84) throw InputError(path, "header", "binary STL shorter than its 84-byte header");
    uint32_t n = 0;
    std::memcpy(&n, data.data() + 80, 4);
    if (data.size() < 84 + 50ull * n)
        throw InputError(path, "triangles", fmt::format("binary STL announces {} triangles but holds {} bytes", n, data.size()));
    for (uint32_t i = 0; i < n; ++i) {
        std::array<Vec3, 3> tri;
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) {
                float f;
                std::memcpy(&f, data.data() + 84 + 50ull * i + 12 + 12 * c + 4 * k, 4);
                tri[c][k] = f;
            }
        add_stl_triangle(s, ids, tri);
    }
    return s;
}

void check_closed(const std::string& path, const Surface& s) {
    if (s.triangles.empty()) throw InputError(path, "faces", "the surface has no triangles");
    for (size_t i = 0; i < s.points.size(); ++i)
        if (!s.points[i].allFinite()) throw InputError(path, fmt::format("vertex {}", i + 1), "coordinate is NaN or infinite");
    std::unordered_map<uint64_t, int> uses;
    for (const auto& t : s.triangles)
        for (int k = 0; k < 3; ++k) ++uses[edge_key(t[k], t[(k + 1) % 3])];
    int open = 0;
    for (const auto& [key, n] : uses) open += n != 2;
    if (open > 0)
        throw InputError(path, "faces",
                         fmt::format("the surface is not closed: {} edges are not shared by exactly two triangles", open));
    // TetGen asserts or crashes on a flat point set (or fewer than 4 points), so a closed but flat
    // surface stops here: the farthest point from p0, from that line, from that plane.
    const auto farthest = [&](auto&& distance) {
        size_t best = 0;
        for (size_t i = 1; i < s.points.size(); ++i)
            if (distance(s.points[i]) > distance(s.points[best])) best = i;
        return s.points[best];
    };
    const Vec3 p0 = s.points[0];
    const Vec3 p1 = farthest([&](const Vec3& p) { return (p - p0).norm(); });
    const double size = (p1 - p0).norm();
    const Vec3 u = (p1 - p0).normalized();
    const Vec3 p2 = farthest([&](const Vec3& p) { return (p - p0 - (p - p0).dot(u) * u).norm(); });
    const Vec3 n = u.cross(p2 - p0).normalized();
    const double thickness = (farthest([&](const Vec3& p) { return std::abs((p - p0).dot(n)); }) - p0).dot(n);
    double volume = 0.0;
    for (const auto& t : s.triangles)
        volume += (s.points[t[0]] - p0).dot((s.points[t[1]] - p0).cross(s.points[t[2]] - p0)) / 6.0;
    if (!(size > 0.0) || !(std::abs(thickness) > 1e-9 * size))
        throw InputError(path, "faces", "the surface encloses no volume: its vertices lie in one plane");
    if (!(std::abs(volume) > 1e-12 * size * size * size))
        throw InputError(path, "faces", fmt::format("the surface encloses no volume ({:.3g} m^3)", volume));
}

}  // namespace

MeshData read_gmsh(const std::string& path) {
    const std::string text = read_file(path);
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

MeshData read_tetgen(const std::string& node_path, const std::string& ele_path) {
    MeshData mesh;
    mesh.source = ele_path;
    Tokens tn(node_path, read_file(node_path), true);
    const long long n = tn.count("node count", 4);
    const long long dim = tn.integer("dimension");
    if (dim != 3) tn.fail(fmt::format("dimension {} (TetGen meshes are 3D)", dim), -1);
    const long long attrs = tn.integer("attribute count");
    const long long marker = tn.integer("boundary marker flag");
    if (attrs < 0 || attrs > 64 || marker < 0 || marker > 1) tn.fail("implausible attribute count or marker flag", -1);
    long long base = 0;
    for (long long i = 0; i < n; ++i) {
        const long long idx = tn.integer("node index");
        if (i == 0) base = idx;
        if (base != 0 && base != 1) tn.fail("node indices must start at 0 or 1", -1);
        check_tetgen_index(tn, idx, base + i);
        Vec3 p;
        for (int k = 0; k < 3; ++k) p[k] = tn.real("coordinate");
        for (long long a = 0; a < attrs + marker; ++a) tn.real("attribute");
        mesh.points.push_back(p);
        mesh.point_id.push_back(idx);
    }
    Tokens te(ele_path, read_file(ele_path), true);
    const long long m = te.count("element count", 5);
    const long long corners = te.integer("nodes per tetrahedron");
    if (corners != 4) te.fail(fmt::format("{}-node tetrahedra are not supported: linear (4-node) only", corners), -1);
    const long long region = te.integer("region attribute count");
    if (region < 0 || region > 64) te.fail("implausible attribute count", -1);
    for (long long e = 0; e < m; ++e) {
        const long long idx = te.integer("element index");
        if (e == 0 && idx != 0 && idx != 1) te.fail("element indices must start at 0 or 1", -1);
        mesh.cell_id.push_back(idx);
        std::array<int, 4> c;
        for (int a = 0; a < 4; ++a) {
            const long long v = te.integer("node index") - base;
            if (v < 0 || v >= n)
                te.fail(fmt::format("node {} is out of range ({} nodes, first index {})", v + base, n, base), -1);
            c[a] = static_cast<int>(v);
        }
        for (long long a = 0; a < region; ++a) te.real("attribute");
        mesh.cells.push_back(c);
    }
    return mesh;
}

ClosedSurface read_closed_surface(const std::string& path) {
    const std::string ext = fs::path(path).extension().string();
    Surface s = ext == ".stl" || ext == ".STL" ? read_stl(path) : read_obj(path);
    check_closed(path, s);
    return {s.points, s.triangles};
}

MeshData read_surface_tetrahedralize(const std::string& path, double max_volume, double min_ratio) {
    const ClosedSurface s = read_closed_surface(path);
    tetgenio in, out;
    in.firstnumber = 0;
    in.numberofpoints = static_cast<int>(s.points.size());
    in.pointlist = new REAL[3 * s.points.size()];
    for (size_t i = 0; i < s.points.size(); ++i)
        for (int k = 0; k < 3; ++k) in.pointlist[3 * i + k] = s.points[i][k];
    in.numberoffacets = static_cast<int>(s.triangles.size());
    in.facetlist = new tetgenio::facet[s.triangles.size()];
    in.facetmarkerlist = nullptr;
    for (size_t f = 0; f < s.triangles.size(); ++f) {
        tetgenio::facet& facet = in.facetlist[f];
        tetgenio::init(&facet);
        facet.numberofpolygons = 1;
        facet.polygonlist = new tetgenio::polygon[1];
        tetgenio::init(&facet.polygonlist[0]);
        facet.polygonlist[0].numberofvertices = 3;
        facet.polygonlist[0].vertexlist = new int[3];
        for (int k = 0; k < 3; ++k) facet.polygonlist[0].vertexlist[k] = s.triangles[f][k];
    }
    // TetGen 1.5 crashes (instead of throwing) when it meets intersecting facets while meshing: ask
    // its own self-intersection check (d: detect only) first.
    {
        tetgenio diagnosis;
        char detect[] = "pdQ";
        try {
            tetrahedralize(detect, &in, &diagnosis);
        } catch (int code) {
            throw InputError(path, "surface", fmt::format("TetGen could not check it (error {})", code));
        }
        if (diagnosis.numberoftrifaces > 0)
            throw InputError(path, "faces", fmt::format("the surface intersects itself ({} triangles cross or overlap "
                                                        "others)", diagnosis.numberoftrifaces));
    }
    // p: a piecewise linear complex; q: quality (radius-edge ratio bound); a: volume bound; Q: quiet.
    std::string switches = fmt::format("pq{}Q", min_ratio);
    if (max_volume > 0.0) switches += fmt::format("a{:.10g}", max_volume);
    try {
        tetrahedralize(switches.data(), &in, &out);
    } catch (int code) {
        throw InputError(path, "surface", fmt::format("TetGen could not tetrahedralize it (error {}): is it a closed, "
                                                      "non-self-intersecting surface?", code));
    }
    MeshData mesh;
    mesh.source = path;
    for (int i = 0; i < out.numberofpoints; ++i)
        mesh.points.emplace_back(out.pointlist[3 * i], out.pointlist[3 * i + 1], out.pointlist[3 * i + 2]);
    for (int e = 0; e < out.numberoftetrahedra; ++e) {
        std::array<int, 4> c;
        for (int a = 0; a < 4; ++a) c[a] = out.tetrahedronlist[e * out.numberofcorners + a] - out.firstnumber;
        Eigen::Matrix3d D;
        for (int k = 0; k < 3; ++k) D.col(k) = mesh.points[c[k + 1]] - mesh.points[c[0]];
        if (D.determinant() < 0.0) std::swap(c[2], c[3]);  // TetGen orients the other way round
        mesh.cells.push_back(c);
    }
    if (mesh.cells.empty()) throw InputError(path, "surface", "TetGen produced no tetrahedra");
    return mesh;
}

MeshData read_mesh_file(const std::string& path, double max_volume) {
    fs::path p(path);
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    MeshData mesh;
    if (ext == ".msh") {
        mesh = read_gmsh(path);
    } else if (ext == ".node" || ext == ".ele") {
        mesh = read_tetgen(p.replace_extension(".node").string(), fs::path(path).replace_extension(".ele").string());
    } else if (ext == ".obj" || ext == ".stl") {
        mesh = read_surface_tetrahedralize(path, max_volume);
    } else {
        throw InputError(path, "mesh.file", fmt::format("unknown mesh format \"{}\" (use .msh, .node/.ele, .obj, .stl)", ext));
    }
    validate_mesh(mesh);
    return mesh;
}

}  // namespace xcut
