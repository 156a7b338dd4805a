// Scene fields of the mesh (docs/scene-format.md, "mesh"): a generator's grid, or a file with its
// units, placement, repairs and regions; and the per-region materials. Loading the mesh applies them.
#include "engine/io/scene_mesh.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "engine/error.h"
#include "engine/io/mesh_io.h"

namespace xcut {

namespace fs = std::filesystem;

namespace {

MeshPlacement read_placement(const JsonFields& m) {
    MeshPlacement p;
    if (m.has("units") && m.has("scale")) m.fail("scale", "give \"units\" or \"scale\", not both");
    const std::string units = m.choice("units", "m", {"m", "cm", "mm"});
    p.scale = units_to_metres(units);
    p.scale = m.number("scale", p.scale, 1e-12, 1e12);
    p.units_given = m.has("units") || m.has("scale");
    p.translate = m.vec3("translate", Eigen::Vector3d::Zero());
    p.rotate_deg = m.vec3("rotate", Eigen::Vector3d::Zero());
    for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(p.translate[k])) m.fail(fmt::format("translate[{}]", k), "must be finite");
        if (!(std::abs(p.rotate_deg[k]) <= 360.0)) m.fail(fmt::format("rotate[{}]", k), "degrees in [-360, 360]");
    }
    p.reorient = m.boolean("reorient", false);
    p.region_array = m.string("region_array", "");
    return p;
}

}  // namespace

MeshSpec read_mesh_spec(const JsonFields& m, const fs::path& scene_dir) {
    MeshSpec spec;
    m.allow_only({"generator", "origin", "size", "cells", "element_size", "jitter", "seed", "file", "max_volume",
                  "bend_radius", "units", "scale", "translate", "rotate", "reorient", "region_array"});
    if (m.has("file") == m.has("generator")) m.fail("file", "give exactly one of \"file\" or \"generator\"");
    if (m.has("file")) {
        const fs::path p = m.string("file", "");
        spec.file = (p.is_absolute() ? p : scene_dir / p).lexically_normal().string();
        spec.max_volume = m.number("max_volume", 0.0, 0.0);
        spec.placement = read_placement(m);
        return spec;
    }
    for (const char* key : {"units", "scale", "translate", "rotate", "reorient", "region_array"})
        if (m.has(key)) m.fail(key, "applies to a mesh file, not to a generator (give the generator's size in metres)");
    spec.generator = m.choice("generator", "box", {"box", "plate"});
    GridSpec& g = spec.grid;
    g.origin = m.vec3("origin", Eigen::Vector3d::Zero());
    g.size = m.required_vec3("size");
    const int dims = spec.generator == "plate" ? 2 : 3;
    for (int k = 0; k < dims; ++k)
        if (!(g.size[k] > 0.0)) m.fail(fmt::format("size[{}]", k), "must be > 0");
    if (m.has("cells") == m.has("element_size"))
        m.fail("element_size", "give exactly one of \"element_size\" [m] or \"cells\"");
    if (m.has("cells")) {
        const std::vector<int> c = m.int_list("cells");
        if (c.size() != 3) m.fail("cells", "expected 3 integers");
        for (int k = 0; k < 3; ++k)
            if (c[k] < 1 || c[k] > 2000) m.fail(fmt::format("cells[{}]", k), "must be in [1, 2000]");
        g.cells = Eigen::Vector3i(c[0], c[1], c[2]);
    } else {
        const double h = m.required_number("element_size", 1e-9);
        g.cells = cells_for_size(g.size, h);
    }
    if (dims == 2) g.cells.z() = 1;
    const double count = double(g.cells.x()) * g.cells.y() * g.cells.z();
    const double elements = count * (dims == 3 ? 6 : 2);
    if (elements > static_cast<double>(kMaxMeshCells))
        m.fail(m.has("cells") ? "cells" : "element_size",
               fmt::format("gives {:.3g} elements, above the limit of {} (about {:.0f} GB): refused before allocating",
                           elements, kMaxMeshCells, elements * 5e3 / 1e9));
    // Doubles near the origin must resolve a cell: their spacing there, 2.2e-16 (|origin| + size),
    // is held below 1e-9 of the cell size (an origin of 1e300 would collapse every cell). Checked
    // after the element count, which refuses a tiny cell in a box of sane size first.
    for (int k = 0; k < dims; ++k) {
        const double h = g.size[k] / g.cells[k], far = std::abs(g.origin[k]) + g.size[k];
        if (!(far * std::numeric_limits<double>::epsilon() <= 1e-9 * h))
            m.fail(fmt::format("origin[{}]", k), fmt::format("{:.6g} m puts the box too far from 0 for cells of {:.3g} m: doubles "
                                                          "there are {:.3g} m apart (keep |origin| + size below {:.3g} m)",
                                                          g.origin[k], h, far * std::numeric_limits<double>::epsilon(),
                                                          1e-9 * h / std::numeric_limits<double>::epsilon()));
    }
    g.jitter = m.number("jitter", 0.0, 0.0, 0.3);
    g.seed = static_cast<uint64_t>(m.integer("seed", 1, 0));
    g.bend_radius = m.number("bend_radius", 0.0, 0.0);
    if (g.bend_radius > 0.0 && dims == 2) m.fail("bend_radius", "only for the 3D box generator");
    if (g.bend_radius > 0.0 && g.size.y() > 3.0 * g.bend_radius)
        m.fail("bend_radius", "the box would wrap more than 3 radians around the cylinder");
    return spec;
}

std::vector<RegionMaterial> read_region_materials(const JsonFields& top, const Material& base) {
    std::vector<RegionMaterial> out;
    const JsonFields regions = top.object("region_materials");
    if (!top.has("region_materials")) return out;
    for (const auto& [key, value] : top.raw("region_materials").items()) {
        const JsonFields mat = regions.object(key);
        RegionMaterial r;
        r.region = key;
        r.material = read_material(mat, base);
        out.push_back(std::move(r));
    }
    return out;
}

Material read_material(const JsonFields& mat, const Material& base) {
    mat.allow_only({"name", "young", "poisson", "density", "thickness", "toughness", "blade_friction", "element"});
    Material m;
    m.name = mat.string("name", base.name);
    m.young = mat.number("young", base.young, 1e-12);
    m.poisson = mat.number("poisson", base.poisson, -0.999, 0.4999);
    m.density = mat.number("density", base.density, 1e-12);
    m.thickness = mat.number("thickness", base.thickness, 1e-12);
    m.toughness = mat.number("toughness", base.toughness, 0.0, 1e6);
    m.blade_friction = mat.number("blade_friction", base.blade_friction, 0.0, 1e6);
    const std::string element = mat.choice("element", base.mean_dilatation ? "quadratic-p0" : base.quadratic ? "quadratic" : "linear",
                                           {"linear", "quadratic", "quadratic-p0"});
    m.quadratic = element != "linear";
    m.mean_dilatation = element == "quadratic-p0";
    return m;
}

std::vector<uint16_t> region_material_index(const std::string& scene_file, const std::string& field, const MeshData& mesh,
                                            const std::vector<RegionMaterial>& regions) {
    std::vector<uint16_t> index(mesh.cells.size(), 0);
    if (regions.empty()) return index;
    std::map<int, uint16_t> of_region;
    for (size_t k = 0; k < regions.size(); ++k) {
        const std::string& key = regions[k].region;
        const std::optional<int> tag = region_tag(mesh.region_names, key);
        if (!tag || std::count(mesh.cell_region.begin(), mesh.cell_region.end(), *tag) == 0) {
            std::map<int, long long> have;
            for (int r : mesh.cell_region) ++have[r];
            std::string list;
            for (const auto& [t, n] : have) {
                const auto name = mesh.region_names.find(t);
                list += fmt::format("{}{}{} ({} cells)", list.empty() ? "" : ", ", t,
                                    name == mesh.region_names.end() ? "" : fmt::format(" \"{}\"", name->second), n);
            }
            throw InputError(scene_file, field + "." + key,
                             fmt::format("{} has no region \"{}\"; its regions: {}", mesh.source, key,
                                         list.empty() ? "none (no physical groups, region attributes or region array)" : list));
        }
        of_region[*tag] = static_cast<uint16_t>(k + 1);
    }
    for (size_t e = 0; e < index.size(); ++e) {
        const auto it = of_region.find(mesh.cell_region[e]);
        if (it != of_region.end()) index[e] = it->second;
    }
    return index;
}

namespace {

MeshData load_body_mesh(const Scene& scene, const MeshSpec& m, const std::string& field) {
    MeshData mesh;
    if (!m.file.empty()) {
        mesh = read_mesh_file(m.file, m.max_volume, m.placement);
    } else {
        mesh = m.generator == "plate" ? generate_plate(m.grid) : generate_box(m.grid);
        try {
            validate_mesh(mesh);
        } catch (const InputError& e) {  // the scene's fields made it: name them, not the generator
            throw InputError(scene.file, field, fmt::format("the \"{}\" generator made an invalid mesh ({}: {}); check "
                                                            "{}.origin, size, cells and bend_radius",
                                                            m.generator, e.field(), e.message(), field));
        }
    }
    for (std::string& note : mesh.notes) note = mesh.source + ": " + note;
    return mesh;
}

}  // namespace

MeshData load_scene_mesh(const Scene& scene) { return load_body_mesh(scene, scene.mesh, "mesh"); }

void read_bodies(const JsonFields& top, const fs::path& scene_dir, Scene& scene) {
    if (!top.has("bodies")) {
        if (!top.has("mesh")) top.fail("mesh", "required field is missing");
        scene.mesh = read_mesh_spec(top.object("mesh"), scene_dir);
        scene.material = read_material(top.object("material"), Material{});
        scene.region_materials = read_region_materials(top, scene.material);
        return;
    }
    for (const char* key : {"mesh", "material", "region_materials"})
        if (top.has(key)) top.fail(key, "give the bodies' meshes and materials in \"bodies\", or one top-level mesh, not both");
    const std::vector<JsonFields> bodies = top.array_of_objects("bodies");
    if (bodies.empty()) top.fail("bodies", "give at least one body");
    for (size_t i = 0; i < bodies.size(); ++i) {
        const JsonFields& b = bodies[i];
        b.allow_only({"name", "mesh", "material", "region_materials"});
        if (!b.has("mesh")) b.fail("mesh", "required field is missing");
        BodySpec body;
        body.name = b.string("name", fmt::format("body{}", i));
        body.mesh = read_mesh_spec(b.object("mesh"), scene_dir);
        body.material = read_material(b.object("material"), Material{});
        body.region_materials = read_region_materials(b, body.material);
        for (size_t j = 0; j < i; ++j)
            if ((j == 0 ? scene.body_name : scene.more_bodies[j - 1].name) == body.name)
                b.fail("name", fmt::format("\"{}\" is the name of bodies[{}] too", body.name, j));
        if (i == 0) {
            scene.body_name = body.name, scene.mesh = body.mesh, scene.material = body.material;
            scene.region_materials = body.region_materials;
        } else {
            scene.more_bodies.push_back(std::move(body));
        }
    }
}

SceneBodies load_scene_bodies(const Scene& scene) {
    SceneBodies out;
    const bool several = !scene.more_bodies.empty();
    auto add = [&](const std::string& name, const MeshSpec& spec, const Material& material,
                   const std::vector<RegionMaterial>& regions, size_t k) {
        const std::string field = several ? fmt::format("bodies[{}]", k) : "";
        MeshData m = load_body_mesh(scene, spec, several ? field + ".mesh" : "mesh");
        const std::vector<uint16_t> index =
            region_material_index(scene.file, several ? field + ".region_materials" : "region_materials", m, regions);
        MeshData& all = out.mesh;
        if (k == 0) {
            all.dim = m.dim;
            all.source = m.source;
        } else if (m.dim != all.dim) {
            throw InputError(scene.file, field + ".mesh", "every body of a scene is 3D, or every body 2D");
        }
        const int base_material = static_cast<int>(out.materials.size()), first = static_cast<int>(all.points.size());
        if (base_material + regions.size() + 1 > 65535) throw InputError(scene.file, field, "too many materials");
        out.materials.push_back(material);
        for (const RegionMaterial& r : regions) out.materials.push_back(r.material);
        out.names.push_back(name);
        all.points.insert(all.points.end(), m.points.begin(), m.points.end());
        for (size_t i = 0; i < m.points.size(); ++i)
            out.file_index.push_back(static_cast<int>(out.file_points + (m.file_index.empty() ? i : m.file_index[i])));
        out.file_points += m.file_points >= 0 ? m.file_points : static_cast<long long>(m.points.size());
        for (size_t e = 0; e < m.cells.size(); ++e) {
            std::array<int, 4> c = m.cells[e];
            for (int a = 0; a < m.nodes_per_cell(); ++a) c[a] += first;
            all.cells.push_back(c);
            all.cell_region.push_back(m.cell_region.empty() ? 0 : m.cell_region[e]);
            out.material_of_cell.push_back(static_cast<uint16_t>(base_material + index[e]));
            out.body_of_cell.push_back(static_cast<int>(k));
        }
        out.region_names.push_back(m.region_names);
        all.notes.insert(all.notes.end(), m.notes.begin(), m.notes.end());
        if (all.cells.size() > static_cast<size_t>(kMaxMeshCells))
            throw InputError(scene.file, field.empty() ? "mesh" : field, fmt::format("the bodies hold {} elements together, above the "
                                                                                     "limit of {}", all.cells.size(), kMaxMeshCells));
    };
    add(scene.body_name, scene.mesh, scene.material, scene.region_materials, 0);
    for (size_t k = 0; k < scene.more_bodies.size(); ++k) {
        const BodySpec& b = scene.more_bodies[k];
        add(b.name, b.mesh, b.material, b.region_materials, k + 1);
    }
    if (std::all_of(out.mesh.cell_region.begin(), out.mesh.cell_region.end(), [](int r) { return r == 0; }))
        out.mesh.cell_region.clear();
    return out;
}

}  // namespace xcut
