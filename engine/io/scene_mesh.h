#pragma once
// The mesh part of a scene: reading the "mesh" fields and "region_materials", and loading the mesh
// the scene describes. Internal to engine/io (scene.cpp); tests use it through load_scene.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "components/material.h"
#include "engine/io/json_fields.h"
#include "engine/io/scene.h"

namespace xcut {

MeshSpec read_mesh_spec(const JsonFields& m, const std::filesystem::path& scene_dir);
/// A material from its JSON fields; fields it leaves out come from `base`.
Material read_material(const JsonFields& mat, const Material& base);
/// "region_materials": { "<region name or number>": { material fields }, ... }, each over `base`.
std::vector<RegionMaterial> read_region_materials(const JsonFields& top, const Material& base);
/// Each cell's index into {the body's material, its region materials...}: 0 unless its region is
/// listed. Throws InputError naming `field` ("region_materials", "bodies[1].region_materials") when
/// a listed region is not in the mesh.
std::vector<uint16_t> region_material_index(const std::string& scene_file, const std::string& field, const MeshData& mesh,
                                            const std::vector<RegionMaterial>& regions);
/// "bodies": [...] or the top-level "mesh", "material", "region_materials" (one body).
void read_bodies(const JsonFields& top, const std::filesystem::path& scene_dir, Scene& scene);

}  // namespace xcut
