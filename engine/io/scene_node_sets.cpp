#include "engine/io/scene_node_sets.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <sstream>

#include "engine/error.h"
#include "engine/io/input_file.h"
#include "engine/mesh_repair.h"

namespace xcut {

namespace fs = std::filesystem;

uint8_t read_axes(const JsonFields& f, const std::string& key) {
    const std::string s = f.string(key, "xyz");
    uint8_t mask = 0;
    for (char c : s) {
        if (c < 'x' || c > 'z') f.fail(key, fmt::format("\"{}\": use letters x, y, z", s));
        mask |= uint8_t(1u << (c - 'x'));
    }
    if (mask == 0) f.fail(key, "must name at least one axis");
    return mask;
}

std::vector<FixedSetSpec> read_fixed_sets(const JsonFields& con, const fs::path& scene_dir) {
    std::vector<FixedSetSpec> out;
    const std::vector<JsonFields> sets = con.array_of_objects("fixed_sets");
    for (size_t i = 0; i < sets.size(); ++i) {
        const JsonFields& f = sets[i];
        f.allow_only({"region", "body", "sphere", "file", "axes", "displacement"});
        FixedSetSpec spec;
        spec.field = f.field("");
        if (!spec.field.empty() && spec.field.back() == '.') spec.field.pop_back();
        const int kinds = f.has("region") + f.has("sphere") + f.has("file");
        if (kinds != 1) f.fail("region", "give exactly one of \"region\", \"sphere\" or \"file\"");
        if (f.has("body") && !f.has("region")) f.fail("body", "names the body of a \"region\"");
        if (f.has("region")) {
            const nlohmann::json& r = f.raw("region");
            if (r.is_number_integer()) spec.region = std::to_string(r.get<long long>());
            else spec.region = f.string("region", "");
            spec.body = f.string("body", "");
        } else if (f.has("sphere")) {
            const JsonFields sphere = f.object("sphere");
            sphere.allow_only({"centre", "radius"});
            spec.centre = sphere.required_vec3("centre");
            spec.radius = sphere.required_number("radius", 0.0);
        } else {
            const fs::path p = f.string("file", "");
            spec.file = (p.is_absolute() ? p : scene_dir / p).lexically_normal().string();
        }
        spec.axes = read_axes(f, "axes");
        spec.displacement = f.vec3("displacement", Eigen::Vector3d::Zero());
        out.push_back(spec);
    }
    return out;
}

namespace {

/// The nodes of the cells in `spec.region` (a name or a number) of the named body, or of every body.
std::vector<int> region_nodes(const Scene& scene, const SceneBodies& b, const FixedSetSpec& spec) {
    const MeshData& m = b.mesh;
    std::vector<uint8_t> in(m.points.size(), 0);
    bool body_found = spec.body.empty(), region_found = false;
    std::string regions;
    for (size_t k = 0; k < b.names.size(); ++k) {
        if (!spec.body.empty() && b.names[k] != spec.body) continue;
        body_found = true;
        const std::optional<int> tag = region_tag(b.region_names[k], spec.region);
        for (size_t e = 0; tag && !m.cell_region.empty() && e < m.cells.size(); ++e) {
            if (b.body_of_cell[e] != static_cast<int>(k) || m.cell_region[e] != *tag) continue;
            region_found = true;
            for (int a = 0; a < m.nodes_per_cell(); ++a) in[m.cells[e][a]] = 1;
        }
        for (const auto& [t, name] : b.region_names[k]) regions += fmt::format("{}{} \"{}\"", regions.empty() ? "" : ", ", t, name);
    }
    if (!body_found) throw InputError(scene.file, spec.field + ".body", fmt::format("no body is named \"{}\"", spec.body));
    if (!region_found)
        throw InputError(scene.file, spec.field + ".region",
                         fmt::format("no cell is in region \"{}\"{} (named regions: {})", spec.region,
                                     spec.body.empty() ? "" : " of body \"" + spec.body + "\"", regions.empty() ? "none" : regions));
    std::vector<int> nodes;
    for (size_t i = 0; i < in.size(); ++i)
        if (in[i]) nodes.push_back(static_cast<int>(i));
    return nodes;
}

std::vector<int> file_nodes(const Scene& scene, const FixedSetSpec& spec, const SceneBodies& b) {
    const long long node_count = b.file_points;
    std::istringstream text(read_input_file(spec.file, spec.field + ".file", "node index"));
    std::vector<int> nodes;
    std::string line;
    for (int n = 1; std::getline(text, line); ++n) {
        line = line.substr(0, line.find('#'));
        std::istringstream words(line);
        std::string w;
        while (words >> w) {
            char* end = nullptr;
            const long long v = std::strtoll(w.c_str(), &end, 10);
            if (end == w.c_str() || *end != '\0' || v < 0 || v >= node_count)
                throw InputError(spec.file, fmt::format("line {}", n),
                                 fmt::format("\"{}\" is not a node index of the scene (0 to {}; {})", w, node_count - 1, scene.file));
            nodes.push_back(node_of_file_index(b, spec.file, fmt::format("line {}", n), v));
        }
    }
    if (nodes.empty()) throw InputError(spec.file, spec.field + ".file", "lists no node");
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    return nodes;
}

}  // namespace

int node_of_file_index(const SceneBodies& b, const std::string& scene_file, const std::string& field, long long index) {
    if (index < 0 || index >= b.file_points)
        throw InputError(scene_file, field,
                         fmt::format("node {} does not exist (the mesh files have {} nodes, 0 to {})", index,
                                     b.file_points, b.file_points - 1));
    const auto it = std::lower_bound(b.file_index.begin(), b.file_index.end(), index);
    if (it == b.file_index.end() || *it != index)
        throw InputError(scene_file, field,
                         fmt::format("node {} of the mesh files is used by no element (it was dropped on reading)", index));
    return static_cast<int>(it - b.file_index.begin());
}

std::vector<FixedSet> resolve_fixed_sets(const Scene& scene, const SceneBodies& b) {
    std::vector<FixedSet> out;
    for (const FixedSetSpec& spec : scene.fixed_sets) {
        FixedSet set;
        set.axes = spec.axes;
        set.displacement = spec.displacement;
        if (!spec.region.empty()) {
            set.nodes = region_nodes(scene, b, spec);
        } else if (spec.radius >= 0.0) {
            for (size_t i = 0; i < b.mesh.points.size(); ++i)
                if ((b.mesh.points[i] - spec.centre).norm() <= spec.radius) set.nodes.push_back(static_cast<int>(i));
            if (set.nodes.empty())
                throw InputError(scene.file, spec.field + ".sphere", "holds no node of the mesh (at rest)");
        } else {
            set.nodes = file_nodes(scene, spec, b);
        }
        out.push_back(std::move(set));
    }
    return out;
}

}  // namespace xcut
