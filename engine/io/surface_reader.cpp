// Closed triangle surfaces (OBJ, ASCII and binary STL), checked closed and non-degenerate, and
// tetrahedralized with TetGen's library (engine/io/mesh_io.h).
#include <tetgen.h>

#include <Eigen/Dense>
#include <cstring>
#include <filesystem>
#include <sstream>
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
#include "engine/io/isolated_mesher.h"
#include "engine/io/mesh_io.h"
#include "engine/io/byte_cursor.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;
using mesh_io_detail::ByteCursor;

/// Sorted-pair key of an undirected edge.
uint64_t edge_key(int a, int b) {
    return (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint32_t>(std::max(a, b));
}

using Surface = ClosedSurface;

Surface read_obj(const std::string& path) {
    const std::string text = read_input_file(path, "file", "mesh");
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
    const std::string data = read_input_file(path, "file", "mesh");
    Surface s;
    std::map<std::array<double, 3>, int> ids;
    const bool ascii = data.compare(0, 5, "solid") == 0 && data.find("facet") != std::string::npos;
    if (ascii) {
        ByteCursor t(path, data);
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

ClosedSurface read_closed_surface(const std::string& path) {
    const std::string ext = fs::path(path).extension().string();
    Surface s = ext == ".stl" || ext == ".STL" ? read_stl(path) : read_obj(path);
    check_closed(path, s);
    return s;
}

void check_closed_surface(const std::string& path, const ClosedSurface& surface) { check_closed(path, surface); }

double enclosed_volume(const ClosedSurface& s) {
    double volume = 0.0;
    if (s.points.empty()) return 0.0;
    const Vec3 p0 = s.points[0];
    for (const auto& t : s.triangles)
        volume += (s.points[t[0]] - p0).dot((s.points[t[1]] - p0).cross(s.points[t[2]] - p0)) / 6.0;
    return volume;
}

MeshData read_surface_tetrahedralize(const std::string& path, double max_volume, double min_ratio, double volume_to_m3) {
    return tetrahedralize_surface(path, read_closed_surface(path), max_volume, min_ratio, volume_to_m3);
}

namespace {

/// TetGen 1.5 asserts (aborts the process) inside its intersection predicates on near-degenerate
/// input such as a coordinate of 1e-309 beside zeros, which binary files make easy. The surface is
/// therefore snapped to a grid of 2^-40 of its size (about 1e-12: far below any tissue feature), and
/// what snapping makes degenerate (a triangle without area, two vertices at one place) is refused.
ClosedSurface conditioned(const std::string& path, ClosedSurface s) {
    Vec3 lo = s.points[0], hi = s.points[0];
    for (const Vec3& p : s.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    const double q = std::ldexp((hi - lo).norm(), -40);
    if (!(q > 0.0) || !std::isfinite(q)) throw InputError(path, "faces", "the surface has no extent");
    for (Vec3& p : s.points)
        for (int k = 0; k < 3; ++k) p[k] = lo[k] + std::round((p[k] - lo[k]) / q) * q;
    std::map<std::array<double, 3>, int> at;
    std::vector<uint8_t> used(s.points.size(), 0);
    for (const auto& t : s.triangles)
        for (int v : t) used[v] = 1;
    for (size_t i = 0; i < s.points.size(); ++i) {
        if (!used[i]) continue;
        const auto [it, fresh] = at.emplace(std::array<double, 3>{s.points[i].x(), s.points[i].y(), s.points[i].z()}, static_cast<int>(i));
        if (!fresh)
            throw InputError(path, fmt::format("vertex {}", i + 1),
                             fmt::format("lies on vertex {} (closer than 1e-12 of the surface's size)", it->second + 1));
    }
    for (size_t f = 0; f < s.triangles.size(); ++f) {
        const auto& t = s.triangles[f];
        const Vec3 n = (s.points[t[1]] - s.points[t[0]]).cross(s.points[t[2]] - s.points[t[0]]);
        if (!(n.norm() > 0.0))
            throw InputError(path, fmt::format("triangle {}", f + 1), "has no area (its vertices are on one line)");
    }
    return s;
}

}  // namespace

namespace {

/// TetGen itself: its self-intersection check, then the quality mesh (run in a child process).
MeshData run_tetgen(const std::string& path, const ClosedSurface& s, double max_volume, double min_ratio) {
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
    // p: a piecewise linear complex; q: quality (radius-edge ratio bound); a: volume bound; S: most
    // added points (mesher_point_limit); Q: quiet.
    const long long limit = mesher_point_limit();
    std::string switches = fmt::format("pq{}S{}Q", min_ratio, limit);
    if (max_volume > 0.0) switches += fmt::format("a{:.10g}", max_volume);
    try {
        tetrahedralize(switches.data(), &in, &out);
    } catch (int code) {
        throw InputError(path, "surface", fmt::format("TetGen could not tetrahedralize it (error {}): is it a closed, "
                                                      "non-self-intersecting surface?", code));
    }
    if (out.numberofpoints - in.numberofpoints >= limit)
        throw InputError(path, "surface",
                         fmt::format("the quality mesh needs more than {} added points (the limit): the surface has "
                                     "features far smaller than its size (a thin gap or sliver); repair or remesh it",
                                     limit));
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

}  // namespace

namespace {
long long g_mesher_point_limit = kMaxMeshCells / 4;
}  // namespace

void set_mesher_point_limit(long long points) { g_mesher_point_limit = std::max(1LL, points); }
long long mesher_point_limit() { return g_mesher_point_limit; }

MeshData tetrahedralize_surface(const std::string& path, const ClosedSurface& input, double max_volume, double min_ratio,
                                double volume_to_m3) {
    const ClosedSurface s = conditioned(path, input);
    if (max_volume > 0.0) {
        // Every tet is at most max_volume, so the enclosed volume over it is a lower bound on the count.
        const double at_least = std::abs(enclosed_volume(s)) / max_volume;
        if (at_least > static_cast<double>(kMaxMeshCells))
            throw InputError(path, "mesh.max_volume",
                             fmt::format("{:.3g} m^3 would make at least {:.3g} tetrahedra, above the limit of {} "
                                         "(docs/scene-format.md): raise max_volume", max_volume * volume_to_m3, at_least,
                                         kMaxMeshCells));
    }
    return run_isolated_mesher(path, [&] { return run_tetgen(path, s, max_volume, min_ratio); });
}

}  // namespace xcut
