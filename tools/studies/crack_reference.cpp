#include "tools/studies/crack_reference.h"
#include "engine/error.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/os.h>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "engine/fnv_hash.h"
#include "engine/io/generators.h"
#include "engine/setup.h"

namespace xcut {
namespace {

/// Grid lines from a to b through the given interior breaks, each piece split into cells of about h.
std::vector<double> lines_through(std::vector<double> stops, double h) {
    std::vector<double> out{stops.front()};
    for (size_t k = 1; k < stops.size(); ++k) {
        const int cells = std::max(1, static_cast<int>(std::lround((stops[k] - stops[k - 1]) / h)));
        for (int i = 1; i <= cells; ++i)
            out.push_back(i == cells ? stops[k] : stops[k - 1] + (stops[k] - stops[k - 1]) * i / cells);
    }
    return out;
}

/// The parameters the reference depends on, as one line (the cache key and the file's header).
std::string key_line(const CutBlockSpec& s, int n) {
    return fmt::format("L={:.17g} B={:.17g} H={:.17g} cut_x={:.17g} depth={:.17g} pull={:.17g} E={:.17g} nu={:.17g} n={}",
                       s.size.x(), s.size.y(), s.size.z(), s.cut_x, s.depth, s.pull, s.young, s.poisson, n);
}

bool read_cache(const std::string& path, const std::string& key, size_t count, ReferenceField& out) {
    std::ifstream in(path);
    std::string line;
    if (!std::getline(in, line) || line != "# " + key) return false;
    if (!std::getline(in, line) || std::sscanf(line.c_str(), "# dofs=%d solve_s=%lf", &out.dofs, &out.solve_s) != 2)
        return false;
    std::getline(in, line);  // column names
    out.displacement.clear();
    while (std::getline(in, line)) {
        std::istringstream row(line);
        double v[6];
        char comma;
        for (int k = 0; k < 6; ++k)
            if (!(row >> v[k]) || (k < 5 && !(row >> comma))) return false;
        out.displacement.emplace_back(v[3], v[4], v[5]);
    }
    return out.displacement.size() == count;
}

}  // namespace

MeshData generate_cracked_block(const CutBlockSpec& s, int n) {
    const double h = s.size.x() / n, front = s.size.z() - s.depth;
    MeshData mesh = generate_box_on_lines({lines_through({0.0, s.cut_x, s.size.x()}, h),
                                           lines_through({0.0, s.size.y()}, h),
                                           lines_through({0.0, front, s.size.z()}, h)});
    mesh.source = "generator cracked block";
    const double eps = 1e-9 * s.size.x();
    std::vector<int> copy(mesh.points.size(), -1);
    const size_t original = mesh.points.size();
    for (size_t i = 0; i < original; ++i) {
        const Vec3 X = mesh.points[i];
        if (std::abs(X.x() - s.cut_x) < eps && X.z() > front + eps) {
            copy[i] = static_cast<int>(mesh.points.size());
            mesh.points.push_back(X);
        }
    }
    for (auto& t : mesh.cells) {
        double cx = 0.0;
        for (int a = 0; a < 4; ++a) cx += 0.25 * mesh.points[t[a]].x();
        if (cx <= s.cut_x) continue;
        for (int a = 0; a < 4; ++a)
            if (copy[t[a]] >= 0) t[a] = copy[t[a]];
    }
    validate_mesh(mesh);
    return mesh;
}

ReferenceField cut_block_reference(const CutBlockSpec& s, int n, const std::string& cache_dir) {
    namespace fs = std::filesystem;
    const std::string key = key_line(s, n);
    const std::vector<Vec3> samples = cut_block_samples(s);
    ReferenceField ref;
    ref.path = (fs::path(cache_dir) / fmt::format("cut_block_ref_{:016x}.csv", fnv1a(key))).string();
    if (read_cache(ref.path, key, samples.size(), ref)) {
        ref.from_cache = true;
        return ref;
    }
    Material m;
    m.young = s.young;
    m.poisson = s.poisson;
    m.density = s.density;
    World w;
    w.materials.list = {m};
    build_bodies(w, generate_cracked_block(s, n));
    pull_block_ends(w, s);
    const auto t0 = std::chrono::steady_clock::now();
    const StaticResult r = solve_equilibrium(w);
    ref.solve_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!r.converged)
        throw std::runtime_error(fmt::format("the conforming reference ({}) did not converge: residual {:.3g}", key, r.residual));
    ref.dofs = 3 * w.nodes.count();
    for (const Probe& p : locate_points(w, samples)) ref.displacement.push_back(probe_displacement(w, p));
    std::error_code ec;
    fs::create_directories(cache_dir, ec);
    if (ec || access(cache_dir.c_str(), W_OK) != 0)
        throw InputError(cache_dir, "--cache-dir", fmt::format("cannot write the reference cache here ({}): give a "
                                                               "writable one with --cache-dir or XDG_CACHE_HOME",
                                                               ec ? ec.message() : "permission denied"));
    const std::string tmp = fmt::format("{}.{}.tmp", ref.path, getpid());
    {
        auto out = fmt::output_file(tmp);
        out.print("# {}\n# dofs={} solve_s={:.6g}\nx,y,z,ux,uy,uz\n", key, ref.dofs, ref.solve_s);
        for (size_t k = 0; k < samples.size(); ++k)
            out.print("{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", samples[k].x(), samples[k].y(), samples[k].z(),
                      ref.displacement[k].x(), ref.displacement[k].y(), ref.displacement[k].z());
    }
    fs::rename(tmp, ref.path);  // whole or absent: an interrupted run leaves no bad cache
    return ref;
}

}  // namespace xcut
